#include "slice/cut_reject.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace slice {
namespace {

enum class Clip { empty, whole, part };

/// Clips the convex polygon `from` by the half-space n . x <= d (Sutherland-Hodgman): a corner on
/// the plane is kept. Writes `to` only when part of the polygon is left (Clip::part).
Clip clip(const std::vector<Vec3>& from, std::vector<Vec3>& to, std::vector<double>& dist,
          const Vec3& n, double d) {
  const std::size_t k = from.size();
  dist.resize(k);
  std::size_t inside = 0;
  for (std::size_t i = 0; i < k; ++i) {
    dist[i] = n.dot(from[i]) - d;
    inside += dist[i] <= 0 ? 1 : 0;
  }
  if (inside == 0) return Clip::empty;
  if (inside == k) return Clip::whole;
  to.clear();
  for (std::size_t i = 0; i < k; ++i) {
    const std::size_t j = i + 1 == k ? 0 : i + 1;
    const double da = dist[i], db = dist[j];
    if (da <= 0) to.push_back(from[i]);
    if ((da <= 0) != (db <= 0)) to.push_back(from[i] + (da / (da - db)) * (from[j] - from[i]));
  }
  return Clip::part;
}

/// A square in the plane, centred at the foot of the box's centre, holding the plane's part of
/// the box grown by `margin` (every such point is within the box's half diagonal plus margin
/// of the centre, so of its foot).
void plane_square(const Plane& plane, const Vec3& lo, const Vec3& hi, double margin,
                  std::vector<Vec3>& out) {
  const Vec3& n = plane.normal;
  const Vec3 c = 0.5 * (lo + hi);
  const Vec3 p = c - plane.distance(c) * n;
  int k = 0;  // the axis least aligned with n
  if (std::abs(n.y()) < std::abs(n[k])) k = 1;
  if (std::abs(n.z()) < std::abs(n[k])) k = 2;
  const Vec3 u = n.cross(Vec3::Unit(k)).normalized();
  const Vec3 v = n.cross(u);
  const double r = 2 * (0.5 * (hi - lo).norm() + margin);
  out.assign({p + r * (u + v), p + r * (v - u), p - r * (u + v), p + r * (u - v)});
}

}  // namespace

double reject_margin(const Tolerances& tol, double magnitude) {
  return tol.cut + 64 * std::numeric_limits<double>::epsilon() * magnitude;
}

bool plane_misses_box(const Plane& plane, const Vec3& lo, const Vec3& hi, double margin) {
  const Vec3 c = 0.5 * (lo + hi);
  const Vec3 h = 0.5 * (hi - lo);
  return std::abs(plane.distance(c)) > plane.normal.cwiseAbs().dot(h) + margin;
}

bool polygon_misses_box(std::span<const Vec3> polygon, const Vec3& lo, const Vec3& hi,
                        double margin) {
  if (polygon.empty()) return false;
  Vec3 plo = polygon.front(), phi = polygon.front();
  for (const Vec3& x : polygon) {
    plo = plo.cwiseMin(x);
    phi = phi.cwiseMax(x);
  }
  return (plo.array() > hi.array() + margin).any() || (phi.array() < lo.array() - margin).any();
}

namespace {

/// The region the faces tests clip: the polygon, or for a persistent joint (none) a square of
/// its plane holding the plane's part of the box [lo, hi] grown by `margin`.
void start_region(const Plane& plane, std::span<const Vec3> polygon, const Vec3& lo, const Vec3& hi,
                  double margin, std::vector<Vec3>& out) {
  if (polygon.empty())
    plane_square(plane, lo, hi, margin, out);
  else
    out.assign(polygon.begin(), polygon.end());
}

/// Clips s.a by every face grown by `grow` (n . x <= d + grow): false once empty.
bool clip_by(std::span<const Face> faces, double grow, ClipScratch& s) {
  for (const Face& f : faces) {
    const Clip c = clip(s.a, s.b, s.dist, f.normal, f.d + grow);
    if (c == Clip::empty) return false;
    if (c == Clip::part) std::swap(s.a, s.b);
  }
  return true;
}

}  // namespace

bool faces_miss_polygon(std::span<const Face> faces, const Plane& plane,
                        std::span<const Vec3> polygon, const Vec3& lo, const Vec3& hi,
                        double margin, ClipScratch& s) {
  start_region(plane, polygon, lo, hi, margin, s.a);
  // A face with every corner outside it (the clip's distances) settles the pair without the
  // clips by the faces before it.
  const auto separates = [&](const Face& f) {
    return std::all_of(s.a.begin(), s.a.end(),
                       [&](const Vec3& x) { return f.normal.dot(x) - (f.d + margin) > 0; });
  };
  if (std::any_of(faces.begin(), faces.end(), separates)) {
    s.clipped = false;
    return true;
  }
  s.clipped = clip_by(faces, margin, s);
  return !s.clipped;
}

bool surely_cuts(std::span<const Face> faces, const Plane& plane, std::span<const Vec3> polygon,
                 std::span<const Plane> edges, const Vec3& lo, const Vec3& hi, double depth,
                 double margin, ClipScratch& s) {
  if (!s.clipped && faces_miss_polygon(faces, plane, polygon, lo, hi, margin, s)) return false;
  s.clipped = false;
  Vec3 x = Vec3::Zero();
  for (const Vec3& p : s.a) x += p;
  x /= static_cast<double>(s.a.size());
  x -= plane.distance(x) * plane.normal;  // back onto the plane (rounding)
  // Only this test of the point proves anything (the region is but a way to find one).
  const double inset = depth + margin;
  const auto deep = [&](const auto& p) { return p.normal.dot(x) - p.d < -inset; };
  return std::all_of(faces.begin(), faces.end(), deep) &&
         std::all_of(edges.begin(), edges.end(), deep);
}

bool plane_splits_points(const Plane& plane, std::span<const Vec3> points, double margin) {
  bool below = false, above = false;
  for (const Vec3& x : points) {
    const double d = plane.distance(x);
    below = below || d < -margin;
    above = above || d > margin;
  }
  return below && above;
}

double parallel_slab_width(std::span<const Face> faces, const Plane& plane) {
  double width = std::numeric_limits<double>::infinity();
  const Vec3& n = plane.normal;
  for (const Face& f : faces) {
    if (f.normal == -n)
      width = std::min(width, plane.d + f.d);  // below: -d_f <= n . x <= d
    else if (f.normal == n)
      width = std::min(width, f.d - plane.d);  // above: d <= n . x <= d_f
  }
  return width;
}

bool surely_irredundant(std::span<const Face> faces, std::size_t f, const Tolerances& tol) {
  // Steps of the search, and the depth inside the face it cuts off that a step gives p.
  constexpr int kSteps = 4;
  const double target = 16 * tol.prune;
  const Face& face = faces[f];
  Vec3 p = face.d * face.normal;  // in the block's frame: the foot of its origin
  for (int step = 0;; ++step) {
    double reach = std::numeric_limits<double>::infinity();
    double worst = std::numeric_limits<double>::infinity();
    std::size_t cutter = f;
    for (std::size_t j = 0; j < faces.size(); ++j) {
      if (j == f) continue;
      const double slack = faces[j].d - faces[j].normal.dot(p);
      if (!(slack >= worst)) {
        worst = slack;
        cutter = j;
      }
      const double along = faces[j].normal.dot(face.normal);
      if (along > 0) reach = std::min(reach, slack / along);
    }
    if (worst >= tol.prune) return reach > 3 * tol.prune;
    if (step == kSteps || cutter == f) return false;
    // Along the cutting face's normal projected on the plane: its slack grows to `target`.
    const Vec3& m = faces[cutter].normal;
    const Vec3 u = m - m.dot(face.normal) * face.normal;
    const double u2 = u.squaredNorm();
    if (!(u2 > 1e-6)) return false;  // (nearly) parallel to the face: no way around it
    p -= ((target - worst) / u2) * u;
  }
}

Ball ball_in_half_space(const Ball& ball, const Plane& half, double shrink) {
  if (!(ball.radius > 0)) return {};
  const double depth = half.d - half.normal.dot(ball.centre);  // the centre's, inside
  if (depth >= ball.radius) return {ball.centre, ball.radius - shrink};
  // The ball of diameter r + depth touching the plane and the far side of `ball`.
  return {ball.centre - 0.5 * (ball.radius - depth) * half.normal,
          0.5 * (ball.radius + depth) - shrink};
}

CutReject reject_cut(std::span<const Face> faces, const Plane& plane, std::span<const Vec3> polygon,
                     const Vec3& lo, const Vec3& hi, std::span<const Vec3> inside, double margin,
                     ClipScratch& scratch) {
  scratch.clipped = false;
  if (plane_misses_box(plane, lo, hi, margin)) return CutReject::plane;
  if (polygon_misses_box(polygon, lo, hi, margin)) return CutReject::box;
  if (!(polygon.empty() && plane_splits_points(plane, inside, margin)) &&
      faces_miss_polygon(faces, plane, polygon, lo, hi, margin, scratch))
    return CutReject::faces;
  return CutReject::none;
}

}  // namespace slice

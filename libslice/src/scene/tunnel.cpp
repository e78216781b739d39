#include "slice/tunnel.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "slice/orientation.hpp"

namespace slice {

namespace {

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// The section vector uv in the global frame.
Vec3 in_global(const TunnelFrame& f, const Vec2& uv) { return uv.x() * f.u + uv.y() * f.v; }

// The half-space inside the section edge a -> b of a counter-clockwise polygon, as a global
// plane (the section at axis point `at`): the outward in-section normal of a -> b is (b - a)
// turned clockwise, (dy, -dx).
Plane side_plane(const TunnelFrame& f, const Vec3& at, const Vec2& a, const Vec2& b) {
  const Vec2 e = b - a;
  const Vec3 m = in_global(f, Vec2(e.y(), -e.x()).normalized());
  return {m, m.dot(at + in_global(f, a))};
}

// The planes of the two ends, outward: the start (s = 0) and the end (s = length).
std::pair<Plane, Plane> end_caps(const TunnelFrame& f, const Tunnel& t) {
  return {{-f.d, -f.d.dot(t.point)}, {f.d, f.d.dot(t.point) + t.length}};
}

}  // namespace

// A construction joint on the convex planar polygon `corners` (in order around it, either way).
Joint construction_face_joint(const std::vector<Vec3>& corners) {
  Vec3 newell = Vec3::Zero(), mean = Vec3::Zero();
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec3& a = corners[i];
    const Vec3& b = corners[(i + 1) % corners.size()];
    newell += a.cross(b);
    mean += a;
  }
  mean /= static_cast<double>(corners.size());
  const DipAndDirection dd = dip_from_normal(newell);
  const JointFrame frame = plane_frame(dd.dip_deg, dd.dip_direction_deg);
  Joint j;
  j.dip_deg = dd.dip_deg;
  j.dip_direction_deg = dd.dip_direction_deg;
  j.centre = mean;
  j.plane = {frame.n, frame.n.dot(mean)};
  j.kind = JointKind::construction;
  j.limits = false;  // the size and shape limits must not undo the outline
  for (const Vec3& x : corners) j.polygon_uv.push_back(frame.to_uv(mean, x));
  if (signed_area(j.polygon_uv) < 0) std::reverse(j.polygon_uv.begin(), j.polygon_uv.end());
  return j;
}

// True if every corner lies on or outside one plane of the domain: the face cuts nothing.
bool face_misses_domain(const std::vector<Vec3>& corners, std::span<const Plane> domain,
                        double tol) {
  return std::any_of(domain.begin(), domain.end(), [&](const Plane& p) {
    return std::all_of(corners.begin(), corners.end(),
                       [&](const Vec3& x) { return p.distance(x) >= -tol; });
  });
}

TunnelFrame tunnel_frame(const Vec3& direction) {
  TunnelFrame f;
  f.d = direction.normalized();
  const Vec3 h = Vec3::UnitZ().cross(f.d);  // horizontal, |h| = the horizontal part of d
  // A vertical axis: u is x made perpendicular to d (d may lean by up to kVerticalAxis).
  f.u = h.norm() > kVerticalAxis ? Vec3(h.normalized())
                                 : Vec3(Vec3::UnitX() - f.d.x() * f.d).normalized();
  f.v = f.d.cross(f.u);  // (u, v, d) right-handed; v.z >= 0 for a non-vertical axis
  return f;
}

std::vector<Vec2> regular_outline(double inradius, std::int64_t sides) {
  // Vertex k at angle -90 + (k + 1/2) 360 / n degrees: side 0 (from vertex n - 1 to vertex 0)
  // faces straight down, the floor. sind/cosd make a square's corners exact.
  const double n = static_cast<double>(sides);
  const double circum = inradius / std::cos(std::numbers::pi / n);
  std::vector<Vec2> p;
  for (std::int64_t k = 0; k < sides; ++k) {
    const double a = -90 + (static_cast<double>(k) + 0.5) * 360 / n;
    p.emplace_back(circum * cosd(a), circum * sind(a));
  }
  return p;
}

double signed_area(std::span<const Vec2> polygon) {
  double a = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
    a += cross2(polygon[i], polygon[(i + 1) % polygon.size()]);
  return 0.5 * a;
}

std::optional<OutlineProblem> check_outline(std::vector<Vec2>& p, double tol) {
  const std::size_t n = p.size();
  const auto name = [n](std::size_t i) { return std::to_string(i % n + 1); };
  const std::string star_fix =
      "give the section's corners in order around the axis (0, 0), every one visible from it "
      "(a convex or star-shaped outline about the axis, e.g. a horseshoe)";
  if (n < 3)
    return OutlineProblem{"has " + std::to_string(n) + " vertices; a polygon needs at least 3",
                          "give at least 3 corners [u, v]", std::nullopt};
  for (std::size_t i = 0; i < n; ++i)
    if ((p[(i + 1) % n] - p[i]).norm() <= tol)
      return OutlineProblem{"vertices " + name(i) + " and " + name(i + 1) + " are the same point",
                            "remove the repeated vertex (do not repeat the first at the end)",
                            (i + 1) % n};
  // Each edge seen from the axis: the signed distance of (0, 0) from the edge's line, positive
  // when the axis is on the left of a -> b. All of one sign: every fan triangle (0, a, b) has
  // area, the vertices go round the axis in one sense.
  int sign = 0;
  double turn = 0;  // the angle the vertices sweep about the axis: 2 pi when winding once
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 &a = p[i], &b = p[(i + 1) % n];
    const double off = cross2(a, b) / (b - a).norm();
    const int s = off > tol ? 1 : off < -tol ? -1 : 0;
    if (s == 0 || (sign != 0 && s != sign))
      return OutlineProblem{
          "is not star-shaped about the axis: the edge from vertex " + name(i) + " to " +
              name(i + 1) +
              (s == 0 ? " lies on a line through (0, 0)" : " turns the other way round the axis"),
          star_fix, i};
    sign = s;
    turn += std::atan2(cross2(a, b), a.dot(b));
  }
  if (std::abs(turn) > 3 * std::numbers::pi)
    return OutlineProblem{"winds " +
                              std::to_string(std::lround(std::abs(turn) / (2 * std::numbers::pi))) +
                              " times round the axis",
                          star_fix, std::nullopt};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 &a = p[(i + n - 1) % n], &b = p[i], &c = p[(i + 1) % n];
    if (std::abs(cross2(b - a, c - b)) / (c - a).norm() <= tol)
      return OutlineProblem{
          "vertices " + name(i + n - 1) + ", " + name(i) + ", " + name(i + 1) + " are collinear",
          "remove vertex " + name(i) + ", which lies on the edge between its neighbours", i};
  }
  if (sign < 0) std::reverse(p.begin(), p.end());
  return std::nullopt;
}

bool outline_convex(std::span<const Vec2> p) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i)
    if (cross2(p[i] - p[(i + n - 1) % n], p[(i + 1) % n] - p[i]) <= 0) return false;
  return true;
}

std::vector<Region> tunnel_regions(const Tunnel& t, double tol) {
  const TunnelFrame f = tunnel_frame(t.direction);
  const Vec3& o = t.point;
  const auto [start, end] = end_caps(f, t);
  const auto& p = t.outline;
  const std::size_t n = p.size();
  if (outline_convex(p)) {
    Region r;
    for (std::size_t i = 0; i < n; ++i) r.planes.push_back(side_plane(f, o, p[i], p[(i + 1) % n]));
    r.planes.push_back(start);
    r.planes.push_back(end);
    return {r};
  }
  return tunnel_fan(t, tol);
}

std::vector<Region> tunnel_fan(const Tunnel& t, double tol) {
  const TunnelFrame f = tunnel_frame(t.direction);
  const Vec3& o = t.point;
  const auto [start, end] = end_caps(f, t);
  const auto& p = t.outline;
  const std::size_t n = p.size();
  const Vec2 axis = Vec2::Zero();
  std::vector<Region> out;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 &a = p[i], &b = p[(i + 1) % n];
    Region r;
    r.planes.push_back(side_plane(f, o, a, b));
    // The fan planes (through the axis), moved out by tol.
    Plane fan_in = side_plane(f, o, b, axis), fan_out = side_plane(f, o, axis, a);
    fan_in.d += tol;
    fan_out.d += tol;
    r.planes.push_back(fan_in);
    r.planes.push_back(fan_out);
    r.planes.push_back(start);
    r.planes.push_back(end);
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<Joint> section_tunnel_joints(const Tunnel& t, std::span<const Plane> domain,
                                         double tol) {
  const TunnelFrame f = tunnel_frame(t.direction);
  const std::size_t n = t.outline.size();
  const Vec3 half = 0.5 * Vec3::UnitY();
  std::vector<Joint> out;
  for (std::size_t i = 0; i < n; ++i) {
    // The edge at the middle of the unit thickness, y = 0.
    const Vec3 a = f.to_global(t.point, t.outline[i], 0.5 * t.length);
    const Vec3 b = f.to_global(t.point, t.outline[(i + 1) % n], 0.5 * t.length);
    const std::vector<Vec3> corners{a - half, b - half, b + half, a + half};
    if (face_misses_domain(corners, domain, tol)) continue;
    const Vec3 e = b - a;
    Vec3 m = Vec3(e.z(), 0, -e.x()).normalized();  // upward; a vertical one towards +x
    if (m.z() < 0 || (m.z() == 0 && m.x() < 0)) m = -m;
    Joint j;
    j.dip_deg = std::atan2(std::abs(m.x()), m.z()) * 180 / std::numbers::pi;
    j.dip_direction_deg = m.x() > 0 ? 90 : m.x() < 0 ? 270 : 0;
    j.centre = 0.5 * (a + b);
    j.plane = {m, m.dot(j.centre)};
    j.kind = JointKind::construction;
    j.limits = false;  // the size and shape limits must not undo the outline
    const JointFrame frame = plane_frame(j.dip_deg, j.dip_direction_deg);
    for (const Vec3& x : corners) j.polygon_uv.push_back(frame.to_uv(j.centre, x));
    if (signed_area(j.polygon_uv) < 0) std::reverse(j.polygon_uv.begin(), j.polygon_uv.end());
    out.push_back(std::move(j));
  }
  return out;
}

std::vector<Joint> tunnel_joints(const Tunnel& t, std::span<const Plane> domain, double tol) {
  const TunnelFrame f = tunnel_frame(t.direction);
  const auto& p = t.outline;
  const std::size_t n = p.size();
  const auto at = [&](const Vec2& uv, double s) { return f.to_global(t.point, uv, s); };
  std::vector<Joint> out;
  const auto add = [&](const std::vector<Vec3>& corners) {
    if (!face_misses_domain(corners, domain, tol)) out.push_back(construction_face_joint(corners));
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 &a = p[i], &b = p[(i + 1) % n];
    add({at(a, 0), at(b, 0), at(b, t.length), at(a, t.length)});
  }
  for (const double s : {0.0, t.length}) {
    if (outline_convex(p)) {
      std::vector<Vec3> cap;
      for (const Vec2& uv : p) cap.push_back(at(uv, s));
      add(cap);
    } else {
      for (std::size_t i = 0; i < n; ++i)
        add({at(Vec2::Zero(), s), at(p[i], s), at(p[(i + 1) % n], s)});
    }
  }
  return out;
}

}  // namespace slice

#include "slice/traces.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "slice/orientation.hpp"

namespace slice {

namespace {

// The part [t0, t1] of the segment p + t (q - p), t in [0, 1], inside |u| <= hu, |v| <= hv
// (Liang and Barsky's clipping); false if none is.
bool clip_to_window(const Vec2& p, const Vec2& q, double hu, double hv, double& t0, double& t1) {
  const Vec2 d = q - p;
  t0 = 0;
  t1 = 1;
  // Each side: s * (p + t d)_k <= h, s = +-1.
  for (int k = 0; k < 2; ++k) {
    const double h = k == 0 ? hu : hv;
    for (const double sgn : {1.0, -1.0}) {
      const double dk = sgn * d(k), room = h - sgn * p(k);
      if (dk == 0) {
        if (room < 0) return false;
      } else if (dk > 0) {
        t1 = std::min(t1, room / dk);
      } else {
        t0 = std::max(t0, room / dk);
      }
    }
  }
  return t0 < t1;
}

}  // namespace

std::optional<Trace> trace_on(const Joint& j, const TraceMapping& w, double tol) {
  const JointFrame f = plane_frame(w.dip_deg, w.dip_direction_deg);
  const double hu = 0.5 * w.width, hv = 0.5 * w.height;
  Vec2 p, q;  // the joint's trace on the whole mapping plane, in (u, v)
  if (j.persistent()) {
    // n . (centre + u U + v V) = d: the line a u + b v = c, as a segment longer than the
    // window's diagonal about the foot of the perpendicular from the window's centre.
    const Vec2 ab(j.plane.normal.dot(f.u), j.plane.normal.dot(f.v));
    const double len = ab.norm();
    if (!(len > 1e-12)) return std::nullopt;  // parallel to the mapping plane
    const Vec2 foot = (-j.plane.distance(w.centre) / (len * len)) * ab;
    const Vec2 along(-ab.y() / len, ab.x() / len);
    const double reach = 2 * (hu + hv) + 1;
    p = foot - reach * along;
    q = foot + reach * along;
  } else {
    // The points where the polygon's edges cross the mapping plane (a convex polygon: at most
    // two, or a vertex on the plane), the extreme ones along the trace.
    const std::vector<Vec3> poly = joint_polygon(j);
    std::vector<double> dist;
    for (const Vec3& x : poly) dist.push_back(f.n.dot(x - w.centre));
    std::vector<Vec2> cross;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const std::size_t k = (i + 1) % poly.size();
      if (dist[i] == 0) cross.push_back(f.to_uv(w.centre, poly[i]));
      if ((dist[i] < 0 && dist[k] > 0) || (dist[i] > 0 && dist[k] < 0))
        cross.push_back(
            f.to_uv(w.centre, poly[i] + (dist[i] / (dist[i] - dist[k])) * (poly[k] - poly[i])));
    }
    if (cross.size() < 2 || cross.size() == poly.size()) return std::nullopt;  // or in-plane
    p = cross.front();
    q = p;
    for (const Vec2& x : cross)
      if ((x - p).norm() > (q - p).norm()) q = x;
  }
  double t0 = 0, t1 = 1;
  if (!clip_to_window(p, q, hu, hv, t0, t1)) return std::nullopt;
  Trace t{p + t0 * (q - p), p + t1 * (q - p), t0 > 0, t1 < 1};
  if (!(t.length() > tol)) return std::nullopt;
  return t;
}

TraceStats trace_stats(const std::vector<const Joint*>& joints, const TraceMapping& w, double tol) {
  TraceStats s;
  std::vector<double> lengths;
  double complete = 0;
  for (const Joint* j : joints) {
    const std::optional<Trace> t = trace_on(*j, w, tol);
    if (!t) continue;
    const int ends = (t->a_censored ? 1 : 0) + (t->b_censored ? 1 : 0);
    ++s.censored[static_cast<std::size_t>(ends)];
    lengths.push_back(t->length());
    if (ends == 0) complete += t->length();
  }
  s.count = static_cast<std::int64_t>(lengths.size());
  if (lengths.empty()) return s;
  double sum = 0;
  for (const double l : lengths) sum += l;
  const double n = static_cast<double>(lengths.size());
  s.mean = sum / n;
  double ss = 0;
  for (const double l : lengths) ss += (l - s.mean) * (l - s.mean);
  s.sd = lengths.size() > 1 ? std::sqrt(ss / (n - 1)) : 0;
  s.complete_mean = s.censored[0] > 0 ? complete / static_cast<double>(s.censored[0]) : 0;
  s.p21 = sum / (w.width * w.height);
  return s;
}

}  // namespace slice

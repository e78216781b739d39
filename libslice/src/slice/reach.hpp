#pragma once
// Which blocks may a joint reach? Bounding spheres only (eq. 17 and Fig. 18): conservative, the
// cut test decides. A task of the cut (cut.cpp) holds at most a few hundred blocks while it has
// joints left, so it tests a joint against all of them, in one pass over a compact array of
// their spheres, rather than through a grid (sphere_grid.hpp, for larger sets): the same blocks,
// in increasing order, without the grid's loose cells or a sort (issue 29).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/scene.hpp"

namespace slice {

/// A joint prepared for cutting: its polygon in global coordinates and its bounding sphere.
struct PreparedJoint {
  Plane plane;                // global
  std::vector<Plane> edges;   // polygon edges as in-plane half-planes (global), empty: persistent
  std::vector<Vec3> corners;  // the polygon's corners (global), counter-clockwise about n
  Vec3 centre = Vec3::Zero();
  double radius = 0;                          // polygon's bounding sphere about centre
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // polygon's bounding box
};

inline PreparedJoint prepare(const Joint& j) {
  PreparedJoint p;
  p.plane = j.plane;
  p.centre = j.centre;
  if (j.persistent()) return p;
  p.corners = joint_polygon(j);
  const std::vector<Vec3>& v = p.corners;
  for (const Vec2& uv : j.polygon_uv) p.radius = std::max(p.radius, uv.norm());
  p.lo = p.hi = v.front();
  p.edges.reserve(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) {
    const Vec3& a = v[k];
    const Vec3& b = v[(k + 1) % v.size()];
    // Counter-clockwise about n: the outward in-plane normal of edge a -> b is (b - a) x n.
    const Vec3 m = (b - a).cross(j.plane.normal).normalized();
    p.edges.push_back({m, m.dot(a)});
    p.lo = p.lo.cwiseMin(a);
    p.hi = p.hi.cwiseMax(a);
  }
  return p;
}

/// What may_reach asks of a sphere, in plain numbers.
struct ReachQuery {
  ReachQuery(const PreparedJoint& pj, double tolerance)
      : a(pj.plane.normal[0]),
        b(pj.plane.normal[1]),
        c(pj.plane.normal[2]),
        d(pj.plane.d),
        px(pj.centre[0]),
        py(pj.centre[1]),
        pz(pj.centre[2]),
        pr(pj.radius + tolerance),
        lo{pj.lo[0] - tolerance, pj.lo[1] - tolerance, pj.lo[2] - tolerance},
        hi{pj.hi[0] + tolerance, pj.hi[1] + tolerance, pj.hi[2] + tolerance},
        tol(tolerance),
        polygon(!pj.edges.empty()) {}
  double a, b, c, d;    // the plane
  double px, py, pz;    // the polygon's centre
  double pr;            // its radius + tol
  double lo[3], hi[3];  // its box grown by tol
  double tol;
  bool polygon;

  /// The plane passes within r + tol of the centre (x, y, z) and, for a polygon, the polygon's
  /// sphere and box overlap the sphere (r) and its box by tol. reach_any and reach_list do the
  /// same arithmetic, four spheres at a time.
  bool operator()(double x, double y, double z, double r) const {
    const bool plane = std::abs(a * x + b * y + c * z - d) < r + tol;
    if (!polygon) return plane;
    const double dx = x - px, dy = y - py, dz = z - pz, reach = r + pr;
    return plane & (dx * dx + dy * dy + dz * dz < reach * reach) & (x + r > lo[0]) &
           (x - r < hi[0]) & (y + r > lo[1]) & (y - r < hi[1]) & (z + r > lo[2]) & (z - r < hi[2]);
  }
};

/// n spheres, one array per coordinate: sphere i has centre (x[i], y[i], z[i]) and radius r[i].
struct SphereArrays {
  const double *x, *y, *z, *r;
  std::size_t n;
};

/// Whether q holds for one of the spheres. `vector`: four spheres at a time where the CPU has
/// AVX2 (reach_vectorised), the same answers as q one sphere at a time; false: one at a time.
bool reach_any(const ReachQuery& q, const SphereArrays& s, bool vector = true);

/// Appends to `out` every i for which q holds for sphere i, increasing (as reach_any).
void reach_list(const ReachQuery& q, const SphereArrays& s, std::vector<std::size_t>& out,
                bool vector = true);

/// Whether reach_any and reach_list test four spheres at a time on this CPU.
bool reach_vectorised();

/// Could the joint reach the sphere of centre (x, y, z) and radius r (ReachQuery)?
inline bool may_reach(const PreparedJoint& pj, double x, double y, double z, double r, double tol) {
  return ReachQuery(pj, tol)(x, y, z, r);
}

inline bool may_reach(const PreparedJoint& pj, const Eigen::Vector4d& sphere, double tol) {
  return may_reach(pj, sphere[0], sphere[1], sphere[2], sphere[3], tol);
}

/// Spheres (centre, radius) by block number, one array per coordinate.
class SphereList {
 public:
  std::size_t size() const { return r_.size(); }
  void clear() {
    x_.clear();
    y_.clear();
    z_.clear();
    r_.clear();
  }
  void push_back(const Eigen::Vector4d& s) {
    x_.push_back(s[0]);
    y_.push_back(s[1]);
    z_.push_back(s[2]);
    r_.push_back(s[3]);
  }
  void set(std::size_t i, const Eigen::Vector4d& s) {
    x_[i] = s[0];
    y_[i] = s[1];
    z_[i] = s[2];
    r_[i] = s[3];
  }

  /// Appends the numbers of the spheres the joint may reach (q: may_reach's), increasing.
  void reached(const ReachQuery& q, std::vector<std::size_t>& out) const {
    reach_list(q, arrays(), out);
  }

  /// Whether the joint may reach any of the spheres (q: may_reach's).
  bool any_reached(const ReachQuery& q) const { return reach_any(q, arrays()); }

 private:
  std::vector<double> x_, y_, z_, r_;
  SphereArrays arrays() const { return {x_.data(), y_.data(), z_.data(), r_.data(), size()}; }
};

/// Spheres and the box that holds them all (a child task's blocks in the cut's hand-out).
class SphereGroup {
 public:
  void add(const Eigen::Vector4d& s) {
    const Vec3 c = s.head<3>(), r = Vec3::Constant(s[3]);
    lo_ = lo_.cwiseMin(c - r);
    hi_ = hi_.cwiseMax(c + r);
    spheres_.push_back(s);
  }
  const Vec3& lo() const { return lo_; }
  const Vec3& hi() const { return hi_; }
  /// Whether the joint may reach one of the spheres (q: may_reach's).
  bool any_reached(const ReachQuery& q) const { return spheres_.any_reached(q); }

 private:
  Vec3 lo_ = Vec3::Constant(INFINITY), hi_ = Vec3::Constant(-INFINITY);
  SphereList spheres_;
};

/// The boxes of up to kMax sphere groups, so that a joint is tested against all of them at once
/// (four at a time where the CPU has AVX2) before any of their spheres.
class GroupBoxes {
 public:
  static constexpr std::size_t kMax = 8;
  /// Group g's box: the box of its spheres (none: lo > hi, and the group is never reached).
  void set(std::size_t g, const Vec3& lo, const Vec3& hi);

  /// Bit g set unless group g's box shows that no sphere inside it can pass may_reach (tol: its
  /// tolerance): the plane passes the box farther than it reaches, or for a polygon, its sphere
  /// or its box misses the box. Looser than may_reach by far more than the rounding (1e-9 of the
  /// coordinates), so a group whose spheres pass is never ruled out. `vector`: as reach_any.
  unsigned may_reach(const PreparedJoint& pj, double tol, bool vector = true) const;

 private:
  // By axis k and group g: the box's centre, half size and corners; the slack's extent.
  alignas(32) double c_[3][kMax] = {}, h_[3][kMax] = {}, lo_[3][kMax] = {}, hi_[3][kMax] = {};
  alignas(32) double extent_[kMax] = {};
  unsigned used_ = 0;  // groups with a box
};

}  // namespace slice

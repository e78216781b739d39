#include "slice/estimate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "slice/polytope.hpp"
#include "slice/tolerance.hpp"

namespace slice {
namespace {

// Work (plane pairs x (domain planes + groups)) above which pairs are sampled: about a second.
constexpr double kBudget = 1e8;

/// Parallel planes (the same unit normal, as a regular or kappa = 0 set gives them), with their
/// offsets sorted.
struct Group {
  Vec3 normal;
  std::vector<double> d;
};

/// The open interval of t where p + t u lies inside every domain plane (strictly, by tol).
bool clip(const std::vector<Plane>& domain, const Vec3& p, const Vec3& u, double tol, double& t0,
          double& t1) {
  t0 = -INFINITY;
  t1 = INFINITY;
  for (const Plane& f : domain) {
    const double a = f.normal.dot(u), b = f.d - tol - f.normal.dot(p);  // a t < b
    if (std::abs(a) < 1e-300) {
      if (b <= 0) return false;
      continue;
    }
    (a > 0 ? t1 : t0) = a > 0 ? std::min(t1, b / a) : std::max(t0, b / a);
  }
  return t0 < t1;
}

/// Planes of `g` with offset strictly between lo and hi.
std::int64_t count_between(const Group& g, double lo, double hi) {
  if (lo > hi) std::swap(lo, hi);
  const auto a = std::upper_bound(g.d.begin(), g.d.end(), lo);
  const auto b = std::lower_bound(g.d.begin(), g.d.end(), hi);
  return b > a ? b - a : 0;
}

}  // namespace

BlockEstimate estimate_blocks(const JointSystem& js) {
  BlockEstimate e;
  // A 2-D section as its slab: every plane is normal to it, so L counts the section's crossing
  // points and V is 0 (docs/2d.md).
  const std::vector<Plane> domain = solid_region(js.domain, js.dimension);
  const PolytopeInfo dom = analyse_polytope(domain, js.options.tolerance * js.length_scale);
  if (!dom.bounded || dom.vertices.empty()) return e;
  const double tol = js.options.tolerance * js.length_scale;

  // P, grouped by normal.
  std::map<std::array<double, 3>, std::size_t> index;
  std::vector<Group> groups;
  for (const Joint& j : js.joints) {
    if (!j.persistent()) continue;
    double lo = INFINITY, hi = -INFINITY;
    for (const Vec3& v : dom.vertices) {
      lo = std::min(lo, j.plane.normal.dot(v));
      hi = std::max(hi, j.plane.normal.dot(v));
    }
    if (!(lo + tol < j.plane.d && j.plane.d < hi - tol)) continue;
    ++e.planes;
    const std::array<double, 3> key{j.plane.normal.x(), j.plane.normal.y(), j.plane.normal.z()};
    const auto [it, fresh] = index.try_emplace(key, groups.size());
    if (fresh) groups.push_back({j.plane.normal, {}});
    groups[it->second].d.push_back(j.plane.d);
  }
  for (Group& g : groups) std::sort(g.d.begin(), g.d.end());

  // L and V: every pair of planes from two non-parallel groups a < b; its line's chord through
  // the domain crosses the planes of the groups c > b whose offsets lie between the chord's ends.
  // Each triple a < b < c is counted once.
  double pairs = 0;
  for (std::size_t a = 0; a < groups.size(); ++a)
    for (std::size_t b = a + 1; b < groups.size(); ++b)
      pairs += double(groups[a].d.size()) * double(groups[b].d.size());
  const double work = pairs * double(domain.size() + groups.size());
  const double stride = std::max(1.0, std::ceil(work / kBudget));
  e.sampled = stride > 1;
  double next = 0;  // the index (over all pairs, in order) of the next pair to look at
  double seen = 0;
  for (std::size_t a = 0; a < groups.size(); ++a) {
    for (std::size_t b = a + 1; b < groups.size(); ++b) {
      const Group& ga = groups[a];
      const Group& gb = groups[b];
      const Vec3 u = ga.normal.cross(gb.normal);
      const double n2 = u.squaredNorm();
      const double block = double(ga.d.size()) * double(gb.d.size());
      if (n2 < 1e-24) {  // parallel (opposite normals): no lines
        seen += block;
        next = std::max(next, seen);
        continue;
      }
      for (; next < seen + block; next += stride) {
        const auto k = static_cast<std::size_t>(next - seen);
        const double da = ga.d[k / gb.d.size()], db = gb.d[k % gb.d.size()];
        // The point of the line nearest the origin: both planes, and u . p = 0.
        const Vec3 p = (da * gb.normal.cross(u) + db * u.cross(ga.normal)) / n2;
        double t0 = 0, t1 = 0;
        if (!clip(domain, p, u, tol, t0, t1)) continue;
        e.lines += stride;
        const Vec3 x0 = p + t0 * u, x1 = p + t1 * u;
        for (std::size_t c = b + 1; c < groups.size(); ++c)
          e.points += stride * double(count_between(groups[c], groups[c].normal.dot(x0),
                                                    groups[c].normal.dot(x1)));
      }
      seen += block;
    }
  }
  return e;
}

}  // namespace slice

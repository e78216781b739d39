// Sub-models: the blocks of a geom.h5 within a region (slice/extract.hpp, docs/submodels.md).
#include "slice/extract.hpp"

#include <CGAL/Gmpzf.h>
#include <CGAL/Polytope_distance_d.h>
#include <CGAL/Polytope_distance_d_traits_3.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include "slice/error.hpp"
#include "slice/mesh.hpp"
#include "slice/polytope.hpp"

namespace slice {
namespace {

std::string num(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

std::string point(const Vec3& p) {
  return "(" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + ")";
}

bool finite(const Vec3& p) { return p.allFinite(); }

using Triangle = std::array<Vec3, 3>;

// The point of triangle t nearest to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Triangle& t) {
  const Vec3 &a = t[0], &b = t[1], &c = t[2];
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// A zone as distance() needs it: its boundary as triangles and a test for inside.
struct ZoneShape {
  std::vector<Triangle> triangles;
  std::vector<Vec3> corners;              // convex zone: its vertices
  std::vector<Plane> planes;              // convex zone: inside = every plane <= 0
  std::optional<MeshInside> mesh_inside;  // mesh zone
  bool inside(const Vec3& x) const {
    if (mesh_inside) return (*mesh_inside)(x);
    return std::all_of(planes.begin(), planes.end(),
                       [&](const Plane& p) { return p.distance(x) <= 0; });
  }
  double distance(const Vec3& x) const {
    if (inside(x)) return 0;
    double best = std::numeric_limits<double>::infinity();
    for (const Triangle& t : triangles)
      best = std::min(best, (closest_on_triangle(x, t) - x).norm());
    return best;
  }
};

// The faces of the convex region `planes` as fans of triangles: each plane's vertices ordered
// by angle about their mean.
std::vector<Triangle> convex_triangles(const std::vector<Plane>& planes, double tol,
                                       const std::string& which, std::vector<Vec3>& corners) {
  const PolytopeInfo info = analyse_polytope(planes, tol);
  if (!info.bounded || !info.has_interior)
    throw Error(which, "is empty or unbounded", "give --near-zone another zone");
  corners = info.vertices;
  std::vector<Triangle> out;
  for (const Plane& p : planes) {
    std::vector<Vec3> on;
    for (const Vec3& v : info.vertices)
      if (std::abs(p.distance(v)) <= 4 * tol &&
          std::none_of(on.begin(), on.end(), [&](const Vec3& w) { return (w - v).norm() <= tol; }))
        on.push_back(v);
    if (on.size() < 3) continue;  // a redundant plane touching at an edge or a vertex
    Vec3 mean = Vec3::Zero();
    for (const Vec3& v : on) mean += v;
    mean /= double(on.size());
    const Vec3 u = (on[0] - mean).normalized(), w = p.normal.cross(u);
    std::sort(on.begin(), on.end(), [&](const Vec3& x, const Vec3& y) {
      return std::atan2((x - mean).dot(w), (x - mean).dot(u)) <
             std::atan2((y - mean).dot(w), (y - mean).dot(u));
    });
    for (std::size_t i = 1; i + 1 < on.size(); ++i) out.push_back({on[0], on[i], on[i + 1]});
  }
  return out;
}

// The distance between the convex hulls of two point sets, by CGAL's Polytope_distance_d (a QP
// solved in exact arithmetic over the double inputs; the square root is the one rounding).
using CgalKernel = CGAL::Simple_cartesian<double>;
using DistanceTraits = CGAL::Polytope_distance_d_traits_3<CgalKernel, CGAL::Gmpzf, double>;

double hull_distance(std::span<const Vec3> p, std::span<const Vec3> q) {
  std::vector<CgalKernel::Point_3> cp, cq;
  for (const Vec3& x : p) cp.emplace_back(x.x(), x.y(), x.z());
  for (const Vec3& x : q) cq.emplace_back(x.x(), x.y(), x.z());
  const CGAL::Polytope_distance_d<DistanceTraits> pd(cp.begin(), cp.end(), cq.begin(), cq.end());
  const double num = CGAL::to_double(pd.squared_distance_numerator());
  const double den = CGAL::to_double(pd.squared_distance_denominator());
  return num == 0 ? 0 : std::sqrt(num / den);
}

// The convex hull of `points` cut by the half-space p.distance(x) <= 0, as points whose hull it
// is: the points inside and, for every pair on opposite sides, the point between them on the
// plane (all pairs, not only the hull's edges: the extra points lie inside the cut hull).
std::vector<Vec3> clip_hull(const std::vector<Vec3>& points, const Plane& p) {
  std::vector<Vec3> in, out;
  for (const Vec3& x : points) (p.distance(x) <= 0 ? in : out).push_back(x);
  std::vector<Vec3> kept = in;
  for (const Vec3& a : in)
    for (const Vec3& b : out) {
      const double da = p.distance(a), db = p.distance(b);
      kept.push_back(a + (b - a) * (da / (da - db)));
    }
  return kept;
}

}  // namespace

void ExtractRegion::validate(const std::string& where) const {
  const auto bad = [&](const std::string& what, const std::string& fix) {
    throw Error(where, what, fix);
  };
  if (!finite(a) || !finite(b) || !std::isfinite(radius))
    bad("a number is not finite", "give finite numbers");
  switch (shape) {
    case RegionShape::box:
      for (int k = 0; k < 3; ++k)
        if (!(a[k] < b[k]))
          bad("min " + num(a[k]) + " is not below max " + num(b[k]) + " on " +
                  std::string(1, "xyz"[k]),
              "give xmin,ymin,zmin,xmax,ymax,zmax with each min below its max");
      break;
    case RegionShape::sphere:
    case RegionShape::cylinder:
      if (!(radius > 0)) bad("the radius is " + num(radius), "give a radius above 0");
      if (shape == RegionShape::cylinder && (b - a).norm() == 0)
        bad("the axis ends " + point(a) + " and " + point(b) + " are the same point",
            "give two distinct points x0,y0,z0,x1,y1,z1 on the axis");
      break;
    case RegionShape::near_zone:
      if (!(radius > 0)) bad("the distance is " + num(radius), "give --distance above 0");
      break;
  }
}

std::string describe(const ExtractRegion& r) {
  switch (r.shape) {
    case RegionShape::box:
      return "box from " + point(r.a) + " to " + point(r.b);
    case RegionShape::sphere:
      return "sphere about " + point(r.a) + ", radius " + num(r.radius);
    case RegionShape::cylinder:
      return "cylinder from " + point(r.a) + " to " + point(r.b) + ", radius " + num(r.radius);
    case RegionShape::near_zone: {
      std::string z;
      for (const std::size_t i : r.zones) z += (z.empty() ? "" : ", ") + std::to_string(i);
      return "within " + num(r.radius) + " of " + (r.zones.empty() ? "every zone" : "zone " + z);
    }
  }
  return "";
}

struct RegionDepth::Impl {
  ExtractRegion region;
  bool section = false;  // 2-D file: a box's y bounds do not count
  std::vector<ZoneShape> zones;
};

RegionDepth::RegionDepth(const ExtractRegion& region, const JointSystem& js)
    : impl_(std::make_unique<Impl>()) {
  impl_->region = region;
  impl_->section = js.dimension == 2;
  if (region.shape != RegionShape::near_zone) return;
  const std::size_t n_regions = js.zones.size(), n = n_regions + js.zone_meshes.size();
  if (n == 0)
    throw Error("--near-zone", "the file has no zones ([[zones]] of its scene)",
                "give a --box, --sphere or --cylinder instead");
  std::vector<std::size_t> which = region.zones;
  if (which.empty())
    for (std::size_t i = 0; i < n; ++i) which.push_back(i);
  const double tol = js.options.tolerance * js.length_scale;
  for (const std::size_t i : which) {
    if (i >= n)
      throw Error("--near-zone " + std::to_string(i), "the file has no zone " + std::to_string(i),
                  "give an index from 0 to " + std::to_string(n - 1) + " (" +
                      std::to_string(n_regions) + " /zones regions, then " +
                      std::to_string(js.zone_meshes.size()) + " meshes) or all");
    ZoneShape z;
    if (i < n_regions) {
      z.planes = solid_region(js.zones[i], js.dimension);
      z.triangles = convex_triangles(z.planes, tol, "zone " + std::to_string(i), z.corners);
    } else {
      const TriangleMesh& m = js.zone_meshes[i - n_regions];
      for (const auto& t : m.triangles)
        z.triangles.push_back({m.vertices[std::size_t(t[0])], m.vertices[std::size_t(t[1])],
                               m.vertices[std::size_t(t[2])]});
      z.mesh_inside.emplace(m);
    }
    impl_->zones.push_back(std::move(z));
  }
}

RegionDepth::~RegionDepth() = default;
RegionDepth::RegionDepth(RegionDepth&&) noexcept = default;
RegionDepth& RegionDepth::operator=(RegionDepth&&) noexcept = default;

double RegionDepth::operator()(const Vec3& x) const {
  const ExtractRegion& r = impl_->region;
  switch (r.shape) {
    case RegionShape::box: {
      double d = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k)
        if (!(impl_->section && k == 1)) d = std::min({d, x[k] - r.a[k], r.b[k] - x[k]});
      return d;
    }
    case RegionShape::sphere:
      return r.radius - (x - r.a).norm();
    case RegionShape::cylinder: {
      const Vec3 axis = r.b - r.a;
      const double h = axis.norm();
      const Vec3 u = axis / h;
      const double t = (x - r.a).dot(u);
      const double radial = (x - r.a - t * u).norm();
      return std::min({r.radius - radial, t, h - t});
    }
    case RegionShape::near_zone: {
      double d = std::numeric_limits<double>::infinity();
      for (const ZoneShape& z : impl_->zones) d = std::min(d, z.distance(x));
      return r.radius - d;
    }
  }
  return 0;
}

bool RegionDepth::reaches_into(std::span<const Vec3> vertices, double tol) const {
  if (vertices.empty()) return false;
  const ExtractRegion& r = impl_->region;
  switch (r.shape) {
    case RegionShape::box: {
      // The box shrunk by tol meets the block.
      Vec3 lo = r.a + Vec3::Constant(tol), hi = r.b - Vec3::Constant(tol);
      if (impl_->section) lo.y() = -1, hi.y() = 1;  // every point of a section has y = 0
      if ((hi - lo).minCoeff() <= 0) return false;
      // The block's bounding box must overlap it (most blocks near a face end here, before the
      // exact test).
      Vec3 vmin = vertices[0], vmax = vertices[0];
      for (const Vec3& v : vertices) vmin = vmin.cwiseMin(v), vmax = vmax.cwiseMax(v);
      if ((vmin.array() >= hi.array()).any() || (vmax.array() <= lo.array()).any()) return false;
      std::vector<Vec3> corners;
      for (int i = 0; i < 8; ++i)
        corners.push_back(
            {(i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z()});
      return hull_distance(vertices, corners) == 0;
    }
    case RegionShape::sphere:
      return hull_distance(vertices, std::span<const Vec3>(&r.a, 1)) < r.radius - tol;
    case RegionShape::cylinder: {
      // The block between the two ends (each moved in by tol), then its distance from the axis.
      const Vec3 u = (r.b - r.a).normalized();
      std::vector<Vec3> cut(vertices.begin(), vertices.end());
      cut = clip_hull(cut, {-u, -u.dot(r.a) - tol});
      cut = clip_hull(cut, {u, u.dot(r.b) - tol});
      const Vec3 axis[2] = {r.a, r.b};
      return !cut.empty() && hull_distance(cut, axis) < r.radius - tol;
    }
    case RegionShape::near_zone:
      for (const ZoneShape& z : impl_->zones) {
        if (!z.mesh_inside) {
          if (hull_distance(vertices, z.corners) < r.radius - tol) return true;
          continue;
        }
        for (const Triangle& t : z.triangles)
          if (hull_distance(vertices, t) < r.radius - tol) return true;
      }
      return false;
  }
  return false;
}

void ExtractOptions::validate() const {
  static const char* const names[] = {"--box", "--sphere", "--cylinder", "--near-zone"};
  region.validate(names[int(region.shape)]);
  if (!std::isfinite(ring) || ring < 0)
    throw Error("--ring " + num(ring), "the ring's thickness must be 0 or more",
                "give --ring 0 (only the blocks on the boundary fixed) or a thickness");
}

namespace {

// What a unit's vertices say about it (see extract.hpp).
struct UnitState {
  bool any_in = false, any_out = false;
  double min_depth = std::numeric_limits<double>::infinity();
  void add(const UnitState& o) {
    any_in |= o.any_in;
    any_out |= o.any_out;
    min_depth = std::min(min_depth, o.min_depth);
  }
};

// Copies block b's rows of `g` (its faces start at face row `face0`) onto the end of `out`.
void append_geometry(Geometry& out, const Geometry& g, std::size_t b, std::size_t face0,
                     std::size_t faces) {
  const auto v0 = std::size_t(g.vertex_offset[b]), v1 = std::size_t(g.vertex_offset[b + 1]);
  out.vertices.insert(out.vertices.end(), g.vertices.begin() + std::ptrdiff_t(v0),
                      g.vertices.begin() + std::ptrdiff_t(v1));
  out.vertex_offset.push_back(std::int64_t(out.vertices.size()));
  for (std::size_t f = face0; f < face0 + faces; ++f) {
    const auto l0 = std::size_t(g.face_vertex_offset[f]);
    const auto l1 = std::size_t(g.face_vertex_offset[f + 1]);
    out.face_vertices.insert(out.face_vertices.end(), g.face_vertices.begin() + std::ptrdiff_t(l0),
                             g.face_vertices.begin() + std::ptrdiff_t(l1));
    out.face_vertex_offset.push_back(std::int64_t(out.face_vertices.size()));
    out.face_area.push_back(g.face_area[f]);
    out.face_joint_fraction.push_back(g.face_joint_fraction[f]);
  }
  out.volume.push_back(g.volume[b]);
  out.centroid.push_back(g.centroid[b]);
  out.inertia.push_back(g.inertia[b]);
}

// A sphere's depth subtracts its centre from each point, a cylinder's an end of its axis, and
// then measures across the axis: with a centre or an end far out (a cylinder with ends at 1e154,
// meant as "through everything") the distances are rounding, past the tolerance, and past 1e154
// their squares overflow to inf: the region kept nothing without a word (issue 42 item 9). A box
// subtracts coordinates one by one, and a large radius is exact enough: both left alone.
void check_region_precision(const ExtractOptions& opt, double tol) {
  const ExtractRegion& r = opt.region;
  if (r.shape != RegionShape::sphere && r.shape != RegionShape::cylinder) return;
  const bool sphere = r.shape == RegionShape::sphere;
  const Vec3 lo = sphere ? r.a : Vec3(r.a.cwiseMin(r.b)),
             hi = sphere ? r.a : Vec3(r.a.cwiseMax(r.b));
  if (const std::string why =
          precision_problem(lo, hi, tol, sphere ? "the sphere's centre" : "the cylinder's axis");
      !why.empty())
    throw Error(sphere ? "--sphere" : "--cylinder", why,
                sphere ? "give a centre within the model (a larger radius takes in more)"
                       : "give axis ends a little beyond the blocks: the cylinder then runs "
                         "through all of them");
}

}  // namespace

SubModel extract_blocks(const BlockSystem& bs, const ExtractOptions& opt,
                        const std::string& source) {
  geometry_of(bs, source);
  opt.validate();
  const double tol = bs.joints.options.tolerance * bs.joints.length_scale;
  check_region_precision(opt, tol);
  const RegionDepth depth(opt.region, bs.joints);
  const Geometry& g = *bs.geometry;
  const std::size_t n = bs.blocks.size();

  // Each block's vertices, then each cluster's (all its blocks together).
  std::vector<UnitState> block_state(n);
  std::size_t reached = 0;
  std::map<std::int64_t, UnitState> cluster_state;
  for (std::size_t b = 0; b < n; ++b) {
    UnitState& s = block_state[b];
    for (auto v = std::size_t(g.vertex_offset[b]); v < std::size_t(g.vertex_offset[b + 1]); ++v) {
      const double d = depth(g.vertices[v]);
      s.any_in |= d > tol;
      s.any_out |= d < -tol;
      s.min_depth = std::min(s.min_depth, d);
    }
    // No vertex in: the region may still reach into the block between its vertices (a
    // cylinder through a large block, a sphere bulging through a face). Depth is 1-Lipschitz,
    // so only a block whose bounding ball reaches in can be; those are decided exactly.
    if (!s.any_in && s.any_out) {
      const std::span<const Vec3> vs(g.vertices.data() + g.vertex_offset[b],
                                     std::size_t(g.vertex_offset[b + 1] - g.vertex_offset[b]));
      Vec3 centre = Vec3::Zero();
      for (const Vec3& v : vs) centre += v;
      centre /= double(vs.size());
      double radius = 0;
      for (const Vec3& v : vs) radius = std::max(radius, (v - centre).norm());
      if (depth(centre) + radius > tol && depth.reaches_into(vs, tol)) {
        s.any_in = true;
        ++reached;
      }
    }
    if (bs.blocks[b].cluster >= 0) cluster_state[bs.blocks[b].cluster].add(s);
  }

  SubModel sub;
  sub.blocks.joints = bs.joints;
  sub.blocks.pruned = bs.pruned;
  Geometry& out = sub.blocks.geometry.emplace();
  ExtractStats& st = sub.stats;
  st.source_blocks = n;
  st.reached = reached;
  std::size_t face0 = 0, live = 0;
  std::map<std::int64_t, bool> clusters_kept;
  for (std::size_t b = 0; b < n; ++b) {
    const Block& src = bs.blocks[b];
    const std::size_t faces = src.faces.size();
    const UnitState& s = src.cluster >= 0 ? cluster_state[src.cluster] : block_state[b];
    if (s.any_in) {
      Block blk = src;
      const bool removed = (blk.flags & kRemoved) != 0;
      if (removed) {
        ++st.removed;
      } else {
        ++live;
        st.volume += g.volume[b];
        st.was_fixed += is_fixed(blk) ? 1 : 0;
        if (s.any_out) {
          ++st.cut;
          blk.flags |= kFixed;
        } else if (s.min_depth <= opt.ring + tol) {
          ++st.ring;
          blk.flags |= kFixed;
        }
      }
      if (blk.cluster >= 0) clusters_kept[blk.cluster] = true;
      sub.blocks.blocks.push_back(std::move(blk));
      sub.source_block.push_back(std::int64_t(b));
      append_geometry(out, g, b, face0, faces);
    }
    face0 += faces;
  }
  st.kept = sub.blocks.blocks.size();
  st.clusters = clusters_kept.size();
  if (live == 0)
    throw Error(source,
                "the region (" + describe(opt.region) + ") keeps no block" +
                    (st.removed ? " that is not removed (" + std::to_string(st.removed) +
                                      " removed ones only)"
                                : ""),
                "check the region against the blocks (slice-info shows the domain); no block has "
                "a vertex inside it");
  return sub;
}

}  // namespace slice

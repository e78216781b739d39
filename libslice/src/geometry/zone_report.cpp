// The removal zones measured against the domain and the ground, and what each removed
// (slice/zone_report.hpp).
#include "slice/zone_report.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/mesh.hpp"
#include "slice/polytope.hpp"

namespace slice {

const char* to_string(ZoneKind k) {
  const auto i = static_cast<std::size_t>(k);
  return i < kZoneKindNames.size() ? kZoneKindNames[i].data() : "unknown";
}

const char* to_string(ZoneGround g) {
  switch (g) {
    case ZoneGround::below:
      return "below";
    case ZoneGround::partly_above:
      return "partly above";
    case ZoneGround::wholly_above:
      return "wholly above";
    case ZoneGround::not_checked:
      break;
  }
  return "not checked";
}

namespace {

// A convex polyhedron as its faces: each a convex polygon with its outward unit normal. Made
// from a box and clipped plane by plane, so a region of a thousand planes (a round tunnel of
// 1000 sides) costs what its faces hold, not analyse_polytope's O(planes^4).
struct Polyhedron {
  std::vector<std::vector<Vec3>> faces;
  std::vector<Vec3> normals;
};

Polyhedron box_polyhedron(const Vec3& lo, const Vec3& hi) {
  Polyhedron p;
  const auto corner = [&](int i) {
    return Vec3(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  };
  // Corners by bits (x, y, z); each face's loop, any orientation (volume() needs none).
  const std::array<std::array<int, 4>, 6> loops{
      {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}}};
  const std::array<Vec3, 6> normals{-Vec3::UnitX(), Vec3::UnitX(),  -Vec3::UnitY(),
                                    Vec3::UnitY(),  -Vec3::UnitZ(), Vec3::UnitZ()};
  for (std::size_t f = 0; f < 6; ++f) {
    std::vector<Vec3> loop;
    for (const int c : loops[f]) loop.push_back(corner(c));
    p.faces.push_back(std::move(loop));
    p.normals.push_back(normals[f]);
  }
  return p;
}

// p cut down to h (normal . x <= d); `eps` an absolute length: a corner within eps of the plane
// is on it. The cut's face is the corners on the plane, ordered about their mean.
void clip(Polyhedron& p, const Plane& h, double eps) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& f : p.faces)
    for (const Vec3& x : f) {
      const double s = h.distance(x);
      lo = std::min(lo, s), hi = std::max(hi, s);
    }
  if (hi <= eps) return;  // wholly inside (or empty)
  if (lo >= -eps) {       // wholly outside, or a face of it on the plane: no volume
    p = {};
    return;
  }
  Polyhedron out;
  std::vector<Vec3> cut, on;
  for (std::size_t f = 0; f < p.faces.size(); ++f) {
    clip_polygon(p.faces[f], h, cut);
    for (const Vec3& x : cut)
      if (std::abs(h.distance(x)) <= eps &&
          std::none_of(on.begin(), on.end(), [&](const Vec3& y) { return (x - y).norm() <= eps; }))
        on.push_back(x);
    if (cut.size() >= 3) out.faces.push_back(cut), out.normals.push_back(p.normals[f]);
  }
  if (on.size() >= 3) {
    Vec3 mean = Vec3::Zero();
    for (const Vec3& x : on) mean += x;
    mean /= double(on.size());
    const Vec3 u = h.normal.unitOrthogonal(), v = h.normal.cross(u);
    std::sort(on.begin(), on.end(), [&](const Vec3& a, const Vec3& b) {
      return std::atan2((a - mean).dot(v), (a - mean).dot(u)) <
             std::atan2((b - mean).dot(v), (b - mean).dot(u));
    });
    out.faces.push_back(on);
    out.normals.push_back(h.normal);
  }
  p = std::move(out);
}

// The divergence theorem over the faces, about a corner (small numbers far from the origin).
double volume(const Polyhedron& p) {
  if (p.faces.empty()) return 0;
  const Vec3 r = p.faces.front().front();
  double v = 0;
  for (std::size_t f = 0; f < p.faces.size(); ++f) {
    const auto [area, centroid] = polygon_area_centroid(p.faces[f]);
    v += area * p.normals[f].dot(centroid - r);
  }
  return std::max(0.0, v / 3);
}

struct Box {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
};
Box bounds(const Polyhedron& p) {
  Box b;
  for (const auto& f : p.faces)
    for (const Vec3& x : f) b.lo = b.lo.cwiseMin(x), b.hi = b.hi.cwiseMax(x);
  return b;
}

// A ground triangle, counter-clockwise seen from above: its vertical prism's three sides and
// the half-space above its plane (normal . x <= d, normals out of the prism's upper part).
struct GroundTriangle {
  std::array<Plane, 4> planes;
  Box box;  // its corners' bounds
};

// The ground of a surface zone: the triangles of the solid above it whose outward normal points
// down (solid_above turns the surface's triangles down; its walls are exactly vertical, its lid
// points up).
std::vector<GroundTriangle> ground_of(const TriangleMesh& solid) {
  std::vector<GroundTriangle> out;
  for (const auto& t : solid.triangles) {
    std::array<Vec3, 3> c{solid.vertices[std::size_t(t[0])], solid.vertices[std::size_t(t[1])],
                          solid.vertices[std::size_t(t[2])]};
    Vec3 n = (c[1] - c[0]).cross(c[2] - c[0]);
    if (!(n.z() < 0)) continue;
    std::swap(c[1], c[2]);  // counter-clockwise from above: n up
    n = -n;
    GroundTriangle g;
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3 e = c[(k + 1) % 3] - c[k];
      const Vec3 out_normal = Vec3(e.y(), -e.x(), 0).normalized();  // right of the edge
      g.planes[k] = {out_normal, out_normal.dot(c[k])};
      g.box.lo = g.box.lo.cwiseMin(c[k]), g.box.hi = g.box.hi.cwiseMax(c[k]);
    }
    const Vec3 up = n.normalized();
    g.planes[3] = {-up, -up.dot(c[0])};  // above the triangle's plane
    out.push_back(g);
  }
  return out;
}

// The part of p above the ground, triangle by triangle.
double volume_above(const Polyhedron& p, const std::vector<GroundTriangle>& ground, double eps) {
  const Box b = bounds(p);
  double v = 0;
  for (const GroundTriangle& g : ground) {
    if (g.box.lo.x() >= b.hi.x() || g.box.hi.x() <= b.lo.x() || g.box.lo.y() >= b.hi.y() ||
        g.box.hi.y() <= b.lo.y() || g.box.lo.z() >= b.hi.z())
      continue;  // beside p in plan, or p wholly below the triangle
    Polyhedron q = p;
    for (const Plane& h : g.planes) clip(q, h, eps);
    v += volume(q);
  }
  return v;
}

}  // namespace

std::vector<ZoneInfo> measure_zones(const JointSystem& js) {
  std::vector<ZoneInfo> info = js.zone_info;
  const std::size_t regions = js.zones.size();
  if (info.size() != regions + js.zone_meshes.size()) return {};
  const double eps = js.options.tolerance * js.length_scale;
  const std::vector<Plane> domain = solid_region(js.domain, js.dimension);
  const PolytopeInfo dom = analyse_polytope(domain, eps);
  const Vec3 margin = Vec3::Constant(0.01 * (dom.max - dom.min).norm() + eps);
  Polyhedron start = box_polyhedron(dom.min - margin, dom.max + margin);
  for (const Plane& h : domain) clip(start, h, eps);

  std::optional<std::size_t> surface;  // the first surface zone: the ground
  for (std::size_t z = regions; z < info.size() && !surface; ++z)
    if (info[z].kind == ZoneKind::surface) surface = z;
  const std::vector<GroundTriangle> ground = surface && js.dimension == 3
                                                 ? ground_of(js.zone_meshes[*surface - regions])
                                                 : std::vector<GroundTriangle>{};
  const auto state = [&](double all, double above, const Box& b) {
    const double layer = eps * (b.hi.x() - b.lo.x()) * (b.hi.y() - b.lo.y());
    return above <= layer         ? ZoneGround::below
           : all - above <= layer ? ZoneGround::wholly_above
                                  : ZoneGround::partly_above;
  };

  for (std::size_t z = 0; z < regions; ++z) {
    Polyhedron p = start;
    for (const Plane& h : solid_region(js.zones[z], js.dimension)) clip(p, h, eps);
    info[z].volume = volume(p);
    if (ground.empty()) continue;
    info[z].volume_above_ground = volume_above(p, ground, eps);
    info[z].ground = state(info[z].volume, info[z].volume_above_ground, bounds(p));
  }
  std::optional<MeshInside> air;  // the surface's solid: the air above the ground
  for (std::size_t z = regions; z < info.size(); ++z) {
    const TriangleMesh& m = js.zone_meshes[z - regions];
    if (info[z].kind == ZoneKind::surface && js.dimension == 3) {
      info[z].volume = volume_above(start, ground_of(m), eps);  // the air in the domain
      continue;
    }
    if (ground.empty()) continue;
    if (!air) air.emplace(js.zone_meshes[*surface - regions]);
    std::size_t in_domain = 0, above = 0;
    for (const Vec3& x : m.vertices) {
      if (std::any_of(domain.begin(), domain.end(),
                      [&](const Plane& h) { return h.distance(x) > eps; }))
        continue;
      ++in_domain;
      above += (*air)(x) ? 1 : 0;
    }
    if (in_domain == 0) continue;
    info[z].ground = above == 0           ? ZoneGround::below
                     : above == in_domain ? ZoneGround::wholly_above
                                          : ZoneGround::partly_above;
  }
  return info;
}

ZoneRemovals zone_removals(const BlockSystem& bs) {
  const JointSystem& js = bs.joints;
  const std::size_t regions = js.zones.size(), n = regions + js.zone_meshes.size();
  std::vector<MeshInside> meshes;
  for (const TriangleMesh& m : js.zone_meshes) meshes.emplace_back(m);
  std::optional<std::size_t> surface;
  if (js.zone_info.size() == n)
    for (std::size_t z = regions; z < n && !surface; ++z)
      if (js.zone_info[z].kind == ZoneKind::surface) surface = z;
  // As slice-cut's test (cut.cpp, in_zone): strictly inside every plane; a mesh's exact test.
  const auto holds = [&](std::size_t z, const Vec3& x) {
    if (z >= regions) return meshes[z - regions](x);
    const auto& planes = js.zones[z].planes;
    return std::all_of(planes.begin(), planes.end(),
                       [&](const Plane& p) { return p.distance(x) < 0; });
  };
  ZoneRemovals r;
  r.blocks.assign(n, 0);
  const bool volumes = bs.geometry.has_value();
  if (volumes) r.volume.assign(n, 0.0);
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    if (!(bs.blocks[b].flags & kRemoved)) continue;
    const Vec3& x = bs.blocks[b].origin;
    std::optional<std::size_t> owner;
    if (surface && holds(*surface, x)) owner = surface;
    for (std::size_t z = 0; z < n && !owner; ++z)
      if (holds(z, x)) owner = z;
    const double v = volumes ? bs.geometry->volume[b] : 0.0;
    if (owner) {
      ++r.blocks[*owner];
      if (volumes) r.volume[*owner] += v;
    } else {
      ++r.other_blocks;
      r.other_volume += v;
    }
  }
  return r;
}

}  // namespace slice

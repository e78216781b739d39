#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>
#include <vector>

#include "scene_read.hpp"
#include "slice/error.hpp"
#include "slice/mesh.hpp"
#include "slice/surface.hpp"

// The [[zones]] surface entries of a scene file (docs/topography.md): the rock above a height
// field, removed as the closed mesh of that rock (a mesh zone to every later stage), and with
// cut = true one construction joint per triangle in the domain.
namespace slice::scene_read {

namespace {

// The rock above each triangle (counter-clockwise from above) up to z = top that may reach
// into the domain: convex prisms, for meets_domain.
std::vector<Region> prisms_above(const TriangleMesh& up, double top, const PolytopeInfo& dom) {
  std::vector<Region> out;
  for (const auto& tri : up.triangles) {
    std::array<Vec3, 3> x;
    Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
    for (int k = 0; k < 3; ++k) {
      x[std::size_t(k)] = up.vertices[std::size_t(tri[std::size_t(k)])];
      lo = lo.cwiseMin(x[std::size_t(k)]), hi = hi.cwiseMax(x[std::size_t(k)]);
    }
    if (lo.x() >= dom.max.x() || hi.x() <= dom.min.x() || lo.y() >= dom.max.y() ||
        hi.y() <= dom.min.y() || lo.z() >= dom.max.z())
      continue;
    Region prism;
    for (int k = 0; k < 3; ++k) {  // the vertical sides, outward: right of each edge
      const Vec3 e = x[std::size_t((k + 1) % 3)] - x[std::size_t(k)];
      const Vec3 n = Vec3(e.y(), -e.x(), 0).normalized();
      prism.planes.push_back({n, n.dot(x[std::size_t(k)])});
    }
    const Vec3 n = (x[1] - x[0]).cross(x[2] - x[0]).normalized();  // up
    prism.planes.push_back({-n, -n.dot(x[0])});
    prism.planes.push_back({Vec3::UnitZ(), top});
    out.push_back(std::move(prism));
  }
  return out;
}

}  // namespace

void read_surface_zone(const Context& cx, const Tbl& t, const toml::node& node, bool cut,
                       ZoneEntry& z) {
  const Reader& r = cx.r;
  const std::filesystem::path file =
      zone_file(cx, t, node, "surface", "an STL, OBJ or ESRI ASCII grid (.asc)");
  const PolytopeInfo& dom = cx.domain_info.info;
  TriangleMesh up;
  try {
    const Vec2 lo = dom.min.head<2>(), hi = dom.max.head<2>();
    // Only the triangles over the domain's plan (and a margin of 5 % of its diagonal) are
    // checked and kept: a fold or an overhang farther out does not matter.
    const Vec2 margin = Vec2::Constant(0.05 * (hi - lo).norm() + cx.tol());
    const CroppedSurface part =
        crop_surface(read_surface(file, lo, hi, cx.tol()), lo - margin, hi + margin);
    up = check_height_field(part.mesh, plan_hull(dom.vertices), cx.tol(), file.string(),
                            part.numbers);
  } catch (const Error& e) {  // its own fix: one per line
    r.fail(node, t.label("surface") + ": " + e.where() + ": " + e.problem(), e.fix());
  }
  // The lid: above the surface and the domain by a tenth of their joint size.
  Vec3 lo = dom.min, hi = dom.max;
  for (const Vec3& x : up.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double top = hi.z() + 0.1 * (hi - lo).norm();
  if (!meets_domain(cx, prisms_above(up, top, dom)))
    r.fail(node,
           t.ctx +
               "'s surface lies on or above the domain everywhere, so it would remove "
               "nothing",
           "check the surface's heights against the domain (same frame and unit)");
  TriangleMesh solid = solid_above(up, top);
  try {
    check_solid_mesh(solid, file.string());
  } catch (const Error& e) {
    r.fail(node,
           t.label("surface") + ": " + e.where() +
               ": the rock above it does not close into a solid (" + e.problem() + ")",
           "join the surface's triangles edge to edge (no T-junctions, no triangles that meet "
           "at a corner only)");
  }
  if (cut) add_face_joints(cx, up, z.joints);
  z.mesh = std::move(solid);
  z.mesh_file = file;
}

}  // namespace slice::scene_read

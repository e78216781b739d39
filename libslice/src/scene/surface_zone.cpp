#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "scene_read.hpp"
#include "slice/error.hpp"
#include "slice/mesh.hpp"
#include "slice/surface.hpp"
#include "slice/tunnel.hpp"

// The [[zones]] surface entries of a scene file (docs/topography.md): the rock above a height
// field, removed as the closed mesh of that rock (a mesh zone to every later stage), and with
// cut = true one construction joint per triangle in the domain.
namespace slice::scene_read {

namespace {

// The rock above each triangle (counter-clockwise from above) up to z = lid that may reach into
// the domain (or, `below`, the rock below it down to z = lid): convex prisms, for meets_domain.
std::vector<Region> prisms(const TriangleMesh& up, double lid, bool below,
                           const PolytopeInfo& dom) {
  std::vector<Region> out;
  for (const auto& tri : up.triangles) {
    std::array<Vec3, 3> x;
    Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
    for (int k = 0; k < 3; ++k) {
      x[std::size_t(k)] = up.vertices[std::size_t(tri[std::size_t(k)])];
      lo = lo.cwiseMin(x[std::size_t(k)]), hi = hi.cwiseMax(x[std::size_t(k)]);
    }
    if (lo.x() >= dom.max.x() || hi.x() <= dom.min.x() || lo.y() >= dom.max.y() ||
        hi.y() <= dom.min.y() || (below ? hi.z() <= dom.min.z() : lo.z() >= dom.max.z()))
      continue;
    Region prism;
    for (int k = 0; k < 3; ++k) {  // the vertical sides, outward: right of each edge
      const Vec3 e = x[std::size_t((k + 1) % 3)] - x[std::size_t(k)];
      const Vec3 n = Vec3(e.y(), -e.x(), 0).normalized();
      prism.planes.push_back({n, n.dot(x[std::size_t(k)])});
    }
    const double side = below ? 1 : -1;
    const Vec3 n = side * (x[1] - x[0]).cross(x[2] - x[0]).normalized();  // outward
    prism.planes.push_back({n, n.dot(x[0])});
    prism.planes.push_back({-side * Vec3::UnitZ(), -side * lid});
    out.push_back(std::move(prism));
  }
  return out;
}

// The triangles of `mesh` that reach into the domain: with cut = true, its construction joints.
std::int64_t triangles_in_domain(const Context& cx, const TriangleMesh& mesh) {
  std::int64_t n = 0;
  std::vector<Vec3> corners(3);
  for (const auto& tri : mesh.triangles) {
    for (std::size_t k = 0; k < 3; ++k) corners[k] = mesh.vertices[std::size_t(tri[k])];
    n += face_misses_domain(corners, cx.box.planes, cx.tol()) ? 0 : 1;
  }
  return n;
}

}  // namespace

void read_surface_zone(const Context& cx, const Tbl& t, const toml::node& node, bool cut,
                       ZoneEntry& z) {
  const Reader& r = cx.r;
  const std::filesystem::path file =
      zone_file(cx, t, node, "surface", "an STL, OBJ, ESRI ASCII grid (.asc) or GeoTIFF (.tif)");
  const PolytopeInfo& dom = cx.domain_info.info;
  TriangleMesh up;
  const auto fail_on = [&](const Error& e) {  // its own fix: one per line
    r.fail(node, t.label("surface") + ": " + e.where() + ": " + e.problem(), e.fix());
  };
  CroppedSurface part;
  try {
    const Vec2 lo = dom.min.head<2>(), hi = dom.max.head<2>();
    // Only the triangles over the domain's plan (and a margin of 5 % of its diagonal) are
    // checked and kept: a fold or an overhang farther out does not matter.
    const Vec2 margin = Vec2::Constant(0.05 * (hi - lo).norm() + cx.tol());
    part = crop_surface(read_surface(file, lo, hi, cx.tol()), lo - margin, hi + margin);
  } catch (const Error& e) {
    fail_on(e);
  }
  // With cut = true each triangle in the domain is a construction joint and the face of a block
  // on either side: a fine grid over a large domain (1 m over 1 km: 2 million triangles) makes
  // millions of blocks, which slice-cut would refuse by max_blocks only after minutes and
  // gigabytes. Refused here first, in the time it takes to read the file (issue 42 item 10).
  if (cut) {
    if (const std::int64_t n = triangles_in_domain(cx, part.mesh); n + 1 > cx.max_blocks)
      r.fail(node,
             t.ctx + " with cut = true makes " + std::to_string(n) +
                 " construction joints (one per triangle of the surface inside the domain), "
                 "each a face of a block: more blocks than max_blocks = " +
                 std::to_string(cx.max_blocks),
             "resample the surface coarser (gdalwarp -tr), give cut = false (blocks then go by "
             "their centres), or raise [options] max_blocks if the machine has the memory "
             "(about 1.4 kB a block at slice-cut's peak)");
  }
  try {
    up = check_height_field(part.mesh, plan_hull(dom.vertices), cx.tol(), file.string(),
                            part.numbers);
  } catch (const Error& e) {
    fail_on(e);
  }
  // The lid: above the surface and the domain by a tenth of their joint size.
  Vec3 lo = dom.min, hi = dom.max;
  for (const Vec3& x : up.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double top = hi.z() + 0.1 * (hi - lo).norm();
  if (!meets_domain(cx, prisms(up, top, false, dom)))
    r.fail(node,
           t.ctx +
               "'s surface lies on or above the domain everywhere, so it would remove "
               "nothing",
           "check the surface's heights against the domain (same frame and unit)");
  // Nor one on or below the domain everywhere: it would remove all of it, and the exports would
  // write a model with no body (issue 42 item 8).
  const double bottom = lo.z() - 0.1 * (hi - lo).norm();
  if (!meets_domain(cx, prisms(up, bottom, true, dom)))
    r.fail(node,
           t.ctx +
               "'s surface lies on or below the domain everywhere, so it would remove all of "
               "it",
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

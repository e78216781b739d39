#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "scene_read.hpp"
#include "slice/error.hpp"
#include "slice/mesh.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"
#include "slice/tunnel.hpp"

// The [[zones]] entries of a scene file (docs/scenes.md): regions, tunnels and meshes removed
// from the rock, and the construction joints of those with cut = true.
namespace slice::scene_read {

namespace {

// A tunnel's cross-section: the regular polygon about its circle (radius, sides), or `outline`.
std::vector<Vec2> read_section(const Context& cx, const Tbl& t) {
  const Reader& r = t.r;
  const toml::node* radius = t.find("radius");
  const toml::node* outline = t.find("outline");
  if (radius && outline)
    r.fail(*outline, t.ctx + " gives both 'radius' and 'outline'",
           "keep one: radius (and sides) for a round tunnel, outline = [[u, v], ...] for any "
           "other section");
  if (!radius && !outline)
    r.fail(t.t, "missing key 'radius' (or 'outline') in " + t.ctx,
           "add radius = <the round tunnel's radius> (and sides = n, default " +
               std::to_string(kDefaultTunnelSides) +
               "), or outline = [[u, v], ...], the section in the tunnel's (u, v) frame");
  const std::string sides_fix = "give the number of sides of the polygon about the tunnel's " +
                                std::string("circle, 3 to ") + std::to_string(kMaxSides);
  if (radius) {
    const double inradius = positive(t, "radius", "give the tunnel's radius, a length > 0");
    std::int64_t sides = kDefaultTunnelSides;
    if (const toml::node* n = t.find("sides")) {
      sides = to_integer(r, *n, t.label("sides"));
      if (sides < 3 || sides > kMaxSides)
        r.fail(*n,
               t.label("sides") + " is " + std::to_string(sides) + ", outside [3, " +
                   std::to_string(kMaxSides) + "]",
               sides_fix);
    }
    return regular_outline(inradius, sides);
  }
  if (const toml::node* n = t.find("sides"))
    r.fail(*n, t.label("sides") + " applies to a round tunnel (radius), not to an outline",
           "remove 'sides': the outline's vertices are its corners");
  const auto* a = outline->as_array();
  if (!a)
    r.fail(*outline, t.label("outline") + " must be an array of [u, v], not " + type_name(*outline),
           "write outline = [[u1, v1], [u2, v2], ...]");
  if (a->size() > static_cast<std::size_t>(kMaxSides))
    r.fail(*outline,
           t.label("outline") + " has " + std::to_string(a->size()) + " vertices, more than " +
               std::to_string(kMaxSides),
           "give the section's corners, at most " + std::to_string(kMaxSides));
  std::vector<Vec2> uv;
  std::vector<const toml::node*> where;
  for (const auto& e : *a) {
    uv.push_back(to_vector<2>(
        r, e, "vertex " + std::to_string(uv.size() + 1) + " of " + t.label("outline")));
    where.push_back(&e);
  }
  if (const auto bad = check_outline(uv, cx.tol()))
    r.fail(bad->vertex ? *where[*bad->vertex] : *outline, t.label("outline") + " " + bad->what,
           bad->fix);
  return uv;
}

// A 3-D tunnel's axis: point, direction, length.
void read_axis(const Tbl& t, Tunnel& tun) {
  const Reader& r = t.r;
  tun.point = to_vector<3>(r, t.require("point", "add point = [x, y, z], where the axis starts"),
                           t.label("point"));
  const toml::node& dn =
      t.require("direction", "add direction = [dx, dy, dz], the axis direction from 'point'");
  const Vec3 d = to_vector<3>(r, dn, t.label("direction"));
  // Its squares may overflow (1e308) or underflow (1e-200) where the direction does not.
  const double len = std::isfinite(d.norm()) && d.norm() > 0 ? d.norm() : d.stableNorm();
  if (!(len > 0) || !std::isfinite(len))
    r.fail(dn, t.label("direction") + " is " + fmt(d) + ", which has no direction",
           "give the axis direction, e.g. [0, 1, 0] for a tunnel driven North");
  tun.direction = d / len;
  t.require("length", "add length = L, the tunnel's length along its axis from 'point'");
  tun.length = positive(t, "length", "give the tunnel's length along its axis, > 0");
}

// A 2-D tunnel (docs/2d.md): its section about `point` = [x, z], (u, v) = (x, z), as the prism
// of the section's unit thickness along -y (section_tunnel_joints).
void read_section_tunnel(const Tbl& t, Tunnel& tun) {
  std::string_view which;
  if (const toml::node* n =
          first_present(t, std::array<std::string_view, 2>{"direction", "length"}, &which))
    t.r.fail(*n, t.label(which) + " is for 3-D tunnels: a 2-D tunnel is its cross-section",
             "remove " + quote_key(which) + "; give point = [x, z] and radius or outline");
  tun.point = to_point(t.r, t.require("point", "add point = [x, z], the tunnel's centre"),
                       t.label("point"), 2) +
              0.5 * Vec3::UnitY();
  tun.direction = -Vec3::UnitY();
  tun.length = 1;
}

Tunnel read_tunnel(const Context& cx, const Tbl& zone, const toml::node& node) {
  const Reader& r = zone.r;
  const Tbl t{
      r,
      as_table(r, node, zone.label("tunnel"),
               cx.dimension == 2 ? "write tunnel = { point = [x, z], radius = R }"
                                 : "write tunnel = { point = [x, y, z], direction = [dx, dy, dz], "
                                   "length = L, radius = R }"),
      "'tunnel' of " + zone.ctx};
  t.check_keys(kTunnelKeys);
  Tunnel tun;
  if (cx.dimension == 2) {
    read_section_tunnel(t, tun);
  } else {
    read_axis(t, tun);
  }
  tun.outline = read_section(cx, t);
  // The sides lie about this far from the axis: their offsets must resolve the tolerance.
  double reach = 0;
  for (const Vec2& v : tun.outline) reach = std::max(reach, v.stableNorm());
  const double step = reach * std::numeric_limits<double>::epsilon();
  if (step > cx.tol())
    r.fail(t.find("radius") ? *t.find("radius") : *t.find("outline"),
           t.ctx + " reaches " + fmt(reach, 3) + " from its axis, where doubles step by " +
               fmt(step, 3) + ", coarser than the tolerance " + fmt(cx.tol(), 3) +
               " (tolerance x the domain's bounding radius)",
           "give the section in the scene's length unit; a box zone larger than the domain "
           "removes all of it");
  return tun;
}

// A cut tunnel's joints reach its ends: refused, as a domain far from the origin is, where
// doubles cannot resolve them (a tunnel 1e18 long through a 20 m cube cut nothing right).
void check_tunnel_precision(const Context& cx, const Tbl& zone, const toml::node& node,
                            const Tunnel& tun) {
  const TunnelFrame f = tunnel_frame(tun.direction);
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const double s : {0.0, tun.length})
    for (const Vec2& uv : tun.outline) {
      const Vec3 x = f.to_global(tun.point, uv, s);
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  if (const std::string why = precision_problem(lo, hi, cx.tol(), "the tunnel"); !why.empty())
    zone.r.fail(node, zone.label("tunnel") + " with cut = true: " + why,
                "shorten it to the part that crosses the domain (its joints span its whole "
                "length), or raise [scene] tolerance");
}

}  // namespace

bool meets_domain(const Context& cx, std::span<const Region> regions) {
  return std::any_of(regions.begin(), regions.end(), [&](const Region& z) {
    std::vector<Plane> both = solid_region(z, cx.dimension);
    both.insert(both.end(), cx.box.planes.begin(), cx.box.planes.end());
    return analyse_polytope(both, cx.tol()).has_interior;
  });
}

std::filesystem::path zone_file(const Context& cx, const Tbl& t, const toml::node& node,
                                std::string_view key, const std::string& kinds) {
  const std::filesystem::path given = to_text(cx.r, node, t.label(key));
  const std::filesystem::path file = given.is_absolute() ? given : cx.dir / given;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    cx.r.fail(node, t.label(key) + " names " + file.string() + ", which is not a file",
              "give the path of " + kinds + " file, relative to the scene file's directory");
  return file;
}

void add_face_joints(const Context& cx, const TriangleMesh& mesh, std::vector<Joint>& joints) {
  for (const auto& tri : mesh.triangles) {
    const std::vector<Vec3> corners{mesh.vertices[std::size_t(tri[0])],
                                    mesh.vertices[std::size_t(tri[1])],
                                    mesh.vertices[std::size_t(tri[2])]};
    if (!face_misses_domain(corners, cx.box.planes, cx.tol()))
      joints.push_back(construction_face_joint(corners));
  }
}

namespace {

// A [[zones]] mesh: a closed triangle mesh from an OBJ or STL file (relative paths from the
// scene's directory), checked; with `cut`, one construction joint per triangle in the domain.
void read_mesh_zone(const Context& cx, const Tbl& t, const toml::node& node, bool cut,
                    ZoneEntry& z) {
  const Reader& r = cx.r;
  const std::filesystem::path file = zone_file(cx, t, node, "mesh", "an OBJ or STL");
  TriangleMesh mesh;
  try {
    mesh = read_mesh(file);
    check_solid_mesh(mesh, file.string());
  } catch (const Error& e) {  // its own fix: one per line
    r.fail(node, t.label("mesh") + ": " + e.where() + ": " + e.problem(), e.fix());
  }
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const Vec3& x : mesh.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const Region box{{{Vec3::UnitX(), hi.x()},
                    {-Vec3::UnitX(), -lo.x()},
                    {Vec3::UnitY(), hi.y()},
                    {-Vec3::UnitY(), -lo.y()},
                    {Vec3::UnitZ(), hi.z()},
                    {-Vec3::UnitZ(), -lo.z()}}};
  if (!meets_domain(cx, std::span<const Region>(&box, 1)))
    r.fail(node, t.ctx + "'s mesh has no volume inside the domain, so it would remove nothing",
           "check the mesh's coordinates against the domain (same frame and unit)");
  if (cut) add_face_joints(cx, mesh, z.joints);
  z.mesh = std::move(mesh);
  z.mesh_file = file;
}

}  // namespace

// A [[zones]] entry: box, planes or tunnel. `default_stage` is the stage of a cut tunnel's
// joints without `stage`; `entry` orders entries on one line (EntryPlace).
ZoneEntry read_zone(const Context& cx, const toml::table& tt, std::size_t index,
                    std::int64_t default_stage, std::int64_t entry) {
  const Reader& r = cx.r;
  const Tbl t{r, tt, "[[zones]] #" + std::to_string(index + 1)};
  t.check_keys(kZoneKeys);
  ZoneEntry z;
  const toml::node* tunnel = t.find("tunnel");
  const toml::node* mesh = t.find("mesh");
  const toml::node* surface = t.find("surface");
  const toml::node* stage = t.find("stage");
  std::string_view which;
  bool in_domain = false;
  if (!tunnel && !mesh && !surface) {
    if (const toml::node* n =
            first_present(t, std::array<std::string_view, 2>{"cut", "stage"}, &which))
      r.fail(
          *n, t.label(which) + " applies to tunnel, mesh and surface zones only",
          "remove " + quote_key(which) + ", or give the zone as tunnel = { ... }, mesh or surface");
    if (!t.find("box") && !t.find("planes"))
      r.fail(tt, t.ctx + " has none of 'box', 'planes', 'tunnel', 'mesh' and 'surface'",
             "add box = { min = [x, y, z], max = [x, y, z] }, planes = [ { normal = [nx, ny, "
             "nz], d = d }, ... ], tunnel = { point = [x, y, z], direction = [dx, dy, dz], "
             "length = L, radius = R }, mesh = \"cavern.obj\" or surface = \"topo.asc\"");
    z.kind = t.find("box") ? ZoneKind::box : ZoneKind::planes;
    z.regions.push_back(region_of(t, cx.dimension));
    in_domain = meets_domain(cx, z.regions);
  } else {
    const std::string_view kind = tunnel ? "tunnel" : mesh ? "mesh" : "surface";
    if (cx.dimension == 2 && !tunnel)
      r.fail(mesh ? *mesh : *surface, t.ctx + ": a " + std::string(kind) + " zone is 3-D",
             "in a 2-D scene give the zone as box = { min = [x, z], max = [x, z] }, planes or "
             "tunnel = { point = [x, z], radius = R }");
    if (const toml::node* n = first_present(t, kRegionKeys, &which))
      r.fail(*n, t.ctx + " gives both " + quote_key(kind) + " and " + quote_key(which),
             "keep one of them");
    if (tunnel && mesh)
      r.fail(*mesh, t.ctx + " gives both 'tunnel' and 'mesh'", "keep one of them");
    if (surface && (tunnel || mesh))
      r.fail(*surface,
             t.ctx + " gives both " + quote_key(tunnel ? "tunnel" : "mesh") + " and 'surface'",
             "keep one of them");
    bool cut = false;
    if (const toml::node* n = t.find("cut")) {
      const auto* b = n->as_boolean();
      if (!b)
        r.fail(*n, t.label("cut") + " must be true or false, not " + type_name(*n),
               "write cut = true to cut the zone's surface into the rock before removal");
      cut = b->get();
    }
    z.kind = tunnel ? ZoneKind::tunnel : mesh ? ZoneKind::mesh : ZoneKind::surface;
    z.cut = cut;
    if (stage && !cut)
      r.fail(*stage,
             t.label("stage") + " applies with cut = true: without it the zone adds no joints",
             "add cut = true, or remove 'stage'");
    if (mesh || surface) {
      if (mesh)
        read_mesh_zone(cx, t, *mesh, cut, z);
      else
        read_surface_zone(cx, t, *surface, cut, z);
      z.place = read_place(r, tt, t.ctx, entry);
      if (!stage) z.place.stage = default_stage;
      return z;
    }
    const Tunnel tun = read_tunnel(cx, t, *tunnel);
    if (cut) check_tunnel_precision(cx, t, *tunnel, tun);
    z.regions = tunnel_regions(tun, cx.tol());
    if (cx.dimension == 2)  // no faces normal to y in a section: the ends are the slab's
      for (Region& reg : z.regions)
        std::erase_if(reg.planes, [](const Plane& p) { return p.normal.y() != 0; });
    if (cut)
      z.joints = cx.dimension == 2 ? section_tunnel_joints(tun, cx.box.planes, cx.tol())
                                   : tunnel_joints(tun, cx.box.planes, cx.tol());
    // The fan's prisms have a few planes each; a convex region of up to 1000 sides is too many
    // for analyse_polytope (O(planes^4)).
    in_domain = meets_domain(cx, tunnel_fan(tun, 0));
  }
  // A zone may be unbounded (e.g. "everything above z = 50"): only its part inside the domain
  // matters, and that must have volume, else it removes nothing and is surely a slip.
  if (!in_domain)
    r.fail(tt, t.ctx + " has no volume inside the domain, so it would remove nothing",
           "check its coordinates against the domain (and that plane normals point out of "
           "the zone)");
  z.place = read_place(r, tt, t.ctx, entry);
  if (!stage) z.place.stage = default_stage;
  return z;
}

}  // namespace slice::scene_read

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "file_common.hpp"
#include "slice/mesh.hpp"
#include "slice/polytope.hpp"

// The groups of joints.h5 that blocks.h5 holds too: /domain, /joints, /sets, /zones, /options
// and /rock; the writer and reader of joints.h5.
namespace slice::h5file {

namespace {

// "000", "001", ...: zero-padded so the groups list in set order.
std::string set_group_name(std::size_t i) {
  const std::string s = std::to_string(i);
  return s.size() < 3 ? std::string(3 - s.size(), '0') + s : s;
}

void check_planes(const Checker& c, const std::string& group, const std::vector<Plane>& planes,
                  std::size_t first_row) {
  for (std::size_t i = 0; i < planes.size(); ++i) {
    c.unit(planes[i].normal, at(group + "/normal", first_row + i));
    c.finite(planes[i].d, at(group + "/d", first_row + i));
  }
}

// /zones/kind, entry, line, cut, above_ground, volume, volume_above_ground: one row per zone
// (regions, then meshes), or none at all (files from before them).
void check_zone_info(const Checker& c, const JointSystem& js) {
  const std::size_t n = js.zones.size() + js.zone_meshes.size();
  if (js.zone_info.empty()) return;
  if (js.zone_info.size() != n)
    c.fail("/zones/kind has " + str(js.zone_info.size()) + " rows; expected one per zone, " +
           str(n) + " (" + str(js.zones.size()) + " regions, then " + str(js.zone_meshes.size()) +
           " meshes)");
  for (std::size_t z = 0; z < n; ++z) {
    const ZoneInfo& i = js.zone_info[z];
    if (static_cast<std::size_t>(i.kind) >= kZoneKindNames.size())
      c.fail(at("/zones/kind", z) + " is " + str(std::int64_t(i.kind)) +
             "; expected 0 box, 1 planes, 2 tunnel, 3 mesh or 4 surface");
    if ((i.kind == ZoneKind::mesh || i.kind == ZoneKind::surface) != (z >= js.zones.size()))
      c.fail(at("/zones/kind", z) + " is " + to_string(i.kind) + " but zone " + str(z) + " is " +
             (z >= js.zones.size() ? "a mesh" : "a region of half-spaces"));
    if (i.entry < -1) c.fail(at("/zones/entry", z) + " is " + str(i.entry) + "; expected >= -1");
    if (i.line < 0) c.fail(at("/zones/line", z) + " is " + str(i.line) + "; expected >= 0");
    const auto g = static_cast<std::int64_t>(i.ground);
    if (g < -1 || g > 2)
      c.fail(at("/zones/above_ground", z) + " is " + str(g) + "; expected -1, 0, 1 or 2");
    for (const auto& [v, name] : {std::pair{i.volume, "/zones/volume"},
                                  std::pair{i.volume_above_ground, "/zones/volume_above_ground"}})
      if (!std::isfinite(v) || (v < 0 && v != -1))
        c.fail(at(name, z) + " is " + num(v) + "; expected a volume >= 0, or -1 (not measured)");
  }
}

}  // namespace

void check_joints(const Checker& c, const JointSystem& js) {
  if (!std::isfinite(js.length_scale) || js.length_scale <= 0)
    c.fail("/domain attribute length_scale is " + num(js.length_scale) +
           "; expected a positive length");
  check_planes(c, "/domain", js.domain.planes, 0);
  // A section in (x, z) (docs/2d.md): every normal and point has y = 0.
  const auto in_section = [&](const Vec3& v, const char* dataset, std::size_t row) {
    if (js.dimension == 2 && v.y() != 0)
      c.fail(at(dataset, row) + " has y = " + num(v.y()) +
             "; a 2-D file (root attribute dimension 2) has y = 0 everywhere");
  };
  for (std::size_t i = 0; i < js.domain.planes.size(); ++i)
    in_section(js.domain.planes[i].normal, "/domain/normal", i);

  const auto sets = static_cast<std::int64_t>(js.sets.size());
  std::size_t uv_row = 0;
  for (std::size_t i = 0; i < js.joints.size(); ++i) {
    const Joint& j = js.joints[i];
    c.unit(j.plane.normal, At{"/joints/normal", i});
    in_section(j.plane.normal, "/joints/normal", i);
    in_section(j.centre, "/joints/centre", i);
    c.finite(j.plane.d, At{"/joints/d", i});
    c.finite(j.centre, At{"/joints/centre", i});
    c.finite(j.dip_deg, At{"/joints/dip", i});
    c.finite(j.dip_direction_deg, At{"/joints/dip_direction", i});
    c.kind(j.kind, At{"/joints/kind", i});
    if (j.set < -1 || j.set >= sets)
      c.fail(at("/joints/set", i) + " is " + str(std::int64_t{j.set}) +
             "; expected -1 (deterministic) or a set index below " + str(sets) +
             " (the groups of /sets)");
    c.finite(j.friction_angle_deg, At{"/joints/friction_angle", i});
    c.finite(j.cohesion, At{"/joints/cohesion", i});
    c.non_negative(j.tension, At{"/joints/tension", i});
    c.side(j.boundary_side, At{"/joints/boundary_side", i});
    if (j.kind == JointKind::boundary && j.boundary_side == 0)
      c.fail(at("/joints/boundary_side", i) + " is 0 for a boundary joint; expected -1 (keep " +
             "below) or 1 (keep above)");
    if (j.polygon_uv.size() == 1 || j.polygon_uv.size() == 2)
      c.fail("/joints/polygon_offset gives joint " + str(i) + " a polygon of " +
             str(j.polygon_uv.size()) + " vertices; expected none (persistent) or at least 3");
    for (const Vec2& uv : j.polygon_uv) c.finite(uv, At{"/joints/polygon_uv", uv_row++});
  }

  for (std::size_t i = 0; i < js.sets.size(); ++i) {
    const JointSetSpec& s = js.sets[i];
    const std::string g = "/sets/" + set_group_name(i) + " attribute ";
    c.finite(s.dip_deg, g + "dip");
    c.finite(s.dip_direction_deg, g + "dip_direction");
    c.finite(s.spacing, g + "spacing");
    c.finite(s.offset, g + "offset");
    c.finite(s.friction_angle_deg, g + "friction_angle");
    c.finite(s.cohesion, g + "cohesion");
    c.non_negative(s.tension, g + "tension");
    c.kind(s.kind, g + "kind");
    c.side(s.boundary_side, g + "boundary_side");
    if (s.kind == JointKind::boundary && s.boundary_side == 0)
      c.fail(g + "boundary_side is 0 for a boundary set; expected -1 (keep below) or 1 (above)");
    if (s.joint_count < 0)
      c.fail(g + "joint_count is " + str(s.joint_count) + "; it cannot be negative");
    c.non_negative(s.fisher_kappa, g + "fisher_kappa");
    c.non_negative(s.density, g + "density");
    if (s.count < 0) c.fail(g + "count is " + str(s.count) + "; it cannot be negative");
    c.non_negative(s.p32, g + "p32");
    c.non_negative(s.p10, g + "p10");
    c.finite(s.scanline_from, g + "scanline_from");
    c.finite(s.scanline_to, g + "scanline_to");
    for (const double v : {s.size.value, s.size.mean, s.size.sd, s.size.min, s.size.max})
      c.non_negative(v, g + "size parameters");
    c.finite(s.size.exponent, g + "size_exponent");
    c.finite(s.aspect, g + "aspect");
    if (s.sides < 0) c.fail(g + "sides is " + str(s.sides) + "; it cannot be negative");
    c.finite(s.rotation_deg, g + "rotation");
    c.non_negative(s.enlargement, g + "enlargement");
    if (s.candidates < 0)
      c.fail(g + "candidates is " + str(s.candidates) + "; it cannot be negative");
    c.non_negative(s.achieved_p32, g + "achieved_p32");
    c.non_negative(s.achieved_p10, g + "achieved_p10");
    if (s.mapping.given) {
      c.finite(s.mapping.centre, g + "mapping_point");
      for (const double v :
           {s.mapping.width, s.mapping.height, s.mapping.field_mean, s.mapping.field_sd,
            s.traces.mean, s.traces.sd, s.traces.complete_mean, s.traces.p21})
        c.non_negative(v, g + "mapping and trace attributes");
    }
  }
  for (const double v : {js.rock.cohesion, js.rock.tension}) c.non_negative(v, "/rock attributes");
  c.finite(js.rock.friction_angle_deg, "/rock attribute friction_angle");

  std::size_t zone_row = 0;
  for (const Region& z : js.zones) {
    check_planes(c, "/zones", z.planes, zone_row);
    zone_row += z.planes.size();
  }
  for (std::size_t k = 0; k < js.zone_meshes.size(); ++k) {
    const TriangleMesh& m = js.zone_meshes[k];
    const std::string which = "/zones mesh " + str(k);
    for (const Vec3& x : m.vertices)
      if (!x.allFinite()) c.fail(which + " has a vertex that is not finite");
    for (const auto& t : m.triangles)
      for (const std::int64_t v : t)
        if (v < 0 || v >= std::int64_t(m.vertices.size()))
          c.fail(which + " has a triangle corner " + str(v) + "; expected a vertex index below " +
                 str(m.vertices.size()));
    try {
      check_solid_mesh(m, which);
    } catch (const Error& e) {
      c.fail(e.where() + " does not bound a solid: " + e.problem());  // the file's fix only
    }
    // As the scene parser refuses it: a mesh whose bounding box has no volume in the domain.
    Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
    for (const Vec3& x : m.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    std::vector<Plane> both = box_planes(lo, hi);
    both.insert(both.end(), js.domain.planes.begin(), js.domain.planes.end());
    if (!analyse_polytope(both, js.options.tolerance * js.length_scale).has_interior)
      c.fail(which + " has no volume inside /domain, so it would remove nothing");
  }

  check_zone_info(c, js);

  if (static_cast<std::size_t>(js.options.order) >= kJointOrderNames.size())
    c.fail("/options attribute order is invalid (" +
           std::to_string(static_cast<int>(js.options.order)) + ")");
  c.finite(js.options.min_inscribed_diameter, "/options attribute min_inscribed_diameter");
  c.finite(js.options.max_aspect_ratio, "/options attribute max_aspect_ratio");
  c.finite(js.options.tolerance, "/options attribute tolerance");
  // As [scene] tolerance: every check of /geometry scales with it (fuzz_export: 1.8e271 let a
  // vertex at y = -1e215 through into a PotentialBlock script as a bounding radius of inf).
  if (!(js.options.tolerance > 0 && js.options.tolerance < 1))
    c.fail("/options attribute tolerance is " + num(js.options.tolerance) +
           "; expected a relative tolerance in (0, 1), as [scene] tolerance");
  if (js.options.max_blocks < 1)
    c.fail("/options attribute max_blocks is " + str(js.options.max_blocks) + "; expected >= 1");
}

namespace {

void write_planes(const Group& g, const std::vector<Plane>& planes) {
  std::vector<double> normal, d;
  for (const Plane& p : planes) {
    normal.insert(normal.end(), p.normal.data(), p.normal.data() + 3);
    d.push_back(p.d);
  }
  g.write<double>("normal", normal, 3);
  g.write<double>("d", d);
}

// The stochastic parameters of a set and what generation achieved (docs/design.md, "Stochastic
// joints"), as attributes of its /sets group. Vectors are three scalars (_x, _y, _z). Unused
// parameters are 0.
void write_set_generation(const Group& sg, const JointSetSpec& s) {
  sg.write_attribute<std::string>("intensity", to_string(s.intensity));
  sg.write_attribute("fisher_kappa", s.fisher_kappa);
  sg.write_attribute("density", s.density);
  sg.write_attribute("count", s.count);
  sg.write_attribute("p32", s.p32);
  sg.write_attribute("p10", s.p10);
  sg.write_attribute<std::int64_t>("scanline_given", s.scanline_given ? 1 : 0);
  for (int k = 0; k < 3; ++k) {
    const std::string axis(1, "xyz"[k]);
    sg.write_attribute("scanline_from_" + axis, s.scanline_from(k));
    sg.write_attribute("scanline_to_" + axis, s.scanline_to(k));
  }
  sg.write_attribute<std::string>("size_distribution", to_string(s.size.distribution));
  sg.write_attribute("size_value", s.size.value);
  sg.write_attribute("size_mean", s.size.mean);
  sg.write_attribute("size_sd", s.size.sd);
  sg.write_attribute("size_exponent", s.size.exponent);
  sg.write_attribute("size_min", s.size.min);
  sg.write_attribute("size_max", s.size.max);
  sg.write_attribute<std::string>("shape", to_string(s.shape));
  sg.write_attribute("aspect", s.aspect);
  sg.write_attribute("sides", s.sides);
  sg.write_attribute<std::string>("fit", to_string(s.fit));
  sg.write_attribute<std::int64_t>("rotation_fixed", s.rotation_fixed ? 1 : 0);
  sg.write_attribute("rotation", s.rotation_deg);
  sg.write_attribute("stream_seed", s.stream_seed);
  sg.write_attribute("enlargement", s.enlargement);
  sg.write_attribute("candidates", s.candidates);
  sg.write_attribute("achieved_p32", s.achieved_p32);
  sg.write_attribute("achieved_p10", s.achieved_p10);
  if (!s.mapping.given) return;  // files of sets without a mapping window stay as they were
  // [[sets]] mapping and trace_length, then the traces found in the window (TraceStats).
  const TraceMapping& m = s.mapping;
  for (int k = 0; k < 3; ++k)
    sg.write_attribute("mapping_point_" + std::string(1, "xyz"[k]), m.centre(k));
  sg.write_attribute("mapping_dip", m.dip_deg);
  sg.write_attribute("mapping_dip_direction", m.dip_direction_deg);
  sg.write_attribute("mapping_width", m.width);
  sg.write_attribute("mapping_height", m.height);
  sg.write_attribute("trace_length_mean", m.field_mean);
  sg.write_attribute("trace_length_sd", m.field_sd);
  const TraceStats& t = s.traces;
  sg.write_attribute("trace_count", t.count);
  for (std::size_t k = 0; k < 3; ++k)
    sg.write_attribute("trace_censored_" + std::to_string(k), t.censored[k]);
  sg.write_attribute("trace_mean", t.mean);
  sg.write_attribute("trace_sd", t.sd);
  sg.write_attribute("trace_complete_mean", t.complete_mean);
  sg.write_attribute("trace_p21", t.p21);
}

}  // namespace

void write_joint_groups(const Group& root, const JointSystem& js) {
  {
    const Group g = root.create_group("domain");
    g.write_attribute("length_scale", js.length_scale);
    write_planes(g, js.domain.planes);
  }
  {
    const std::size_t n = js.joints.size();
    std::vector<double> normal, d, centre, dip, dip_direction, friction, cohesion, tension, uv;
    std::vector<std::uint8_t> kind, limits;
    std::vector<std::int32_t> set;
    std::vector<std::int8_t> side;
    std::vector<std::int64_t> offset{0};
    for (auto* v : {&d, &dip, &dip_direction, &friction, &cohesion}) v->reserve(n);
    for (const Joint& j : js.joints) {
      normal.insert(normal.end(), j.plane.normal.data(), j.plane.normal.data() + 3);
      d.push_back(j.plane.d);
      centre.insert(centre.end(), j.centre.data(), j.centre.data() + 3);
      dip.push_back(j.dip_deg);
      dip_direction.push_back(j.dip_direction_deg);
      kind.push_back(static_cast<std::uint8_t>(j.kind));
      limits.push_back(j.limits ? 1 : 0);
      set.push_back(j.set);
      friction.push_back(j.friction_angle_deg);
      cohesion.push_back(j.cohesion);
      tension.push_back(j.tension);
      side.push_back(j.boundary_side);
      for (const Vec2& p : j.polygon_uv) uv.insert(uv.end(), p.data(), p.data() + 2);
      offset.push_back(offset.back() + static_cast<std::int64_t>(j.polygon_uv.size()));
    }
    const Group g = root.create_group("joints");
    g.write<double>("normal", normal, 3);
    g.write<double>("d", d);
    g.write<double>("centre", centre, 3);
    g.write<double>("dip", dip);
    g.write<double>("dip_direction", dip_direction);
    g.write<std::uint8_t>("kind", kind);
    g.write<std::int32_t>("set", set);
    g.write<double>("friction_angle", friction);
    g.write<double>("cohesion", cohesion);
    g.write<double>("tension", tension);
    g.write<std::int8_t>("boundary_side", side);
    g.write<std::uint8_t>("limits", limits);
    g.write<std::int64_t>("polygon_offset", offset);
    g.write<double>("polygon_uv", uv, 2);
  }
  {
    const Group g = root.create_group("sets");
    g.write_attribute("count", static_cast<std::int64_t>(js.sets.size()));
    for (std::size_t i = 0; i < js.sets.size(); ++i) {
      const JointSetSpec& s = js.sets[i];
      const Group sg = g.create_group(set_group_name(i));
      sg.write_attribute("name", s.name);
      sg.write_attribute("dip", s.dip_deg);
      sg.write_attribute("dip_direction", s.dip_direction_deg);
      sg.write_attribute("spacing", s.spacing);
      sg.write_attribute("offset", s.offset);
      sg.write_attribute("friction_angle", s.friction_angle_deg);
      sg.write_attribute("cohesion", s.cohesion);
      sg.write_attribute("tension", s.tension);
      sg.write_attribute<std::int64_t>("limits", s.limits ? 1 : 0);
      sg.write_attribute<std::string>("kind", to_string(s.kind));
      sg.write_attribute<std::int64_t>("boundary_side", s.boundary_side);
      sg.write_attribute("joint_count", s.joint_count);
      write_set_generation(sg, s);
    }
  }
  {
    std::vector<std::int64_t> offset{0};
    std::vector<Plane> planes;
    for (const Region& z : js.zones) {
      planes.insert(planes.end(), z.planes.begin(), z.planes.end());
      offset.push_back(static_cast<std::int64_t>(planes.size()));
    }
    const Group g = root.create_group("zones");
    g.write<std::int64_t>("offset", offset);
    write_planes(g, planes);
    if (!js.zone_meshes.empty()) {  // only then: files without meshes stay as they were
      std::vector<std::int64_t> vertex_offset{0}, triangle_offset{0}, triangles;
      std::vector<double> vertices;
      for (const TriangleMesh& m : js.zone_meshes) {
        for (const Vec3& x : m.vertices) vertices.insert(vertices.end(), x.data(), x.data() + 3);
        for (const auto& t : m.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
        vertex_offset.push_back(std::int64_t(vertices.size() / 3));
        triangle_offset.push_back(std::int64_t(triangles.size() / 3));
      }
      g.write<std::int64_t>("mesh_vertex_offset", vertex_offset);
      g.write<double>("mesh_vertices", vertices, 3);
      g.write<std::int64_t>("mesh_triangle_offset", triangle_offset);
      g.write<std::int64_t>("mesh_triangles", triangles, 3);
    }
    if (!js.zone_info.empty()) {  // one row per zone, regions then meshes (docs/formats.md)
      std::vector<std::uint8_t> kind, cut;
      std::vector<std::int64_t> entry, line;
      std::vector<std::int8_t> ground;
      std::vector<double> volume, above;
      for (const ZoneInfo& i : js.zone_info) {
        kind.push_back(static_cast<std::uint8_t>(i.kind));
        entry.push_back(i.entry);
        line.push_back(i.line);
        cut.push_back(i.cut ? 1 : 0);
        ground.push_back(static_cast<std::int8_t>(i.ground));
        volume.push_back(i.volume);
        above.push_back(i.volume_above_ground);
      }
      g.write<std::uint8_t>("kind", kind);
      g.write<std::int64_t>("entry", entry);
      g.write<std::int64_t>("line", line);
      g.write<std::uint8_t>("cut", cut);
      g.write<std::int8_t>("above_ground", ground);
      g.write<double>("volume", volume);
      g.write<double>("volume_above_ground", above);
    }
  }
  {
    const Group g = root.create_group("options");
    g.write_attribute<std::string>("order", to_string(js.options.order));
    g.write_attribute("min_inscribed_diameter", js.options.min_inscribed_diameter);
    g.write_attribute("max_aspect_ratio", js.options.max_aspect_ratio);
    g.write_attribute("tolerance", js.options.tolerance);
    g.write_attribute<std::int64_t>("max_blocks", js.options.max_blocks);
    g.write_attribute<std::string>("fixed_faces", fixed_faces_string(js.options.fixed_faces));
    g.write_attribute<std::string>("slivers",
                                   std::string(kSliverRuleNames[std::size_t(js.options.slivers)]));
  }
  if (js.rock.given) {  // [rock]: intact rock for rock-bridge contacts (docs/3dec.md)
    const Group g = root.create_group("rock");
    g.write_attribute("friction_angle", js.rock.friction_angle_deg);
    g.write_attribute("cohesion", js.rock.cohesion);
    g.write_attribute("tension", js.rock.tension);
  }
}

namespace {

std::vector<Plane> read_planes(const Group& g, const std::string& count_what) {
  const auto normal = g.read<double>("normal", 3);
  const auto d = g.read<double>("d");
  const std::size_t n = normal.size() / 3;
  expect_rows(g, "d", d.size(), n, count_what);
  std::vector<Plane> planes(n);
  for (std::size_t i = 0; i < n; ++i) planes[i] = {vec3(normal, i), d[i]};
  return planes;
}

// A name attribute read back into its enum.
template <class Enum>
Enum read_name(const Group& sg, const std::string& attr,
               std::optional<Enum> (*parse)(std::string_view), const std::string& expected) {
  const auto v = sg.read_attribute<std::string>(attr);
  const auto parsed = parse(v);
  if (!parsed) fail(sg, sg.attribute_label(attr) + " is \"" + v + "\"; expected " + expected);
  return *parsed;
}

// The inverse of write_set_generation. A file without these attributes (written before
// stochastic sets existed) holds regular sets only: the defaults stand.
void read_set_generation(const Group& sg, JointSetSpec& s) {
  if (!sg.has_attribute("intensity")) return;
  s.intensity = read_name<SetIntensity>(sg, "intensity", parse_set_intensity,
                                        "spacing, density, count, p32, p10 or deterministic");
  s.fisher_kappa = sg.read_attribute<double>("fisher_kappa");
  s.density = sg.read_attribute<double>("density");
  s.count = sg.read_attribute<std::int64_t>("count");
  s.p32 = sg.read_attribute<double>("p32");
  s.p10 = sg.read_attribute<double>("p10");
  s.scanline_given = sg.read_attribute<std::int64_t>("scanline_given") != 0;
  for (int k = 0; k < 3; ++k) {
    const std::string axis(1, "xyz"[k]);
    s.scanline_from(k) = sg.read_attribute<double>("scanline_from_" + axis);
    s.scanline_to(k) = sg.read_attribute<double>("scanline_to_" + axis);
  }
  s.size.distribution =
      read_name<SizeDistribution>(sg, "size_distribution", parse_size_distribution,
                                  "none, fixed, lognormal, exponential or power-law");
  s.size.value = sg.read_attribute<double>("size_value");
  s.size.mean = sg.read_attribute<double>("size_mean");
  s.size.sd = sg.read_attribute<double>("size_sd");
  s.size.exponent = sg.read_attribute<double>("size_exponent");
  s.size.min = sg.read_attribute<double>("size_min");
  s.size.max = sg.read_attribute<double>("size_max");
  s.shape = read_name<JointShape>(sg, "shape", parse_joint_shape,
                                  "square, rectangle, polygon or ellipse");
  s.aspect = sg.read_attribute<double>("aspect");
  s.sides = sg.read_attribute<std::int64_t>("sides");
  s.fit = read_name<EllipseFit>(sg, "fit", parse_ellipse_fit, "circumscribed or equal-area");
  s.rotation_fixed = sg.read_attribute<std::int64_t>("rotation_fixed") != 0;
  s.rotation_deg = sg.read_attribute<double>("rotation");
  s.stream_seed = sg.read_attribute<std::uint64_t>("stream_seed");
  s.enlargement = sg.read_attribute<double>("enlargement");
  s.candidates = sg.read_attribute<std::int64_t>("candidates");
  s.achieved_p32 = sg.read_attribute<double>("achieved_p32");
  s.achieved_p10 = sg.read_attribute<double>("achieved_p10");
  if (!sg.has_attribute("mapping_dip")) return;
  TraceMapping& m = s.mapping;
  m.given = true;
  for (int k = 0; k < 3; ++k)
    m.centre(k) = sg.read_attribute<double>("mapping_point_" + std::string(1, "xyz"[k]));
  m.dip_deg = sg.read_attribute<double>("mapping_dip");
  m.dip_direction_deg = sg.read_attribute<double>("mapping_dip_direction");
  m.width = sg.read_attribute<double>("mapping_width");
  m.height = sg.read_attribute<double>("mapping_height");
  m.field_mean = sg.read_attribute<double>("trace_length_mean");
  m.field_sd = sg.read_attribute<double>("trace_length_sd");
  TraceStats& t = s.traces;
  t.count = sg.read_attribute<std::int64_t>("trace_count");
  for (std::size_t k = 0; k < 3; ++k)
    t.censored[k] = sg.read_attribute<std::int64_t>("trace_censored_" + std::to_string(k));
  t.mean = sg.read_attribute<double>("trace_mean");
  t.sd = sg.read_attribute<double>("trace_sd");
  t.complete_mean = sg.read_attribute<double>("trace_complete_mean");
  t.p21 = sg.read_attribute<double>("trace_p21");
}

// /zones/mesh_*: closed meshes, each with its own vertices (checked by check_joints).
std::vector<TriangleMesh> read_zone_meshes(const Group& g) {
  const auto vertex_offset = g.read<std::int64_t>("mesh_vertex_offset");
  const auto vertices = g.read<double>("mesh_vertices", 3);
  const auto triangle_offset = g.read<std::int64_t>("mesh_triangle_offset");
  const auto triangles = g.read<std::int64_t>("mesh_triangles", 3);
  if (vertex_offset.empty()) fail(g, "/zones/mesh_vertex_offset is empty; expected at least 0");
  const std::size_t meshes = vertex_offset.size() - 1;
  check_offsets(g, "mesh_vertex_offset", vertex_offset, meshes, "meshes", vertices.size() / 3,
                "/zones/mesh_vertices");
  check_offsets(g, "mesh_triangle_offset", triangle_offset, meshes, "meshes", triangles.size() / 3,
                "/zones/mesh_triangles");
  std::vector<TriangleMesh> out(meshes);
  for (std::size_t k = 0; k < meshes; ++k) {
    for (auto v = vertex_offset[k]; v < vertex_offset[k + 1]; ++v)
      out[k].vertices.push_back(vec3(vertices, std::size_t(v)));
    for (auto t = triangle_offset[k]; t < triangle_offset[k + 1]; ++t) {
      const auto i = 3 * std::size_t(t);
      out[k].triangles.push_back({triangles[i], triangles[i + 1], triangles[i + 2]});
    }
  }
  return out;
}

// /joints: one row per joint, its polygon as CSR (polygon_offset, polygon_uv).
void read_joints_group(const Group& root, JointSystem& js) {
  const Group g = root.open_group("joints");
  const auto normal = g.read<double>("normal", 3);
  const std::size_t n = normal.size() / 3;
  const std::string because = "the rows of /joints/normal";
  const auto d = read_rows<double>(g, "d", n, because);
  const auto centre = read_rows<double>(g, "centre", n, because, 3);
  const auto dip = read_rows<double>(g, "dip", n, because);
  const auto dip_direction = read_rows<double>(g, "dip_direction", n, because);
  const auto kind = read_rows<std::uint8_t>(g, "kind", n, because);
  const auto set = read_rows<std::int32_t>(g, "set", n, because);
  const auto friction = read_rows<double>(g, "friction_angle", n, because);
  const auto cohesion = read_rows<double>(g, "cohesion", n, because);
  const auto side = read_rows<std::int8_t>(g, "boundary_side", n, because);
  std::vector<double> tension(n, 0.0);  // files from before tension: 0
  if (g.exists("tension")) tension = g.read<double>("tension");
  expect_rows(g, "tension", tension.size(), n, because);
  // Files from before the limits exemption: every joint obeys the limits.
  std::vector<std::uint8_t> limits(n, 1);
  if (g.exists("limits")) {
    limits = g.read<std::uint8_t>("limits");
    expect_rows(g, "limits", limits.size(), n, because);
    for (std::size_t i = 0; i < n; ++i)
      if (limits[i] > 1)
        fail(g, "/joints/limits[" + str(i) + "] is " + str(std::int64_t{limits[i]}) +
                    "; expected 0 or 1");
  }
  const auto offset = g.read<std::int64_t>("polygon_offset");
  const auto uv = g.read<double>("polygon_uv", 2);
  check_offsets(g, "polygon_offset", offset, n, "joints", uv.size() / 2, "/joints/polygon_uv");

  js.joints.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Joint& j = js.joints[i];
    j.plane = {vec3(normal, i), d[i]};
    j.centre = vec3(centre, i);
    j.dip_deg = dip[i];
    j.dip_direction_deg = dip_direction[i];
    j.kind = static_cast<JointKind>(kind[i]);  // range checked by check_joints
    j.set = set[i];
    j.friction_angle_deg = friction[i];
    j.cohesion = cohesion[i];
    j.tension = tension[i];
    j.boundary_side = side[i];
    j.limits = limits[i] == 1;
    for (auto k = static_cast<std::size_t>(offset[i]); k < static_cast<std::size_t>(offset[i + 1]);
         ++k)
      j.polygon_uv.emplace_back(uv[2 * k], uv[2 * k + 1]);
  }
}

// /sets: one group per set, its parameters as attributes.
void read_sets_group(const Group& root, JointSystem& js) {
  const Group g = root.open_group("sets");
  const auto count = g.read_attribute<std::int64_t>("count");
  if (count < 0 || static_cast<std::size_t>(count) != g.member_count())
    fail(g, "/sets holds " + str(g.member_count()) + " groups but its attribute count is " +
                str(count));
  for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) {
    const Group sg = g.open_group(set_group_name(i));
    JointSetSpec s;
    s.name = sg.read_attribute<std::string>("name");
    s.dip_deg = sg.read_attribute<double>("dip");
    s.dip_direction_deg = sg.read_attribute<double>("dip_direction");
    s.spacing = sg.read_attribute<double>("spacing");
    s.offset = sg.read_attribute<double>("offset");
    s.friction_angle_deg = sg.read_attribute<double>("friction_angle");
    s.cohesion = sg.read_attribute<double>("cohesion");
    if (sg.has_attribute("tension")) s.tension = sg.read_attribute<double>("tension");
    if (sg.has_attribute("limits")) {  // files from before the exemption: 1
      const auto limits = sg.read_attribute<std::int64_t>("limits");
      if (limits != 0 && limits != 1)
        fail(sg, "/sets/" + set_group_name(i) + " attribute limits is " + str(limits) +
                     "; expected 0 or 1");
      s.limits = limits == 1;
    }
    const auto kind = sg.read_attribute<std::string>("kind");
    const auto parsed = parse_joint_kind(kind);
    if (!parsed)
      fail(sg, sg.attribute_label("kind") + " is \"" + kind +
                   "\"; expected \"rock\", \"construction\" or \"boundary\"");
    s.kind = *parsed;
    const auto side = sg.read_attribute<std::int64_t>("boundary_side");
    if (side < -1 || side > 1)
      fail(sg, sg.attribute_label("boundary_side") + " is " + str(side) + "; expected -1, 0 or 1");
    s.boundary_side = static_cast<std::int8_t>(side);
    s.joint_count = sg.read_attribute<std::int64_t>("joint_count");
    read_set_generation(sg, s);
    js.sets.push_back(std::move(s));
  }
}

// /zones: the regions (CSR of planes) and the meshes.
void read_zones_group(const Group& root, JointSystem& js) {
  const Group g = root.open_group("zones");
  const auto offset = g.read<std::int64_t>("offset");
  if (offset.empty()) fail(g, "/zones/offset is empty; expected at least one row (0)");
  const auto planes = read_planes(g, "the rows of /zones/normal");
  check_offsets(g, "offset", offset, offset.size() - 1, "zones", planes.size(), "/zones/normal");
  for (std::size_t z = 0; z + 1 < offset.size(); ++z)
    js.zones.push_back(
        {std::vector<Plane>(planes.begin() + offset[z], planes.begin() + offset[z + 1])});
  // The four /zones/mesh_* datasets come together: some without the others is a damaged file,
  // not one without meshes (whose zone would be dropped without a word).
  const char* parts[] = {"mesh_vertex_offset", "mesh_vertices", "mesh_triangle_offset",
                         "mesh_triangles"};
  const auto n =
      std::count_if(std::begin(parts), std::end(parts), [&](const char* p) { return g.exists(p); });
  for (const char* p : parts)
    if (n > 0 && !g.exists(p))
      fail(g, std::string("/zones/") + p + " is missing, though /zones has other mesh_* " +
                  "datasets (a mesh zone)");
  if (n > 0) js.zone_meshes = read_zone_meshes(g);
  // What each zone is (kind ...): files from before have none, and list their zones' kinds as
  // not known; the seven datasets come together.
  const char* info[] = {
      "kind", "entry", "line", "cut", "above_ground", "volume", "volume_above_ground"};
  const auto m =
      std::count_if(std::begin(info), std::end(info), [&](const char* p) { return g.exists(p); });
  for (const char* p : info)
    if (m > 0 && !g.exists(p))
      fail(g, std::string("/zones/") + p + " is missing, though /zones has " +
                  (g.exists("kind") ? "kind" : "others of kind, entry, line, cut, ...") +
                  " (written together)");
  if (m == 0) return;
  const std::size_t zones = js.zones.size() + js.zone_meshes.size();
  const std::string because = "the zones (/zones/offset's regions, then the meshes)";
  const auto kind = read_rows<std::uint8_t>(g, "kind", zones, because);
  const auto entry = read_rows<std::int64_t>(g, "entry", zones, because);
  const auto line = read_rows<std::int64_t>(g, "line", zones, because);
  const auto cut = read_rows<std::uint8_t>(g, "cut", zones, because);
  const auto ground = read_rows<std::int8_t>(g, "above_ground", zones, because);
  const auto volume = read_rows<double>(g, "volume", zones, because);
  const auto above = read_rows<double>(g, "volume_above_ground", zones, because);
  for (std::size_t z = 0; z < zones; ++z) {
    if (cut[z] > 1)
      fail(g, at("/zones/cut", z) + " is " + str(std::int64_t{cut[z]}) + "; expected 0 or 1");
    // kind and above_ground ranges: check_zone_info
    js.zone_info.push_back({static_cast<ZoneKind>(kind[z]), entry[z], line[z], cut[z] == 1,
                            static_cast<ZoneGround>(ground[z]), volume[z], above[z]});
  }
}

// /options: attributes; files from before an option keep its default.
void read_options_group(const Group& root, JointSystem& js) {
  const Group g = root.open_group("options");
  const auto order = g.read_attribute<std::string>("order");
  const auto parsed = parse_joint_order(order);
  if (!parsed)
    fail(g, "/options attribute order is \"" + order +
                "\"; expected as-given, largest-first, by-set or alternating");
  js.options.order = *parsed;
  js.options.min_inscribed_diameter = g.read_attribute<double>("min_inscribed_diameter");
  js.options.max_aspect_ratio = g.read_attribute<double>("max_aspect_ratio");
  js.options.tolerance = g.read_attribute<double>("tolerance");
  // Files written before max_blocks existed keep the default.
  if (g.has_attribute("max_blocks"))
    js.options.max_blocks = g.read_attribute<std::int64_t>("max_blocks");
  if (g.has_attribute("fixed_faces")) {  // so are files from before fixed_faces: none
    const auto faces = g.read_attribute<std::string>("fixed_faces");
    const auto bits = parse_fixed_faces(faces);
    if (!bits)
      fail(g, "/options attribute fixed_faces is \"" + faces +
                  "\"; expected face names -x, +x, -y, +y, -z, +z joined by commas");
    js.options.fixed_faces = *bits;
  }
  if (g.has_attribute("slivers")) {  // files from before the rule: join (what it did)
    const auto rule = g.read_attribute<std::string>("slivers");
    const auto k = std::find(kSliverRuleNames.begin(), kSliverRuleNames.end(), rule);
    if (k == kSliverRuleNames.end())
      fail(g, "/options attribute slivers is \"" + rule + "\"; expected join or excavate");
    js.options.slivers = static_cast<SliverRule>(k - kSliverRuleNames.begin());
  }
}

}  // namespace

JointSystem read_joint_groups(const Group& root) {
  JointSystem js;
  js.dimension = read_root_header(root).dimension;
  js.name = root.read_attribute<std::string>("name");
  js.seed = root.read_attribute<std::uint64_t>("seed");
  {
    const Group g = root.open_group("domain");
    js.length_scale = g.read_attribute<double>("length_scale");
    js.domain.planes = read_planes(g, "the rows of /domain/normal");
  }
  read_joints_group(root, js);
  read_sets_group(root, js);
  read_zones_group(root, js);
  read_options_group(root, js);
  if (root.exists("rock")) {  // files without [rock] (and from before it) have no /rock
    const Group g = root.open_group("rock");
    js.rock = {true, g.read_attribute<double>("friction_angle"),
               g.read_attribute<double>("cohesion"), g.read_attribute<double>("tension")};
  }
  return js;
}

}  // namespace slice::h5file

namespace slice {

using namespace h5file;

void write_joints(const fs::path& out, const JointSystem& js, const Provenance& prov,
                  const WriteOptions& opt) {
  check_joints(Checker(out.string(), kNotWritten), js);
  write_file(out, FileKind::joints, prov, js, opt, [](const Group&) {});
}

JointSystem read_joints(const fs::path& in) {
  const h5::File f = h5::File::open(in, {in.string(), kJointsFix});
  expect_kind(f.root(), FileKind::joints);
  JointSystem js = read_joint_groups(f.root());
  check_joints(Checker(in.string(), kJointsFix), js);
  return js;
}

}  // namespace slice

#include "slice/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include "scene_read.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/polytope.hpp"
#include "slice/stochastic.hpp"
#include "slice/utf8.hpp"

namespace slice {

namespace {
template <typename Enum, std::size_t N>
std::optional<Enum> parse_name(std::string_view s, const std::array<std::string_view, N>& names) {
  for (std::size_t i = 0; i < N; ++i)
    if (s == names[i]) return static_cast<Enum>(i);
  return std::nullopt;
}
}  // namespace

// The tables hold string literals, so data() is NUL-terminated.
const char* to_string(JointKind k) { return kJointKindNames.at(std::size_t(k)).data(); }
const char* to_string(JointOrder o) { return kJointOrderNames.at(std::size_t(o)).data(); }
std::optional<JointKind> parse_joint_kind(std::string_view s) {
  return parse_name<JointKind>(s, kJointKindNames);
}
std::optional<JointOrder> parse_joint_order(std::string_view s) {
  return parse_name<JointOrder>(s, kJointOrderNames);
}
std::vector<Plane> solid_region(const Region& region, int dimension) {
  std::vector<Plane> planes = region.planes;
  if (dimension == 2) {
    planes.push_back({-Vec3::UnitY(), 0.5});
    planes.push_back({Vec3::UnitY(), 0.5});
  }
  return planes;
}

std::string fixed_faces_string(std::uint8_t faces) {
  std::string s;
  for (std::size_t k = 0; k < kBoxFaceNames.size(); ++k)
    if (faces & (1u << k)) {
      if (!s.empty()) s += ',';
      s += kBoxFaceNames[k];
    }
  return s;
}
std::optional<std::uint8_t> parse_fixed_faces(std::string_view text) {
  std::uint8_t faces = 0;
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    const auto k = parse_name<std::size_t>(text.substr(0, comma), kBoxFaceNames);
    if (!k) return std::nullopt;
    faces |= static_cast<std::uint8_t>(1u << *k);
    text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
  }
  return faces;
}
const char* to_string(SetIntensity v) { return kSetIntensityNames.at(std::size_t(v)).data(); }
const char* to_string(SizeDistribution v) {
  return kSizeDistributionNames.at(std::size_t(v)).data();
}
const char* to_string(JointShape v) { return kJointShapeNames.at(std::size_t(v)).data(); }
const char* to_string(EllipseFit v) { return kEllipseFitNames.at(std::size_t(v)).data(); }
std::optional<SetIntensity> parse_set_intensity(std::string_view s) {
  return parse_name<SetIntensity>(s, kSetIntensityNames);
}
std::optional<SizeDistribution> parse_size_distribution(std::string_view s) {
  return parse_name<SizeDistribution>(s, kSizeDistributionNames);
}
std::optional<JointShape> parse_joint_shape(std::string_view s) {
  return parse_name<JointShape>(s, kJointShapeNames);
}
std::optional<EllipseFit> parse_ellipse_fit(std::string_view s) {
  return parse_name<EllipseFit>(s, kEllipseFitNames);
}

}  // namespace slice

namespace slice::scene_read {

// ---------------------------------------------------------------------------------------------
// Regions (domain, zones)

// Analyses a region with tolerances relative to its own size. A first pass with a tolerance from
// the planes' offsets finds the vertices roughly; the length scale L of those sets the absolute
// tolerance rel * L of the second pass, so a scene in mm or shifted by 1e6 m gives the same
// answers as the same scene in m at the origin (docs/design.md, "Tolerances and the length scale").
// A 2-D section's planes are its slab's (solid_region); its size is measured in (x, z).
RegionAnalysis analyse_region(std::span<const Plane> planes, double rel, int dimension) {
  const bool section = dimension == 2;
  RegionAnalysis a;
  double dmax = 0;
  for (const auto& p : planes) dmax = std::max(dmax, std::abs(p.d));
  const PolytopeInfo rough = analyse_polytope(planes, rel * dmax);
  if (!rough.bounded) {
    a.status = RegionStatus::unbounded;
    return a;
  }
  if (rough.vertices.empty()) return a;
  const double rough_scale = 0.5 * (rough.max - rough.min).norm();
  a.info = analyse_polytope(planes, rel * rough_scale);
  if (!a.info.bounded) {
    a.status = RegionStatus::unbounded;
    return a;
  }
  if (a.info.vertices.empty() || !a.info.has_interior) return a;
  Vec3 size = a.info.max - a.info.min;
  if (section) size.y() = 0;
  a.length_scale = 0.5 * size.norm();
  a.status = a.length_scale > 0 ? RegionStatus::ok : RegionStatus::empty;
  return a;
}

// Range of n . v over the domain's vertices.
std::pair<double, double> extent_along(const std::vector<Vec3>& vertices, const Vec3& n) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& v : vertices) {
    lo = std::min(lo, n.dot(v));
    hi = std::max(hi, n.dot(v));
  }
  return {lo, hi};
}

// The upward unit normal of dip / dip direction; in a 2-D section (dip direction 90 or 270)
// exactly (+-sin dip, 0, cos dip), so that every normal has y = 0 (docs/2d.md).
Vec3 dip_normal(double dip_deg, double dip_direction_deg, int dimension) {
  if (dimension == 3) return normal_from_dip(dip_deg, dip_direction_deg);
  const double dip = dip_deg * std::numbers::pi / 180;
  return {(dip_direction_deg == 270 ? -1.0 : 1.0) * std::sin(dip), 0.0, std::cos(dip)};
}

// The region of a table with `box` or `planes` (its keys already checked).
Region region_of(const Tbl& t, int dimension) {
  const Reader& r = t.r;
  const toml::node* box = t.find("box");
  const toml::node* planes = t.find("planes");
  const std::string both =
      dimension == 3
          ? "box = { min = [x, y, z], max = [x, y, z] } or planes = [ { normal = [nx, ny, nz], d "
            "= d }, ... ] (outward normals, normal . x <= d inside)"
          : "box = { min = [x, z], max = [x, z] } or planes = [ { normal = [nx, nz], d = d }, "
            "... ] (outward normals, normal . x <= d inside)";
  const std::string corner = dimension == 3 ? "[x, y, z]" : "[x, z]";
  if (box && planes) r.fail(*planes, t.ctx + " gives both 'box' and 'planes'", "keep one of them");
  if (!box && !planes) r.fail(t.t, t.ctx + " has neither 'box' nor 'planes'", "add " + both);
  Region region;
  if (box) {
    const Tbl b{r,
                as_table(r, *box, t.label("box"),
                         "write box = { min = " + corner + ", max = " + corner + " }"),
                "'box' of " + t.ctx};
    b.check_keys(kBoxKeys);
    const Vec3 mn = to_point(r, b.require("min", "add min = " + corner + ", the lower corner"),
                             b.label("min"), dimension);
    const Vec3 mx = to_point(r, b.require("max", "add max = " + corner + ", the upper corner"),
                             b.label("max"), dimension);
    for (int i = 0; i < 3; ++i)
      if (!(mn(i) < mx(i)) && !(dimension == 2 && i == 1)) {
        const std::string axis(1, "xyz"[i]);
        r.fail(*b.find("max"),
               "'box' of " + t.ctx + " has min " + axis + " = " + fmt(mn(i)) + " >= max " + axis +
                   " = " + fmt(mx(i)),
               "make min the lower corner and max the upper corner, min < max in every axis");
      }
    region.planes = box_planes(mn, mx);
    if (dimension == 2)  // no faces normal to y in a section
      std::erase_if(region.planes, [](const Plane& p) { return p.normal.y() != 0; });
    return region;
  }
  const auto elems = table_array(r, *planes, t.label("planes"), "write " + both);
  if (elems.empty()) r.fail(*planes, t.label("planes") + " is empty", "write " + both);
  for (std::size_t i = 0; i < elems.size(); ++i) {
    const Tbl p{r, *elems[i], "plane #" + std::to_string(i + 1) + " of " + t.ctx};
    p.check_keys(kPlaneKeys);
    const toml::node& nn =
        p.require("normal", dimension == 3 ? "add normal = [nx, ny, nz], pointing outward"
                                           : "add normal = [nx, nz], pointing outward");
    const Vec3 n = to_point(r, nn, p.label("normal"), dimension);
    const double d = required_number(p, "d", "add d, so that the plane is normal . x = d");
    const double len = std::isfinite(n.norm()) && n.norm() > 0 ? n.norm() : n.stableNorm();
    if (!(len > 0) || !std::isfinite(len))
      r.fail(nn, p.label("normal") + " is " + fmt(n) + ", which has no direction",
             "give the plane's outward normal, e.g. [0, 0, 1] for a top face");
    // Unit normals: scale d with the normal, so that the half-space itself does not change.
    region.planes.push_back({n / len, d / len});
  }
  return region;
}

DomainBox domain_box(const Region& domain, const RegionAnalysis& a, double rel_tol) {
  DomainBox b;
  b.planes = domain.planes;
  b.min = a.info.min;
  b.max = a.info.max;
  b.interior_point = a.info.interior_point;
  b.volume = a.info.volume;
  b.tol = rel_tol * a.length_scale;
  return b;
}

// An entry's place in the sequence: `stage` (a whole number >= 1, default 1) and its line.
EntryPlace read_place(const Reader& r, const toml::table& t, const std::string& ctx,
                      std::int64_t entry) {
  EntryPlace p;
  p.line = t.source().begin.line;
  p.entry = entry;
  if (const toml::node* n = t.get("stage")) {
    p.stage = to_integer(r, *n, quote_key("stage") + " in " + ctx);
    if (p.stage < 1)
      r.fail(*n, quote_key("stage") + " in " + ctx + " is " + std::to_string(p.stage) + ", below 1",
             "give a whole number >= 1: stage 1 is introduced first, then 2, ...");
  }
  return p;
}

namespace {

// Whether [scene] gives a name (else the scene is named after its file).
bool st_has_name(const toml::table& root) {
  const toml::node* st = root.get("scene");
  return st != nullptr && st->is_table() && st->as_table()->get("name") != nullptr;
}

Region read_region(const Tbl& t, int dimension) {
  t.check_keys(kRegionKeys);
  return region_of(t, dimension);
}

// [scene]: name, seed, max_joints, tolerance.
void read_scene_table(const Reader& r, const toml::table& st, Scene& scene) {
  const Tbl t{r, st, "[scene]"};
  t.check_keys(kSceneKeys);
  if (const toml::node* n = t.find("name")) {
    scene.name = to_text(r, *n, t.label("name"));
    if (scene.name.find('\0') != std::string::npos)  // HDF5 strings end at a NUL
      r.fail(*n, t.label("name") + " holds a NUL character", "remove the \\u0000 from the name");
  }
  if (const toml::node* n = t.find("seed")) {
    const auto* i = n->as_integer();
    if (!i)
      r.fail(*n, t.label("seed") + " must be an integer, not " + type_name(*n),
             "write a whole number >= 0 without quotes or decimals");
    if (i->get() < 0)
      r.fail(*n, t.label("seed") + " is " + std::to_string(i->get()) + ", below 0",
             "give a seed >= 0");
    scene.seed = static_cast<std::uint64_t>(i->get());
  }
  if (const toml::node* n = t.find("max_joints")) {
    scene.max_joints = to_integer(r, *n, t.label("max_joints"));
    if (scene.max_joints < 1)
      r.fail(*n, t.label("max_joints") + " is " + std::to_string(scene.max_joints) + ", below 1",
             "give the most joints one stochastic set may draw, >= 1 (default " +
                 std::to_string(kDefaultMaxJoints) + ")");
  }
  if (const toml::node* n = t.find("dimension")) {
    const std::int64_t d = to_integer(r, *n, t.label("dimension"));
    if (d != 2 && d != 3)
      r.fail(*n, t.label("dimension") + " is " + std::to_string(d) + ", not 2 or 3",
             "write dimension = 2 for a section in (x, z) (docs/2d.md), or leave it out for 3-D");
    scene.dimension = static_cast<int>(d);
  }
  scene.options.tolerance = number(t, "tolerance", 1e-9);
  if (!(scene.options.tolerance > 0 && scene.options.tolerance < 1))
    r.fail(*t.find("tolerance"),
           t.label("tolerance") + " is " + fmt(scene.options.tolerance) + ", outside (0, 1)",
           "give a small positive number relative to the domain size, e.g. 1e-9");
}

// [rock]: friction_angle, cohesion, tension of intact rock.
void read_rock(const Reader& r, const toml::table& rt, Scene& scene) {
  const Tbl t{r, rt, "[rock]"};
  t.check_keys(kRockKeys);
  scene.rock.given = true;
  scene.rock.friction_angle_deg = number(t, "friction_angle", 30);
  check_range(t, "friction_angle", scene.rock.friction_angle_deg, 0, 90, true,
              "give the friction angle in degrees, 0 <= friction_angle < 90");
  scene.rock.cohesion = stress(t, "cohesion", 0);
  scene.rock.tension = stress(t, "tension", 0);
}

// [options]: order, limits, max_blocks, fixed_faces, slivers.
void read_options(const Reader& r, const toml::table& ot, Scene& scene) {
  const Tbl t{r, ot, "[options]"};
  t.check_keys(kOptionKeys);
  if (const toml::node* n = t.find("order"))
    scene.options.order =
        static_cast<JointOrder>(to_choice(r, *n, t.label("order"), kJointOrderNames));
  const double dmin = number(t, "min_inscribed_diameter", 0);
  if (dmin < 0)
    r.fail(*t.find("min_inscribed_diameter"),
           t.label("min_inscribed_diameter") + " is " + fmt(dmin) + ", below 0",
           "give a length >= 0 (0: no size limit)");
  scene.options.min_inscribed_diameter = dmin;
  const double amax = number(t, "max_aspect_ratio", 0);
  if (amax < 0 || (amax > 0 && amax < 1))
    r.fail(*t.find("max_aspect_ratio"),
           t.label("max_aspect_ratio") + " is " + fmt(amax) + "; it must be 0 (none) or >= 1",
           "give 0 for no shape limit, or a ratio >= 1 (bounding radius / inscribed radius)");
  scene.options.max_aspect_ratio = amax;
  if (const toml::node* n = t.find("slivers"))
    scene.options.slivers =
        static_cast<SliverRule>(to_choice(r, *n, t.label("slivers"), kSliverRuleNames));
  if (const toml::node* n = t.find("max_blocks")) {
    scene.options.max_blocks = to_integer(r, *n, t.label("max_blocks"));
    if (scene.options.max_blocks < 1)
      r.fail(
          *n,
          t.label("max_blocks") + " is " + std::to_string(scene.options.max_blocks) + ", below 1",
          "give the most blocks slice-cut may make, >= 1 (default " +
              std::to_string(kDefaultMaxBlocks) + ")");
  }
  if (const toml::node* n = t.find("fixed_faces")) {
    const std::string label = t.label("fixed_faces");
    const auto* a = n->as_array();
    if (!a)
      r.fail(*n, label + " must be an array of face names, not " + type_name(*n),
             "write e.g. fixed_faces = [\"-z\", \"+x\"]");
    for (const toml::node& f : *a) {
      const std::size_t k = to_choice(r, f, label, kBoxFaceNames);
      if (scene.dimension == 2 && (k == 2 || k == 3))
        r.fail(f, label + " names \"" + std::string(kBoxFaceNames[k]) + "\" in a 2-D scene",
               "a section in (x, z) has the faces -x, +x, -z and +z");
      if (scene.options.fixed_faces & (1u << k))
        r.fail(f, label + " names \"" + std::string(kBoxFaceNames[k]) + "\" twice",
               "name each face once");
      scene.options.fixed_faces |= static_cast<std::uint8_t>(1u << k);
    }
  }
}

}  // namespace

}  // namespace slice::scene_read

namespace slice {

using namespace scene_read;

std::vector<SceneKeys> scene_keys() {
  const auto list = [](Keys keys) {
    return std::vector<std::string_view>(keys.begin(), keys.end());
  };
  // `size` takes the keys of its distribution: all of them, each once.
  std::vector<std::string_view> size;
  for (const Keys keys :
       {Keys(kFixedKeys), Keys(kLognormalKeys), Keys(kExponentialKeys), Keys(kPowerLawKeys)})
    for (const auto& k : keys)
      if (std::find(size.begin(), size.end(), k) == size.end()) size.push_back(k);
  return {{"", "", list(kTopTables)},
          {"scene", "", list(kSceneKeys)},
          {"domain", "", list(kRegionKeys)},
          {"domain", "box", list(kBoxKeys)},
          {"domain", "planes", list(kPlaneKeys)},
          {"options", "", list(kOptionKeys)},
          {"joints", "", list(kJointKeys)},
          {"sets", "", list(kSetKeys)},
          {"sets", "size", std::move(size)},
          {"sets", "scanline", list(kScanlineKeys)},
          {"sets", "mapping", list(kMappingKeys)},
          {"sets", "trace_length", list(kTraceLengthKeys)},
          {"zones", "", list(kZoneKeys)},
          {"zones", "box", list(kBoxKeys)},
          {"zones", "planes", list(kPlaneKeys)},
          {"zones", "tunnel", list(kTunnelKeys)},
          {"rock", "", list(kRockKeys)},
          {"section", "", list(kSectionKeys)},
          {"dfn", "", list(kDfnKeys)},
          {"dfn", "sets", list(kDfnSetKeys)}};
}

namespace {

// The scene file's text parsed; the characters toml++ 3.3 cannot take moved out of its way
// (shelter).
toml::table parse_toml(const Reader& r, const std::string& text, const std::string& file) {
  toml::table root;
  const std::string safe = shelter(text, false, [&](char32_t c, std::size_t at) {
    char code[16];
    std::snprintf(code, sizeof code, "U+%05X", static_cast<unsigned>(c));
    toml::source_region where{};
    where.begin.line = static_cast<toml::source_index>(
        1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    r.fail(where, std::string("character ") + code + " (private use) is not accepted in a scene",
           "remove it");
  });
  try {
    root = toml::parse(std::string_view(safe), std::string_view(file));
  } catch (const toml::parse_error& e) {
    r.fail(e.source(), "TOML syntax error: " + std::string(e.description()),
           "fix the syntax on this line (see https://toml.io)");
  }
  return root;
}

// Top level: only the known tables.
void check_top_tables(const Reader& r, const toml::table& root) {
  const toml::key* bad = nullptr;
  for (auto&& [k, v] : root)
    if (std::find(kTopTables.begin(), kTopTables.end(), k.str()) == kTopTables.end())
      if (!bad || k.source().begin.line < bad->source().begin.line) bad = &k;
  if (bad) {
    const toml::node& v = *root.get(bad->str());
    const bool is_array = v.is_array_of_tables();
    auto form = [](std::string_view n) {
      const bool arr = n == "joints" || n == "sets" || n == "zones" || n == "dfn";
      return (arr ? "[[" : "[") + std::string(n) + (arr ? "]]" : "]");
    };
    const std::string near = closest(bad->str(), kTopTables);
    std::string home;  // a key of a table written outside it: say which table
    const std::pair<std::string_view, Keys> homes[] = {
        {"[scene]", kSceneKeys}, {"[domain]", kRegionKeys}, {"[options]", kOptionKeys}};
    for (const auto& [table, keys] : homes)
      if (!v.is_table() && !is_array &&
          std::find(keys.begin(), keys.end(), bad->str()) != keys.end())
        home = table;
    const std::string what = v.is_table() ? "unknown table [" + std::string(bad->str()) + "]"
                             : is_array
                                 ? "unknown table [[" + std::string(bad->str()) + "]]"
                                 : "unknown key " + quote_key(bad->str()) + " outside any table";
    std::string known;
    for (const auto& k : kTopTables) known += (known.empty() ? "" : ", ") + form(k);
    r.fail(bad->source(), what,
           !home.empty()  ? "put it under " + home
           : near.empty() ? "the tables of a scene are " + known
                          : "did you mean " + form(near) + "?");
  }
}

// [domain] (`dt`, read first: every tolerance below scales with its size) and the context
// the entries are read in.
Context read_domain(const Reader& r, const toml::table& dt, const std::filesystem::path& name,
                    Scene& scene) {
  const Tbl dtbl{r, dt, "[domain]"};
  scene.domain = read_region(dtbl, scene.dimension);
  const Region solid{solid_region(scene.domain, scene.dimension)};
  Context cx{r, scene.dimension,
             analyse_region(solid.planes, scene.options.tolerance, scene.dimension),
             scene.options.tolerance};
  cx.dir = name.parent_path();
  {
    const toml::node& at = dt.get("planes") ? *dt.get("planes") : dt;
    if (cx.domain_info.status == RegionStatus::unbounded)
      r.fail(at, "the 'planes' of [domain] do not enclose a bounded region",
             "add planes (outward normals, normal . x <= d inside) that close it in every "
             "direction");
    if (cx.domain_info.status == RegionStatus::empty && dt.get("box")) {
      // min < max on every axis (region_of): only the tolerance flattens a box.
      Vec3 size = Vec3::Zero();  // box_planes: axis normals, the two d of an axis add up
      for (const Plane& p : scene.domain.planes) size += p.d * p.normal.cwiseAbs();
      int thin = 0;  // the thinnest axis (a section has no y)
      (scene.dimension == 2 ? Vec3(size.x(), INFINITY, size.z()) : size).minCoeff(&thin);
      const double scale = 0.5 * size.norm(), tol = scene.options.tolerance * scale;
      r.fail(
          *dt.get("box"),
          "the 'box' of [domain] is only " + fmt(size(thin), 4) + " thick in " +
              std::string(1, "xyz"[thin]) + ": the tolerance, " + fmt(scene.options.tolerance, 4) +
              " x the length scale " + fmt(scale, 4) + " = " + fmt(tol, 4) +
              ", leaves it no volume",
          "make the box thicker than a few times " + fmt(tol, 4) + ", or lower [scene] tolerance");
    }
    if (cx.domain_info.status == RegionStatus::empty)
      r.fail(at,
             "the 'planes' of [domain] enclose no volume (the half-spaces normal . x <= d "
             "have no common interior)",
             "check that every normal points outward and every d puts the plane on the "
             "domain's face");
  }
  if (const std::string why =
          precision_problem(cx.domain_info.info.min, cx.domain_info.info.max, cx.tol());
      !why.empty())
    r.fail(dt, "[domain]: " + why,
           "move the scene nearer the origin (subtract a local origin from every coordinate) or "
           "raise [scene] tolerance");
  cx.box = domain_box(solid, cx.domain_info, scene.options.tolerance);
  cx.max_joints = scene.max_joints;
  return cx;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::filesystem::path& name) {
  const std::string file = name.string();
  const Reader r(file);
  const toml::table root = parse_toml(r, text, file);
  // Each of the known tables, of its kind.
  check_top_tables(r, root);
  auto single = [&](std::string_view key) -> const toml::table* {
    const toml::node* n = root.get(key);
    if (!n) return nullptr;
    const std::string s(key);
    return &as_table(r, *n, "[" + s + "]", "write it as a table: a line [" + s + "] and its keys");
  };
  auto multi = [&](std::string_view key) {
    const toml::node* n = root.get(key);
    if (!n) return std::vector<const toml::table*>{};
    const std::string s(key);
    if (n->is_table())
      r.fail(*n, "[" + s + "] must be an array of tables, [[" + s + "]]",
             "write [[" + s + "]] (double brackets) before each entry");
    return table_array(r, *n, "'" + s + "'", "write [[" + s + "]] before each entry");
  };

  Scene scene;
  scene.source = name;
  scene.name = name.stem().string();
  if (const toml::table* st = single("scene")) read_scene_table(r, *st, scene);
  // The outputs keep the name as UTF-8 text (HDF5 strings, Python str): a file name in Latin-1
  // made files that slice-info and Python could not read (issue 42 item 5).
  if (!st_has_name(root))
    for (std::size_t i = 0; i < scene.name.size();) {
      const auto [c, len] = decode_utf8(scene.name, i);
      if (len == 0)
        r.fail(root,
               "the scene's name is its file name's stem, which is not UTF-8 text (its byte " +
                   std::to_string(i + 1) + " begins no UTF-8 character)",
               "rename the file in UTF-8, or give the name in the scene: [scene] name = \"...\"");
      i += len;
    }

  // Domain first: every tolerance below scales with its size.
  const toml::table* dt = single("domain");
  if (!dt)
    r.fail(root, "the scene has no [domain]",
           "add [domain] with box = { min = [x, y, z], max = [x, y, z] } or planes = [...]");
  Context cx = read_domain(r, *dt, name, scene);

  if (const toml::table* ot = single("options")) read_options(r, *ot, scene);
  cx.max_blocks = scene.options.max_blocks;
  if (const toml::table* rt = single("rock")) read_rock(r, *rt, scene);
  if (const toml::table* st = single("section")) {
    cx.section = read_section_plane(cx, *st);
    scene.section = cx.section;
  }

  const auto joints = multi("joints");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    scene.joints.push_back(read_joint(cx, *joints[i], i));
    scene.joint_places.push_back(read_place(r, *joints[i], "[[joints]] #" + std::to_string(i + 1),
                                            static_cast<std::int64_t>(i)));
  }

  std::set<std::string> names;
  const auto sets = multi("sets");
  for (std::size_t i = 0; i < sets.size(); ++i) {
    SectionTrace trace;
    scene.sets.push_back(read_set(cx, *sets[i], i, names, &trace));
    if (scene.sets.back().name.find('\0') != std::string::npos)  // HDF5 strings end at a NUL
      r.fail(*sets[i]->get("name"),
             "'name' in [[sets]] #" + std::to_string(i + 1) + " holds a NUL character",
             "remove the \\u0000 from the set's name");
    if (cx.section) scene.set_traces.push_back(trace);
    scene.set_places.push_back(read_place(r, *sets[i],
                                          "[[sets]] \"" + scene.sets.back().name + "\"",
                                          static_cast<std::int64_t>(joints.size() + i)));
  }

  const auto dfns = multi("dfn");
  for (std::size_t i = 0; i < dfns.size(); ++i) {
    DfnEntry d =
        read_dfn(cx, *dfns[i], i, static_cast<std::int64_t>(joints.size() + sets.size() + i), names,
                 scene.sets.size());
    std::move(d.joints.begin(), d.joints.end(), std::back_inserter(scene.joints));
    std::move(d.places.begin(), d.places.end(), std::back_inserter(scene.joint_places));
    std::move(d.sets.begin(), d.sets.end(), std::back_inserter(scene.sets));
    std::move(d.set_places.begin(), d.set_places.end(), std::back_inserter(scene.set_places));
    scene.dfn_files.push_back(d.file);
  }
  assign_joint_sets(cx, joints, scene);

  // A cut tunnel's joints come after every [[joints]] and [[sets]] entry unless given a stage:
  // the paper's order, construction joints after the rock joints (section 3.4).
  std::int64_t last_stage = 0;
  for (const auto* places : {&scene.joint_places, &scene.set_places})
    for (const EntryPlace& p : *places) last_stage = std::max(last_stage, p.stage);
  const auto zones = multi("zones");
  // Zones are numbered regions first, then meshes (slice-extract --near-zone): so their info.
  std::vector<ZoneInfo> mesh_info;
  for (std::size_t i = 0; i < zones.size(); ++i) {
    ZoneEntry z =
        read_zone(cx, *zones[i], i, last_stage + 1,
                  static_cast<std::int64_t>(joints.size() + sets.size() + dfns.size() + i));
    const ZoneInfo info{z.kind, static_cast<std::int64_t>(i), z.place.line, z.cut};
    scene.zone_info.insert(scene.zone_info.end(), z.regions.size(), info);
    std::move(z.regions.begin(), z.regions.end(), std::back_inserter(scene.zones));
    if (z.mesh) {
      mesh_info.push_back(info);
      scene.zone_meshes.push_back(std::move(*z.mesh));
      scene.mesh_files.push_back(z.mesh_file);
    }
    for (Joint& j : z.joints) {
      scene.joints.push_back(std::move(j));
      scene.joint_places.push_back(z.place);
    }
  }
  scene.zone_info.insert(scene.zone_info.end(), mesh_info.begin(), mesh_info.end());
  return scene;
}

std::vector<std::pair<std::string, std::filesystem::path>> scene_files(const Scene& scene) {
  std::vector<std::pair<std::string, std::filesystem::path>> files;
  for (const auto& f : scene.mesh_files) files.emplace_back("the [[zones]] mesh or surface", f);
  for (const auto& f : scene.dfn_files) files.emplace_back("the [[dfn]] file", f);
  return files;
}

Scene load_scene(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec))
    throw Error(file.string(), "scene file not found", "check the path");
  if (std::filesystem::is_directory(file, ec))
    throw Error(file.string(), "is a directory, not a scene file", "give the .toml file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string(), "cannot open the scene file", "check its permissions");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw Error(file.string(), "reading the scene file failed", "check the file");
  return parse_scene(text, file);
}

}  // namespace slice

#pragma once
// What the readers of a scene file share (libslice/src/scene/: scene.cpp reads the file and its
// single tables, joint_entries.cpp [[joints]] and [[sets]], zones.cpp [[zones]]): the scene's
// schema, the keys of each table, and the context every entry is read in (scene_common.hpp has
// what generate.cpp needs too). Private to libslice/src/scene/.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene_common.hpp"
#include "slice/mesh.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"
#include "slice/stochastic.hpp"
#include "toml_read.hpp"

namespace slice::scene_read {

// The keys of each table of a scene file (docs/scenes.md).
inline constexpr std::array<std::string_view, 9> kTopTables = {
    "scene", "domain", "options", "joints", "sets", "zones", "rock", "section", "dfn"};
inline constexpr std::array<std::string_view, 5> kSceneKeys = {"name", "seed", "tolerance",
                                                               "max_joints", "dimension"};
inline constexpr std::array<std::string_view, 2> kRegionKeys = {"box", "planes"};
// A zone is a region, a tunnel, a mesh or a surface; `cut` and `stage` apply to all but regions.
inline constexpr std::array<std::string_view, 7> kZoneKeys = {"box", "planes", "tunnel", "mesh",
                                                              "cut", "stage",  "surface"};
inline constexpr std::array<std::string_view, 6> kTunnelKeys = {"point",  "direction", "length",
                                                                "radius", "sides",     "outline"};
// A tunnel's default number of sides: the 16-gon's area is 1.3 % above its inscribed circle's.
inline constexpr std::int64_t kDefaultTunnelSides = 16;
inline constexpr std::array<std::string_view, 2> kBoxKeys = {"min", "max"};
inline constexpr std::array<std::string_view, 2> kPlaneKeys = {"normal", "d"};
inline constexpr std::array<std::string_view, 6> kOptionKeys = {
    "order", "min_inscribed_diameter", "max_aspect_ratio", "max_blocks", "fixed_faces", "slivers"};
inline constexpr std::array<std::string_view, 14> kJointKeys = {
    "dip",      "dip_direction", "point", "polygon", "polygon_uv", "kind",    "friction_angle",
    "cohesion", "keep",          "stage", "limits",  "segment",    "tension", "set"};
inline constexpr std::array<std::string_view, 26> kSetKeys = {
    "name",           "dip",      "dip_direction", "spacing", "offset",      "kind", "keep",
    "friction_angle", "cohesion", "fisher_kappa",  "density", "count",       "p32",  "p10",
    "scanline",       "size",     "shape",         "aspect",  "sides",       "fit",  "rotation",
    "stage",          "limits",   "tension",       "mapping", "trace_length"};
// A set's mapping window (TraceMapping) and the trace lengths mapped in it.
inline constexpr std::array<std::string_view, 5> kMappingKeys = {"point", "dip", "dip_direction",
                                                                 "width", "height"};
inline constexpr std::array<std::string_view, 2> kTraceLengthKeys = {"mean", "sd"};
// [section]: the vertical plane a 2-D scene cuts 3-D joint sets in (section.cpp).
inline constexpr std::array<std::string_view, 3> kSectionKeys = {"point", "strike", "normal"};
// [rock]: intact rock, for the contacts DEM exports put through rock bridges (RockSpec).
inline constexpr std::array<std::string_view, 3> kRockKeys = {"friction_angle", "cohesion",
                                                              "tension"};
// The intensity keys of a set, in the order of SetIntensity: exactly one is given.
inline constexpr std::array<std::string_view, 5> kIntensityKeys = {"spacing", "density", "count",
                                                                   "p32", "p10"};
// Keys that only finite (sized) joints of a stochastic set take.
inline constexpr std::array<std::string_view, 5> kFiniteKeys = {"shape", "aspect", "sides", "fit",
                                                                "rotation"};
inline constexpr std::array<std::string_view, 2> kScanlineKeys = {"from", "to"};
// The keys of `size` for each distribution (SizeDistribution order; "none" takes none).
inline constexpr std::array<std::string_view, 2> kFixedKeys = {"distribution", "value"};
inline constexpr std::array<std::string_view, 3> kLognormalKeys = {"distribution", "mean", "sd"};
inline constexpr std::array<std::string_view, 2> kExponentialKeys = {"distribution", "mean"};
inline constexpr std::array<std::string_view, 4> kPowerLawKeys = {"distribution", "exponent", "min",
                                                                  "max"};
// Distributions a scene may name (SizeDistribution without "none").
inline constexpr std::array<std::string_view, 4> kSizeNames = {"fixed", "lognormal", "exponential",
                                                               "power-law"};
// More corners than this is a slip (a polygon is meant, not a circle drawn point by point).
inline constexpr std::int64_t kMaxSides = 1000;

inline constexpr std::array<std::string_view, 2> kKeepNames = {"above", "below"};

// [[dfn]] (dfn_entries.cpp): a DFN file's fractures, and what its joints get, for the whole file
// or, in `sets`, per set of the file.
inline constexpr std::array<std::string_view, 14> kDfnKeys = {
    "file",   "format", "kind",  "keep", "friction_angle", "cohesion", "tension", "stage",
    "limits", "order",  "sides", "fit",  "planarity",      "sets"};
inline constexpr std::array<std::string_view, 7> kDfnSetKeys = {
    "kind", "keep", "friction_angle", "cohesion", "tension", "stage", "limits"};
inline constexpr std::array<std::string_view, 2> kDfnFormats = {"fab", "csv"};
// A FAB fracture's nodes may lie this far (x its radius) from its plane: FAB files carry 6 to 9
// significant digits, and a 1e-4 tilt changes no block a DEM model could tell apart.
inline constexpr double kDefaultPlanarity = 1e-4;

// ---------------------------------------------------------------------------------------------
// Regions (domain, zones): scene.cpp

// The region of a table with `box` or `planes` (its keys already checked).
Region region_of(const Tbl& t, int dimension);

// The context every [[joints]], [[sets]] and [[zones]] entry is read in.
struct Context {
  const Reader& r;
  int dimension = 3;
  RegionAnalysis domain_info;
  double rel_tol = 1e-9;
  DomainBox box{};  // the domain as the joint generator sees it
  std::int64_t max_joints = kDefaultMaxJoints;
  std::int64_t max_blocks = kDefaultMaxBlocks;  // [options] max_blocks (a cut surface's check)
  std::filesystem::path dir{};  // the scene file's directory: relative mesh paths start there
  std::optional<SectionPlane> section{};  // [section]: dips are 3-D, traced in the section
  double tol() const { return rel_tol * domain_info.length_scale; }
};

// An entry's place in the sequence: `stage` (a whole number >= 1, default 1) and its line.
EntryPlace read_place(const Reader& r, const toml::table& t, const std::string& ctx,
                      std::int64_t entry);

// ---------------------------------------------------------------------------------------------
// [section]: section.cpp

SectionPlane read_section_plane(const Context& cx, const toml::table& st);
// The trace of a 3-D dip / dip direction of entry `t` in cx.section; refuses a parallel plane.
SectionTrace trace_in_section(const Context& cx, const Tbl& t, double dip, double dip_direction);

// ---------------------------------------------------------------------------------------------
// Entries: joint_entries.cpp, zones.cpp

Joint read_joint(const Context& cx, const toml::table& tt, std::size_t index);
// `names`: the names of the sets before it (two sets may not share one). In a section
// (cx.section) the set is its trace, and `trace` (if given) receives how it was traced.
JointSetSpec read_set(const Context& cx, const toml::table& tt, std::size_t index,
                      std::set<std::string>& names, SectionTrace* trace = nullptr);

// What a [[zones]] entry makes: removal regions and, for a tunnel with cut = true, the
// construction joints along its surface, all introduced at `place`.
struct ZoneEntry {
  std::vector<Region> regions;
  std::optional<TriangleMesh> mesh;
  std::filesystem::path mesh_file;
  std::vector<Joint> joints;
  EntryPlace place;
  ZoneKind kind = ZoneKind::box;
  bool cut = false;
};

// What a [[dfn]] entry makes: its fractures as joints (each in a set of the file), the file's
// sets (intensity deterministic), their places, and the file read (for the tools' checks).
struct DfnEntry {
  std::vector<Joint> joints;
  std::vector<EntryPlace> places;
  std::vector<JointSetSpec> sets;
  std::vector<EntryPlace> set_places;
  std::filesystem::path file;
};
// `names`: the names of the sets before it; `first_set`: the index its first set will have.
DfnEntry read_dfn(const Context& cx, const toml::table& tt, std::size_t index, std::int64_t entry,
                  std::set<std::string>& names, std::size_t first_set);
// The `set` keys of [[joints]] (tables[i] made scene.joints[i]): a set of a [[dfn]] file, or a
// new set of that name, made by its first joint.
void assign_joint_sets(const Context& cx, const std::vector<const toml::table*>& tables,
                       Scene& scene);

// A [[zones]] entry: box, planes, tunnel, mesh or surface (zones.cpp).
ZoneEntry read_zone(const Context& cx, const toml::table& tt, std::size_t index,
                    std::int64_t default_stage, std::int64_t entry);
// True if one of the regions has volume inside the domain (zones.cpp).
bool meets_domain(const Context& cx, std::span<const Region> regions);
// The file a zone's `key` names (relative paths from the scene's directory), which must exist;
// `kinds` names what it should be ("an OBJ or STL") (zones.cpp).
std::filesystem::path zone_file(const Context& cx, const Tbl& t, const toml::node& node,
                                std::string_view key, const std::string& kinds);
// One construction joint per triangle of `mesh` that reaches into the domain (cut = true of
// mesh and surface zones; zones.cpp).
void add_face_joints(const Context& cx, const TriangleMesh& mesh, std::vector<Joint>& joints);
// A [[zones]] surface, the rock above a height field: its closed solid in z.mesh
// (surface_zone.cpp).
void read_surface_zone(const Context& cx, const Tbl& t, const toml::node& node, bool cut,
                       ZoneEntry& z);

}  // namespace slice::scene_read

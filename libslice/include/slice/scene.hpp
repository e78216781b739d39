#pragma once
// The scene (docs/scenes.md) and the joint system it generates (the content of joints.h5;
// docs/design.md, "Files and schema").
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/mesh.hpp"

namespace slice {

enum class JointKind : std::uint8_t { rock = 0, construction = 1, boundary = 2 };
enum class JointOrder { as_given, largest_first, by_set, alternating };

/// The names scene files and HDF5 files use, indexed by the enum's value (a public contract).
inline constexpr std::array<std::string_view, 3> kJointKindNames = {"rock", "construction",
                                                                    "boundary"};
inline constexpr std::array<std::string_view, 4> kJointOrderNames = {"as-given", "largest-first",
                                                                     "by-set", "alternating"};

/// The most joints a stochastic set may draw unless [scene] max_joints says otherwise: 1e6 take
/// about 4 s to draw and 170 MB in joints.h5.
inline constexpr std::int64_t kDefaultMaxJoints = 1'000'000;

const char* to_string(JointKind k);
const char* to_string(JointOrder o);
/// The enum named by s, or nothing if s names none.
std::optional<JointKind> parse_joint_kind(std::string_view s);
std::optional<JointOrder> parse_joint_order(std::string_view s);

/// One joint: a plane, optionally bounded by a convex polygon.
struct Joint {
  Plane plane;                   // upward unit normal, global frame: normal . x = d
  Vec3 centre = Vec3::Zero();    // a point on the plane, origin of polygon_uv (global)
  double dip_deg = 0;            // [0, 90]
  double dip_direction_deg = 0;  // [0, 360)
  JointKind kind = JointKind::rock;
  std::int32_t set = -1;  // index into JointSystem::sets; -1 = a [[joints]] entry
  double friction_angle_deg = 30;
  double cohesion = 0;            // Pa
  std::int8_t boundary_side = 0;  // boundary joints: +1 keep blocks above (the side the normal
                                  // points to), -1 below; 0 for other kinds
  std::vector<Vec2> polygon_uv;   // convex, counter-clockwise in the plane frame (orientation.hpp)
                                  // about centre; empty = persistent
  bool limits = true;             // false: the size and shape limits never undo this joint's cuts
  double tension = 0;             // Pa, tensile strength (>= 0)
  bool persistent() const { return polygon_uv.empty(); }
};

/// A convex region as half-spaces normal . x <= d with outward unit normals.
struct Region {
  std::vector<Plane> planes;
};

/// Slicing options from the scene's [options] and [scene] tables.
/// The default [options] max_blocks: about 2.8 GB and 10 s at slice-cut's peak (1.4 kB and
/// 5 us a block on 2 threads, measured at 964,156 blocks), so a typo (a spacing of 1e-4 for 1) is
/// refused in seconds instead of running for minutes; bigger jobs raise it.
inline constexpr std::int64_t kDefaultMaxBlocks = 2'000'000;

/// The faces of the domain's bounding box, in the order of box_planes: -x +x -y +y -z +z.
inline constexpr std::array<std::string_view, 6> kBoxFaceNames = {"-x", "+x", "-y",
                                                                  "+y", "-z", "+z"};

/// What becomes of a sliver: a free block (kept, in no cluster) under the size or shape limits,
/// which only cuts exempt from them leave (docs/design.md, "Clusters and slivers").
enum class SliverRule {
  join,     // it joins the cluster of the kept neighbour it touches most
  excavate  // next to an excavated block, within min_inscribed_diameter: removed with it; else join
};
inline constexpr std::array<std::string_view, 2> kSliverRuleNames = {"join", "excavate"};

struct SliceOptions {
  JointOrder order = JointOrder::as_given;
  double min_inscribed_diameter = 0;            // 0 = no size limit
  double max_aspect_ratio = 0;                  // 0 = no shape limit
  double tolerance = 1e-9;                      // relative to JointSystem::length_scale
  std::int64_t max_blocks = kDefaultMaxBlocks;  // slice-cut refuses to make more blocks
  // Bit k: blocks that touch face kBoxFaceNames[k] of the domain's bounding box are fixed
  // (kFixed): boundary conditions without boundary joints ([options] fixed_faces).
  std::uint8_t fixed_faces = 0;
  SliverRule slivers = SliverRule::join;  // [options] slivers
};

/// How a [[sets]] entry says how many joints it has (docs/design.md, "Stochastic joints").
enum class SetIntensity {
  spacing,       // regular persistent planes n . x = offset + k * spacing
  density,       // Poisson process: centres per unit volume
  count,         // this many joints that meet the domain
  p32,           // joints until their area inside the domain per unit volume reaches p32
  p10,           // joints until those crossing the scanline per unit length reach p10
  deterministic  // the joints are given: a [[dfn]] file's set, or [[joints]] with `set`
};
enum class SizeDistribution { persistent, fixed, lognormal, exponential, power_law };
enum class JointShape { square, rectangle, polygon, ellipse };
enum class EllipseFit { circumscribed, equal_area };

/// Names in scene files and HDF5 attributes, indexed by the enums' values (a public contract).
inline constexpr std::array<std::string_view, 6> kSetIntensityNames = {
    "spacing", "density", "count", "p32", "p10", "deterministic"};
inline constexpr std::array<std::string_view, 5> kSizeDistributionNames = {
    "none", "fixed", "lognormal", "exponential", "power-law"};
inline constexpr std::array<std::string_view, 4> kJointShapeNames = {"square", "rectangle",
                                                                     "polygon", "ellipse"};
inline constexpr std::array<std::string_view, 2> kEllipseFitNames = {"circumscribed", "equal-area"};

const char* to_string(SetIntensity v);
const char* to_string(SizeDistribution v);
const char* to_string(JointShape v);
const char* to_string(EllipseFit v);
std::optional<SetIntensity> parse_set_intensity(std::string_view s);
std::optional<SizeDistribution> parse_size_distribution(std::string_view s);
std::optional<JointShape> parse_joint_shape(std::string_view s);
std::optional<EllipseFit> parse_ellipse_fit(std::string_view s);

/// The size distribution of a set's joints. Size is the side of a square, the long side of a
/// rectangle, the diameter of the circle through a regular polygon's corners, the long diameter
/// of an ellipse. Parameters the distribution does not use are 0.
struct SizeSpec {
  SizeDistribution distribution = SizeDistribution::persistent;  // persistent: no polygon
  double value = 0;                                              // fixed
  double mean = 0;      // lognormal, exponential: mean of the size itself (not of its log)
  double sd = 0;        // lognormal: standard deviation of the size itself
  double exponent = 0;  // power-law: density proportional to size^-exponent on [min, max]
  double min = 0;
  double max = 0;
};

/// [[sets]] `mapping` and `trace_length` (docs/scenes.md): a rectangular window on a plane where
/// the set's traces are sampled as a field mapper sees them (slice/traces.hpp), and the trace
/// lengths mapped in the field, to compare them with.
struct TraceMapping {
  bool given = false;
  Vec3 centre = Vec3::Zero();  // the window's centre
  double dip_deg = 90;         // the mapping plane
  double dip_direction_deg = 0;
  double width = 0;       // along the plane's strike (u)
  double height = 0;      // along its dip line (v)
  double field_mean = 0;  // trace_length mean; 0: not given
  double field_sd = 0;    // trace_length sd; 0: not given
};
/// The traces of a set's joints on its mapping window: each joint's intersection with the
/// mapping plane, clipped to the window, as long as it is inside.
struct TraceStats {
  std::int64_t count = 0;                  // traces in the window
  std::array<std::int64_t, 3> censored{};  // of them, with 0, 1, 2 ends on the window's border
  double mean = 0, sd = 0;                 // of their lengths inside the window (sd: n - 1)
  double complete_mean = 0;                // mean length of those with no end censored
  double p21 = 0;                          // their total length / the window's area
};

/// A [[sets]] entry as the scene gave it, plus what was generated from it. Angles in degrees.
struct JointSetSpec {
  std::string name;
  double dip_deg = 0;  // mean orientation
  double dip_direction_deg = 0;
  double spacing = 0;  // regular persistent planes n . x = offset + k * spacing
  double offset = 0;
  double friction_angle_deg = 30;
  double cohesion = 0;
  JointKind kind = JointKind::rock;
  std::int8_t boundary_side = 0;
  std::int64_t joint_count = 0;  // generated joints that meet the domain
  double tension = 0;            // Pa, tensile strength (>= 0)

  // Stochastic sets (every intensity but spacing).
  SetIntensity intensity = SetIntensity::spacing;
  double fisher_kappa = 0;  // Fisher concentration of the poles; 0 = every joint at the mean
  double density = 0;       // targets: the one `intensity` names is set, the others are 0
  std::int64_t count = 0;
  double p32 = 0;
  double p10 = 0;
  // The scanline P10 is measured along (and, for intensity p10, targeted on), inside the domain.
  // When the scene gives none: the chord of the domain along the set's mean normal through the
  // mean of the domain's vertices.
  bool scanline_given = false;
  Vec3 scanline_from = Vec3::Zero();
  Vec3 scanline_to = Vec3::Zero();
  SizeSpec size{};
  JointShape shape = JointShape::square;
  double aspect = 1;       // rectangle, ellipse: long / short side or diameter (>= 1)
  std::int64_t sides = 4;  // polygon, ellipse: corners of the polygon
  EllipseFit fit = EllipseFit::circumscribed;
  bool rotation_fixed = false;  // false: each joint turned by a uniform random angle in-plane
  double rotation_deg = 0;      // fixed rotation, counter-clockwise from strike in (u, v)

  bool limits = true;      // false: the set's cuts are exempt from the size and shape limits
  TraceMapping mapping{};  // [[sets]] mapping, trace_length

  // What generation did (stochastic and regular sets alike).
  std::uint64_t stream_seed = 0;  // seed of the set's gsl_rng_mt19937 stream
  double enlargement = 0;         // centres drawn in the domain's bounding box grown by this
  std::int64_t candidates = 0;    // joints drawn, including those that missed the domain
  double achieved_p32 = 0;        // joint area inside the domain / domain volume
  double achieved_p10 = 0;        // joints crossing the scanline / its length
  TraceStats traces{};            // on `mapping`, if given
};

/// Intact rock, the scene's [rock] table: the strength a DEM export gives a contact through
/// intact rock (a rock bridge: where a cut extended a finite joint beyond its polygon,
/// /geometry/face_joint_fraction < 1). joints.h5: attributes of /rock.
struct RockSpec {
  bool given = false;  // the scene has a [rock] table (files without /rock: false)
  double friction_angle_deg = 30;
  double cohesion = 0;  // Pa
  double tension = 0;   // Pa
};

/// Where a [[joints]] or [[sets]] entry stands in the introduction sequence (issue 13): stages
/// in increasing order (`stage = N`, default 1), each stage's entries in file order.
struct EntryPlace {
  std::int64_t stage = 1;
  std::int64_t line = 0;   // the entry's line in the scene file
  std::int64_t entry = 0;  // ties on one line (inline tables): [[joints]] by index, then [[sets]]
};

/// A 2-D scene's section of the 3-D frame ([section], docs/2d.md "Sections of a 3-D scene"): a
/// vertical plane through `point` with horizontal unit normal `normal` = (0, 0, 1) x `along`;
/// a point (x, z) of the section is global point_h + x along + z (0, 0, 1), point_h = (px, py,
/// 0): x the distance along the strike from `point`, z the elevation. Strike 90 (along = +x) is
/// the plane y = py seen as the default section (x, z) is.
struct SectionPlane {
  Vec3 point = Vec3::Zero();
  Vec3 along = Vec3::UnitX();   // horizontal unit vector: the section's x axis
  Vec3 normal = Vec3::UnitY();  // horizontal unit normal
  double strike_deg = 90;       // azimuth of `along`, clockwise from North, [0, 360)
};

/// A 3-D plane orientation (dip, dip direction) traced in a section: the trace's apparent dip
/// in the section's (x, z) frame and how the set's spacing and offset carry over. With n the
/// plane's upward unit normal, the trace is the line (n . along) x + n_z z = c - n . point_h of
/// the section; sin_angle = |(n . along, n_z)| = sin of the angle between n and the section's
/// normal, so the lines of planes n . X = offset + k spacing lie spacing / sin_angle apart.
struct SectionTrace {
  double dip_deg = 0, dip_direction_deg = 0;  // the plane's, in 3-D
  double apparent_dip_deg = 0;                // in the section, [0, 90]
  double apparent_dip_direction_deg = 90;     // 90 (dips towards +x) or 270 (towards -x)
  double sin_angle = 1;                       // 0: the plane is parallel to the section
  double shift = 0;                           // n . point_h
  double spacing(double s) const { return s / sin_angle; }
  double offset(double o) const { return (o - shift) / sin_angle; }
};
SectionTrace section_trace(const SectionPlane& section, double dip_deg, double dip_direction_deg);

/// The kind of [[zones]] entry a removal zone came from (docs/scenes.md). HDF5 /zones/kind, by
/// value (a public contract: only append).
enum class ZoneKind : std::uint8_t { box = 0, planes = 1, tunnel = 2, mesh = 3, surface = 4 };
inline constexpr std::array<std::string_view, 5> kZoneKindNames = {"box", "planes", "tunnel",
                                                                   "mesh", "surface"};
/// Where a zone lies against the ground (the first [[zones]] surface of the scene), as
/// slice-joints measured it (zone_report.hpp). HDF5 /zones/above_ground, by value.
enum class ZoneGround : std::int8_t {
  not_checked = -1,  // no surface in the scene, the surface itself, or a 2-D scene
  below = 0,         // wholly in the rock below the ground
  partly_above = 1,  // part of it in the air above the ground
  wholly_above = 2,  // all of it (in the domain) in the air: it removes no rock
};
const char* to_string(ZoneKind k);
const char* to_string(ZoneGround g);

/// One removal zone: where it came from and what slice-joints measured of it. A JointSystem
/// holds one per zone (its `zones`, then its `zone_meshes`: slice-extract's zone numbers) or
/// none (a file from before /zones/kind, or one built in code).
struct ZoneInfo {
  ZoneKind kind = ZoneKind::box;
  std::int64_t entry = -1;  // the [[zones]] entry, 0-based in file order; -1 not known
  std::int64_t line = 0;    // that entry's line in the scene file; 0 not known
  bool cut = false;         // cut = true: its surface cut into the rock first
  ZoneGround ground = ZoneGround::not_checked;
  double volume = -1;               // its volume inside the domain; -1 not measured (meshes)
  double volume_above_ground = -1;  // of that, the part above the ground; -1 not measured
};

/// What a scene file says, parsed and validated.
struct Scene {
  std::filesystem::path source;  // the file it came from (for messages)
  std::string name;
  std::uint64_t seed = 0;
  std::int64_t max_joints = kDefaultMaxJoints;  // per stochastic set, joints drawn
  int dimension = 3;                            // [scene] dimension: 2 for a section (x, z)
  Region domain;
  SliceOptions options;
  // [[joints]], in file order, then the fractures of [[dfn]] files (set: their file's set), then
  // the construction joints of [[zones]] tunnels with cut = true (tunnel.hpp), zone by zone.
  std::vector<Joint> joints;
  // [[sets]], then the sets of [[dfn]] files, then the sets [[joints]] `set` names (intensity
  // deterministic: their joints are given).
  std::vector<JointSetSpec> sets;
  RockSpec rock;
  std::vector<Region> zones;              // a [[zones]] tunnel may give several (tunnel_regions)
  std::vector<TriangleMesh> zone_meshes;  // [[zones]] mesh: closed meshes (mesh.hpp)
  std::vector<ZoneInfo> zone_info;        // one per zone (zones, then zone_meshes), or none
  std::vector<std::filesystem::path> mesh_files;  // the files they were read from (for tools'
                                                  //   same-file checks)
  std::vector<EntryPlace> joint_places;           // one per joint: its [[joints]] entry or its zone
  std::vector<EntryPlace> set_places;             // one per [[sets]] entry
  std::optional<SectionPlane> section;   // [section]: the 2-D scene is a section of 3-D sets
  std::vector<SectionTrace> set_traces;  // with a section: one per [[sets]] entry
  // The [[dfn]] files read, in file order (for tools' same-file checks and provenance).
  std::vector<std::filesystem::path> dfn_files;
};

/// The joint system of a rock mass: everything in joints.h5.
struct JointSystem {
  std::string name;
  std::uint64_t seed = 0;
  /// 3, or 2 for a section in (x, z) (docs/2d.md): every normal and point has y = 0, the
  /// domain and the blocks have no faces normal to y. HDF5 root attribute `dimension`.
  int dimension = 3;
  Region domain;
  double length_scale = 1;  // the domain's bounding radius: half its bounding-box diagonal
  SliceOptions options;
  std::vector<Joint> joints;  // in the order they will be introduced (options.order)
  std::vector<JointSetSpec> sets;
  RockSpec rock;
  std::vector<Region> zones;
  /// Removal zones of any shape: closed triangle meshes (a block whose centre is inside one is
  /// removed, as for `zones`). HDF5 /zones/mesh_*.
  std::vector<TriangleMesh> zone_meshes;
  /// One per zone (zones, then zone_meshes: the numbers slice-info lists and slice-extract
  /// --near-zone takes), or none (files from before /zones/kind). HDF5 /zones/kind, entry, ...
  std::vector<ZoneInfo> zone_info;
};

/// The keys a scene file's tables accept, from the lists the parser checks them against (for
/// docs/scenes.md and the test that it names them all). `table` is "" for the top level, whose
/// keys are the tables, or a table: "scene", "domain", "options", "joints", "sets", "zones",
/// "rock";
/// `within` is "" or an inline table of it ("box", "planes", "size", "scanline", "tunnel").
struct SceneKeys {
  std::string_view table;
  std::string_view within;
  std::vector<std::string_view> keys;
};
std::vector<SceneKeys> scene_keys();

/// Parses and validates a scene file. Throws Error("<file>:<line>", what, fix) on bad input.
Scene load_scene(const std::filesystem::path& file);
/// The same from a string; `name` stands for the file in messages.
Scene parse_scene(const std::string& text, const std::filesystem::path& name);

/// The files a scene names besides itself ([[zones]] meshes, [[dfn]] files), each with what
/// names it: for the tools' same-file checks and provenance.
std::vector<std::pair<std::string, std::filesystem::path>> scene_files(const Scene& scene);

/// Generates every joint of the scene (sets expanded) in introduction order.
JointSystem generate_joints(const Scene& scene);

/// The region's planes closed, in 2-D, by y = -0.5 and y = 0.5: the unit-thickness slab a
/// section stands for (docs/2d.md), for 3-D polytope analysis (vertices, bounding box; its
/// volume is the section's area). In 3-D the region's own planes.
std::vector<Plane> solid_region(const Region& region, int dimension);

/// fixed_faces as written in scene files and joints.h5: "-z,+x" (kBoxFaceNames order); "" for none.
std::string fixed_faces_string(std::uint8_t faces);
/// The bits of a fixed_faces string, or nothing if it names something else.
std::optional<std::uint8_t> parse_fixed_faces(std::string_view text);

/// Puts joints in introduction order, stage by stage (place[i]: joint i's entry), each stage by
/// `order`: as-given and by-set (the entries in file order, [[joints]] and [[sets]] alike, a
/// set's joints as generated), largest-first (by polygon area, persistent first; ties in file
/// order), alternating (one joint of each entry in turn, each entry largest first). Stable.
void order_joints(std::vector<Joint>& joints, JointOrder order, std::span<const EntryPlace> place);
/// The same with every [[joints]] entry (set < 0) before the sets, all in stage 1.
void order_joints(std::vector<Joint>& joints, JointOrder order);

/// A joint's polygon in global coordinates, counter-clockwise about its upward normal; empty
/// for a persistent joint.
std::vector<Vec3> joint_polygon(const Joint& j);

/// Area of a joint's polygon; +infinity for a persistent joint.
double polygon_area(const Joint& j);

}  // namespace slice

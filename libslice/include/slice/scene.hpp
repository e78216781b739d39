#pragma once
// The scene (DESIGN section 6) and the joint system it generates (the content of joints.h5,
// DESIGN section 7).
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slice/geometry.hpp"

namespace slice {

enum class JointKind : std::uint8_t { rock = 0, construction = 1, boundary = 2 };
enum class JointOrder { as_given, largest_first, by_set, alternating };

/// The names scene files and HDF5 files use, indexed by the enum's value (a public contract).
inline constexpr std::array<std::string_view, 3> kJointKindNames = {"rock", "construction",
                                                                    "boundary"};
inline constexpr std::array<std::string_view, 4> kJointOrderNames = {"as-given", "largest-first",
                                                                     "by-set", "alternating"};

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
  bool persistent() const { return polygon_uv.empty(); }
};

/// A convex region as half-spaces normal . x <= d with outward unit normals.
struct Region {
  std::vector<Plane> planes;
};

/// Slicing options from the scene's [options] and [scene] tables.
struct SliceOptions {
  JointOrder order = JointOrder::as_given;
  double min_inscribed_diameter = 0;  // 0 = no size limit
  double max_aspect_ratio = 0;        // 0 = no shape limit
  double tolerance = 1e-9;            // relative to JointSystem::length_scale
};

/// A [[sets]] entry as the scene gave it, plus what was generated from it.
struct JointSetSpec {
  std::string name;
  double dip_deg = 0;
  double dip_direction_deg = 0;
  double spacing = 0;  // regular persistent planes n . x = offset + k * spacing
  double offset = 0;
  double friction_angle_deg = 30;
  double cohesion = 0;
  JointKind kind = JointKind::rock;
  std::int8_t boundary_side = 0;
  std::int64_t joint_count = 0;  // generated joints that meet the domain
};

/// What a scene file says, parsed and validated.
struct Scene {
  std::filesystem::path source;  // the file it came from (for messages)
  std::string name;
  std::uint64_t seed = 0;
  Region domain;
  SliceOptions options;
  std::vector<Joint> joints;  // [[joints]], in file order
  std::vector<JointSetSpec> sets;
  std::vector<Region> zones;
};

/// The joint system of a rock mass: everything in joints.h5.
struct JointSystem {
  std::string name;
  std::uint64_t seed = 0;
  Region domain;
  double length_scale = 1;  // the domain's bounding radius: half its bounding-box diagonal
  SliceOptions options;
  std::vector<Joint> joints;  // in the order they will be introduced (options.order)
  std::vector<JointSetSpec> sets;
  std::vector<Region> zones;
};

/// Parses and validates a scene file. Throws Error("<file>:<line>", what, fix) on bad input.
Scene load_scene(const std::filesystem::path& file);
/// The same from a string; `name` stands for the file in messages.
Scene parse_scene(const std::string& text, const std::filesystem::path& name);

/// Generates every joint of the scene (sets expanded) in introduction order.
JointSystem generate_joints(const Scene& scene);

/// Puts joints in introduction order: as-given (file order), largest-first (by polygon area,
/// persistent first), by-set (deterministic joints one set each in file order, then the sets),
/// alternating (one joint of each set in turn, each set largest first). Stable.
void order_joints(std::vector<Joint>& joints, JointOrder order);

/// Area of a joint's polygon; +infinity for a persistent joint.
double polygon_area(const Joint& j);

}  // namespace slice

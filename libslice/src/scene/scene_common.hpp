#pragma once
// What reading a scene (scene_read.hpp) and making its joints (generate.cpp) share, without
// TOML: numbers in messages, the domain's analysis, a set's normal and extent. Private to
// libslice/src/scene/; toml_read.cpp and scene.cpp define it.
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/orientation.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"
#include "slice/stochastic.hpp"

namespace slice::scene_read {

// A number (a vector) as messages show it, `digits` significant digits.
std::string fmt(double x, int digits = 12);
std::string fmt(const Vec3& v);

// More planes than this in one set is a unit slip (spacing in m, domain in mm), not a scene.
inline constexpr double kMaxPlanesPerSet = 1e6;

enum class RegionStatus { ok, unbounded, empty };

struct RegionAnalysis {
  RegionStatus status = RegionStatus::empty;
  PolytopeInfo info;
  double length_scale = 0;  // half the bounding-box diagonal of the vertices
};

// A region analysed with tolerances relative to its own size (scene.cpp says how).
RegionAnalysis analyse_region(std::span<const Plane> planes, double rel, int dimension);
// Range of n . v over the domain's vertices.
std::pair<double, double> extent_along(const std::vector<Vec3>& vertices, const Vec3& n);
// The upward unit normal of dip / dip direction (y = 0 in a 2-D section).
Vec3 dip_normal(double dip_deg, double dip_direction_deg, int dimension);
DomainBox domain_box(const Region& domain, const RegionAnalysis& a, double rel_tol);
// What a joint of set `set` takes from its set: kind, set index, friction, cohesion, tension,
// limits and boundary side (generate.cpp).
void set_joint_properties(Joint& j, const JointSetSpec& spec, std::int32_t set);
// The polygon of a 2-D joint, the segment a-b of its line (points with y = 0): the rectangle of
// its plane that spans y from -0.5 to 0.5, in the plane's frame about `centre` (section.cpp).
std::vector<Vec2> segment_polygon(const JointFrame& frame, const Vec3& centre, const Vec3& a,
                                  const Vec3& b);

}  // namespace slice::scene_read

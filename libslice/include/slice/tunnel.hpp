#pragma once
// Tunnel excavations ([[zones]] tunnel, issue 16): a straight prism along an axis whose cross
// section is a polygon star-shaped about the axis, as removal regions and as the construction
// joints that cut the excavation surface into the rock before removal (Boon et al. 2015,
// section 3.4: construction joints outline the opening, then the zone removes what is inside).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/scene.hpp"

namespace slice {

/// The frame of a tunnel's cross-section, (u, v, d) right-handed and orthonormal: d the unit
/// axis direction, v the upward direction perpendicular to d, u = v x d horizontal. For an axis
/// along +y (North), u = -x (West), v = +z: the section as seen from ahead of the tunnel,
/// looking back along -d. A vertical axis (horizontal part of d shorter than kVerticalAxis) has
/// u = +x (made perpendicular to d) and v = d x u (+y for d = +z).
struct TunnelFrame {
  Vec3 u, v, d;
  /// The point at section coordinates uv, distance s along the axis from `point`.
  Vec3 to_global(const Vec3& point, const Vec2& uv, double s = 0) const {
    return point + uv.x() * u + uv.y() * v + s * d;
  }
};
/// Below this length the horizontal part of a unit axis direction counts as none (vertical axis).
inline constexpr double kVerticalAxis = 1e-9;
/// The section frame of an axis along `direction` (any non-zero length).
TunnelFrame tunnel_frame(const Vec3& direction);

/// A tunnel: the prism { point + u a + v b + s d : (a, b) in outline, 0 <= s <= length }.
struct Tunnel {
  Vec3 point = Vec3::Zero();       // on the axis: the section origin (0, 0) at the start
  Vec3 direction = Vec3::UnitY();  // unit axis direction
  double length = 0;               // along the axis from `point`
  std::vector<Vec2> outline;       // section polygon in (u, v), counter-clockwise,
                                   //   star-shaped about (0, 0) (check_outline)
};

/// The regular n-gon that circumscribes the circle of radius `inradius` about (0, 0): the
/// circle of that radius lies inside it, so a round tunnel of that radius is fully excavated.
/// A flat side at the bottom (v = -inradius), counter-clockwise; circumradius inradius /
/// cos(pi / sides).
std::vector<Vec2> regular_outline(double inradius, std::int64_t sides);

/// What is wrong with an outline: `vertex` is the (0-based) vertex it concerns, or nothing.
struct OutlineProblem {
  std::string what, fix;
  std::optional<std::size_t> vertex;
};
/// Checks a cross-section outline: at least 3 vertices, no repeated and no collinear
/// consecutive vertices (each vertex more than `tol` off the line through its neighbours),
/// star-shaped about the axis (the line of every edge passes more than `tol` from (0, 0), which
/// is on its inner side: every vertex is visible from the axis), winding once about it. That
/// makes it simple. On success makes it counter-clockwise and returns nothing.
std::optional<OutlineProblem> check_outline(std::vector<Vec2>& outline, double tol);

/// Whether a checked (counter-clockwise) outline is convex.
bool outline_convex(std::span<const Vec2> outline);

/// The tunnel as removal regions whose union is the prism: one region (its side planes and the
/// two end caps) for a convex outline; else one triangular prism per edge, the fan from the
/// axis, each internal fan plane moved outward by `tol` so that neighbouring prisms overlap and
/// a block centre on a fan plane is inside one of them.
std::vector<Region> tunnel_regions(const Tunnel& t, double tol);
/// The fan alone, for any outline: prism i over the section triangle (0, outline[i],
/// outline[i + 1]), its two fan planes moved outward by `tol`.
std::vector<Region> tunnel_fan(const Tunnel& t, double tol);

/// Construction joints (kind construction, limits = false) along the tunnel's surface: one
/// rectangle per side face, exactly `length` long, and each end cap (one polygon for a convex
/// outline, else a fan of triangles from the axis). A face that lies on or outside a face of
/// the domain (every corner at least -tol outside one of `domain`'s planes) is left out: it
/// would cut nothing. Polygons as [[joints]] gives them: in the plane frame of the joint's dip
/// and dip direction (orientation.hpp), counter-clockwise, about the face's vertex mean.
std::vector<Joint> tunnel_joints(const Tunnel& t, std::span<const Plane> domain, double tol);

/// A tunnel of a 2-D section (docs/2d.md): the prism of the section's unit thickness, `point` at
/// y = 0.5 and `direction` -y, length 1, so that (u, v) = (x, z) about the section point. Its
/// construction joints: one segment joint per edge of the outline (stored as 2-D segments are,
/// the rectangle of the joint's plane from y = -0.5 to 0.5), its normal exactly the edge's with
/// y = 0. An edge on or outside a face of `domain` is left out.
std::vector<Joint> section_tunnel_joints(const Tunnel& t, std::span<const Plane> domain,
                                         double tol);

/// A construction joint (limits = false) on the convex planar polygon `corners` (in order
/// around it, either way), as [[joints]] gives polygons: in the plane frame of its dip and dip
/// direction, counter-clockwise, about the corners' mean. For tunnels and [[zones]] meshes.
Joint construction_face_joint(const std::vector<Vec3>& corners);
/// True if every corner lies on or outside (within tol) one of `domain`'s planes: the face
/// would cut nothing.
bool face_misses_domain(const std::vector<Vec3>& corners, std::span<const Plane> domain,
                        double tol);

/// The area of a polygon (shoelace), positive when counter-clockwise.
double signed_area(std::span<const Vec2> polygon);

}  // namespace slice

#pragma once
// Orientation conventions (docs/design.md, "The linear programs": Frame). Global frame
// x = East, y = North, z = Up. Dip direction alpha clockwise from North, dip delta from
// horizontal, both in degrees at the edges (scene files, HDF5), radians nowhere in this header.
#include "slice/geometry.hpp"

namespace slice {

/// sin and cos of an angle in degrees, reduced to [-45, 45] first, so that they are exact at
/// multiples of 90 and sind(90 - x) == cosd(x), sind(x - 180) == -sind(x) bit for bit.
double sind(double deg);
double cosd(double deg);

/// Upward unit normal n = (sin d sin a, sin d cos a, cos d) of a plane with dip d and
/// dip direction a (degrees).
Vec3 normal_from_dip(double dip_deg, double dip_direction_deg);

struct DipAndDirection {
  double dip_deg = 0;            // [0, 90]
  double dip_direction_deg = 0;  // [0, 360); 0 for a horizontal plane
};
/// The inverse: dip and dip direction of the plane with normal n (any length, any sign).
DipAndDirection dip_from_normal(const Vec3& n);

/// Strike vector: horizontal, azimuth = dip direction - 90 (right-hand rule).
Vec3 strike_vector(double dip_direction_deg);
/// Dip vector: the down-dip line of steepest descent, strike x n (z <= 0).
Vec3 dip_vector(double dip_deg, double dip_direction_deg);

/// The local frame of a joint polygon: u along strike, v = n x strike (along the dip line,
/// pointing up dip), n the upward normal; (u, v, n) is right-handed, so a polygon listed
/// counter-clockwise in (u, v) is counter-clockwise seen from above.
struct JointFrame {
  Vec3 u, v, n;
  Vec3 to_global(const Vec3& origin, const Vec2& uv) const {
    return origin + uv.x() * u + uv.y() * v;
  }
  Vec2 to_uv(const Vec3& origin, const Vec3& x) const {
    return {u.dot(x - origin), v.dot(x - origin)};
  }
};
JointFrame plane_frame(double dip_deg, double dip_direction_deg);

/// The paper's pole in the Priest frame (x North, y East, z Down):
/// N = (cos b cos a, sin b cos a, sin a), a = 90 - dip, b = dip direction - 180 (eq. 1-2).
Vec3 priest_pole(double dip_deg, double dip_direction_deg);
/// A Priest-frame vector (North, East, Down) in the global frame (East, North, Up).
Vec3 priest_to_global(const Vec3& p);

}  // namespace slice

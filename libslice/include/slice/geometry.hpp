#pragma once
// Planes, half-spaces and blocks. A convex block is nothing but its faces (DESIGN section 1).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace slice {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

/// The plane normal . x = d, or the half-space normal . x <= d. |normal| = 1.
struct Plane {
  Vec3 normal = Vec3::UnitZ();
  double d = 0;
  /// Signed distance of x from the plane (positive on the side the normal points to).
  double distance(const Vec3& x) const { return normal.dot(x) - d; }
};

/// The same plane written relative to a local origin o: normal . (x - o) = d - normal . o.
inline Plane to_local(const Plane& p, const Vec3& o) { return {p.normal, p.d - p.normal.dot(o)}; }
inline Plane to_global(const Plane& p, const Vec3& o) { return {p.normal, p.d + p.normal.dot(o)}; }

/// A face of a block: normal . (x - origin) <= d, |normal| = 1, outward.
struct Face {
  Vec3 normal = Vec3::UnitZ();  // unit, outward
  double d = 0;                 // relative to Block::origin, scene length unit
  std::int64_t joint = -1;      // joint that made the face; -1 = domain face
};

/// Bits of Block::flags (HDF5 /blocks/flags, DESIGN section 7).
enum BlockFlag : std::uint8_t { kBoundary = 1u << 0, kRemoved = 1u << 1 };

struct Block {
  Vec3 origin = Vec3::Zero();  // local origin of the faces (its Chebyshev centre once known)
  std::vector<Face> faces;
  double inradius = 0;                                // Chebyshev radius; 0 = not computed
  Eigen::Vector4d bsphere = Eigen::Vector4d::Zero();  // bounding sphere: centre (global), radius
  std::uint8_t flags = 0;                             // BlockFlag bits
  std::int64_t cluster = -1;                          // cluster id; -1 = none
};

}  // namespace slice

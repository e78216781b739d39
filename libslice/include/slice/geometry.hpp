#pragma once
// Planes, half-spaces and blocks. A convex block is nothing but its faces (docs/design.md,
// "Architecture and data flow").
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
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

/// Bits of Block::flags (HDF5 /blocks/flags; docs/design.md, "Files and schema").
// kFixed: the block touches a face of the domain named in [options] fixed_faces, or slice-extract
// fixed it (it lies across the boundary ring of an extracted sub-model).
enum BlockFlag : std::uint8_t { kBoundary = 1u << 0, kRemoved = 1u << 1, kFixed = 1u << 2 };

struct Block {
  Vec3 origin = Vec3::Zero();  // local origin of the faces (its Chebyshev centre once known)
  std::vector<Face> faces;
  double inradius = 0;                                // Chebyshev radius; 0 = not computed
  Eigen::Vector4d bsphere = Eigen::Vector4d::Zero();  // bounding sphere: centre (global), radius
  std::uint8_t flags = 0;                             // BlockFlag bits
  std::int64_t cluster = -1;                          // cluster id; -1 = none
};

/// A block that never moves in a DEM model: a boundary block or one on a fixed_faces face.
inline bool is_fixed(const Block& b) { return (b.flags & (kBoundary | kFixed)) != 0; }

/// Inertia tensor components, in the order of HDF5 /geometry/inertia: xx yy zz xy yz zx.
/// The tensor of the block at unit density about its centroid, I = integral of
/// (|r|^2 Id - r r^T) dV, so off-diagonal entries carry the minus sign (Ixy = -integral x y dV).
using Inertia = std::array<double, 6>;

/// Vertices, face loops and mass properties of every block of a block system (HDF5 /geometry;
/// docs/design.md, "Files and schema"), stored as the file stores them: CSR arrays. Per-block
/// arrays have one row per block (B rows); per-face arrays one row per face, in the order of the
/// blocks' faces (F rows, the rows of /blocks/face_normal).
struct Geometry {
  std::vector<std::int64_t> vertex_offset{0};       // B + 1: block b owns vertices [o_b, o_b+1)
  std::vector<Vec3> vertices;                       // V, global frame
  std::vector<std::int64_t> face_vertex_offset{0};  // F + 1: face f's loop is [o_f, o_f+1)
  std::vector<std::int64_t> face_vertices;          // FV: indices into the block's own vertices
                                                    //   (0-based per block), counter-clockwise
                                                    //   seen from outside; in 2-D an
                                                    //   edge's start and end (docs/2d.md)
  std::vector<double> volume;                       // B
  std::vector<Vec3> centroid;                       // B, global frame
  std::vector<Inertia> inertia;                     // B, about the centroid, unit density
  std::vector<double> face_area;                    // F
  std::vector<double> face_joint_fraction;          // F: part of the face inside its joint's
                                                    //   polygon (1: persistent or domain face)
};

/// Receives the geometry of a run of consecutive blocks, [first, first + part.volume.size()), as
/// a Geometry of its own (its offsets count from 0). compute_geometry hands its result over in
/// runs of kGeometryRun blocks (the last one shorter), in block order. A sanitizer build
/// (SLICE_SANITIZE, which defines SLICE_SMALL_RUNS) uses runs of 1,024: the same code, with
/// run boundaries in the tests' small models, and the tests that need two runs run on 1,331
/// blocks instead of 35,937 (under ASan + UBSan 109 s each, CI's slowest tests).
using GeometrySink = std::function<void(std::size_t first, Geometry&& part)>;
#ifdef SLICE_SMALL_RUNS
inline constexpr std::size_t kGeometryRun = 1024;
#else
inline constexpr std::size_t kGeometryRun = 32768;
#endif

}  // namespace slice

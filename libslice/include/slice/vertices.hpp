#pragma once
// Vertices, face loops and mass properties of the blocks that survive slicing, computed once at the
// end (docs/design.md, "Architecture and data flow" and "Files and schema"). Slicing keeps only
// half-spaces; this is where a block becomes a polyhedron.
//
// Method: the block's faces n_i . (x - o) <= d_i about an interior point o (its Chebyshev
// centre, d_i >= inradius > 0) are dual to the points n_i / d_i; the convex hull of those points
// (CGAL, exact predicates) has one facet per vertex of the block and one vertex per face. So
// the hull's combinatorics are consistent by construction: faces and vertices cannot disagree.
// Where four or more planes meet, the hull splits the (exactly or nearly) coplanar dual facet
// into triangles whose primal vertices coincide: these are merged when closer than the geometry
// tolerance, so such a vertex is one vertex.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/h5io.hpp"
#include "slice/polytope.hpp"  // newell_normal, clip_polygon
#include "slice/progress.hpp"
#include "slice/tolerance.hpp"

namespace slice {

/// The geometry of one block.
struct BlockGeometry {
  std::vector<Vec3> vertices;                    // V by 3, global frame
  std::vector<std::vector<std::int64_t>> loops;  // one per face, in Block::faces order: indices
                                                 //   into vertices, counter-clockwise seen from
                                                 //   outside (right-handed about the normal)
  double volume = 0;
  Vec3 centroid = Vec3::Zero();             // global frame
  Inertia inertia{};                        // about the centroid, unit density (geometry.hpp)
  std::vector<double> face_area;            // one per face
  std::vector<double> face_joint_fraction;  // one per face, in [0, 1]
};

/// The geometry of block `b` (its faces must all touch it: a pruned block). `js` supplies the
/// joint polygons for face_joint_fraction (faces of persistent joints and domain faces get 1);
/// `id` names the block in messages. Throws Error naming the block and the face if a face has
/// no area: fewer than three distinct vertices, or area < tol.geometry * its half perimeter
/// (its in-plane width is below the tolerance), or a face that is not on the block at all.
/// Such a face should have been pruned; it points at a slicer defect, not at bad input data.
/// A block of a section (js.dimension == 2, docs/2d.md) is a convex polygon in (x, z): its
/// vertices (y = 0) counter-clockwise with x to the right and z up, each face's loop the start
/// and end of its edge (2 indices), face_area the edge's length, volume the area, inertia the
/// section's second moments (docs/2d.md), face_joint_fraction the part of the edge between the
/// ends of a segment joint. It throws as above for a face whose edge is no longer than
/// tol.geometry, and for a face normal with a y component.
BlockGeometry block_geometry(const Block& b, const JointSystem& js, const Tolerances& tol,
                             std::size_t id = 0);

/// Mass properties of a closed polyhedron given by counter-clockwise face loops (indices into
/// `vertices`), by tetrahedra from `about` (any point; an interior one is most accurate).
struct MassProperties {
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
  Inertia inertia{};  // about the centroid, unit density
};
MassProperties mass_properties(const std::vector<Vec3>& vertices,
                               const std::vector<std::vector<std::int64_t>>& loops,
                               const Vec3& about);

/// The sign (+1, 0 or -1) of det [q - p; r - p; s - p]: +1 if s lies on the side of the plane
/// p q r that its normal (q - p) x (r - p) points to. Exact for any finite coordinates, as
/// CGAL::orientation (floating-point expansions; CGAL's multiprecision fallback where products
/// could underflow or overflow). The predicate of the dual hull; public for its property test.
int orientation_sign(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s);

struct GeometryStats {
  std::size_t blocks = 0, vertices = 0, faces = 0;
  double seconds = 0;  // compute_geometry's own time (no file I/O)
};

/// Computes bs.geometry for every block (removed blocks too, so volumes add up to the domain).
/// The blocks must be pruned (bs.pruned): a redundant face has no polygon. Throws Error if not,
/// or if a block has a face without area (block_geometry). `threads`: 0 for all cores; the
/// result and the error reported are the same for every count.
GeometryStats compute_geometry(BlockSystem& bs, const Progress& progress = {}, int threads = 0);
/// The same, handed over run by run to `sink` (kGeometryRun blocks each, in block order; the
/// sink is called on one thread at a time, while the next run is computed) instead of stored:
/// BlocksFileWriter::geometry_sink() writes the runs as they come.
GeometryStats compute_geometry(const BlockSystem& bs, const GeometrySink& sink,
                               const Progress& progress = {}, int threads = 0);

}  // namespace slice

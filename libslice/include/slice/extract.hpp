#pragma once
// libslice/src/geometry/extract.cpp: sub-models (issue 26 item 3, docs/submodels.md). The blocks
// of a geom.h5 within a region (a box, a sphere, a capped cylinder, or the points within a
// distance of the file's zones), as a block system of their own that write_blocks writes: the
// blocks and their /geometry rows copied unchanged, in source order; every other block left out.
//
// The rule, on the blocks' vertices (/geometry). depth(x) is the region's signed depth: the
// distance from x to the region's boundary inside it, negative outside. A vertex is in if
// depth > tol, out if depth < -tol, on the boundary otherwise (tol: the file's length tolerance,
// [options] tolerance x length_scale). A unit is a block in no cluster, or a whole cluster (a DEM
// clump is never cut in pieces); its vertices are those of all its blocks.
//   - A block with no vertex in that the region still reaches into (some point of the block
//     deeper than tol: a cylinder through a large block, a sphere bulging through a face;
//     RegionDepth::reaches_into) counts as having a vertex in: it is cut.
//   - A unit with no vertex in is left out.
//   - A unit with a vertex in and one out is cut by the boundary: kept whole, its blocks fixed.
//   - A unit with every vertex in or on is inside: kept; its blocks fixed if its shallowest
//     vertex lies within `ring` of the boundary (depth <= ring + tol). For a convex region the
//     block's point nearest the boundary is a vertex, so this is "the block comes within ring of
//     the boundary". ring = 0 fixes the cut units and those that touch the boundary.
// Removed blocks (kRemoved, an excavation) are selected by the same rule and stay removed (never
// marked fixed); a region whose kept units are all removed selects nothing and is refused.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/h5io.hpp"

namespace slice {

enum class RegionShape { box, sphere, cylinder, near_zone };

/// A region of space. Lengths in the scene unit, global frame.
struct ExtractRegion {
  RegionShape shape = RegionShape::box;
  Vec3 a = Vec3::Zero();  // box: min corner; sphere: centre; cylinder: one end of the axis
  Vec3 b = Vec3::Zero();  // box: max corner; cylinder: the other end (flat caps at a and b)
  double radius = 0;      // sphere, cylinder: radius; near_zone: the distance from the zones
  /// near_zone: the zones, by index: /zones regions first (0 .. R-1, as slice-info counts them),
  /// then /zones meshes (R .. R+M-1). Empty: every zone.
  std::vector<std::size_t> zones;
  /// Throws Error (naming `where`, e.g. "--sphere") unless the numbers make a region: finite,
  /// min < max on every axis, radius > 0, two distinct axis ends.
  void validate(const std::string& where) const;
};

/// The region in words, for the summary and the docs: "cylinder from (15, -1, 15) to (15, 21,
/// 15), radius 15".
std::string describe(const ExtractRegion& r);

/// The signed depth of points in a region (see the top of this file). near_zone: distance -
/// dist(x, zones), where dist is 0 inside a zone (exact for convex zones: the distance to the
/// nearest face triangle; a mesh zone: to its nearest triangle, 0 inside it).
class RegionDepth {
 public:
  /// Throws Error if a near_zone region names a zone `js` does not have, or `js` has none.
  RegionDepth(const ExtractRegion& region, const JointSystem& js);
  ~RegionDepth();
  RegionDepth(RegionDepth&&) noexcept;
  RegionDepth& operator=(RegionDepth&&) noexcept;
  double operator()(const Vec3& x) const;
  /// Whether some point of the convex hull of `vertices` (a block) lies deeper than tol in the
  /// region, though maybe none of the vertices does: exact but for the rounding of the inputs
  /// (CGAL's Polytope_distance_d in exact arithmetic; a mesh zone triangle by triangle).
  bool reaches_into(std::span<const Vec3> vertices, double tol) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct ExtractOptions {
  ExtractRegion region;
  double ring = 0;  // thickness of the fixed outer ring (scene unit), >= 0
  void validate() const;
};

struct ExtractStats {
  std::size_t source_blocks = 0;
  std::size_t kept = 0;       // blocks written, removed ones included
  std::size_t removed = 0;    // of those, removed in the source (kept removed)
  std::size_t cut = 0;        // blocks of units the boundary cuts (fixed)
  std::size_t ring = 0;       // blocks of inside units within `ring` of the boundary (fixed)
  std::size_t was_fixed = 0;  // kept blocks already fixed in the source (boundary, fixed)
  std::size_t reached = 0;    // source blocks with no vertex in that the region reaches into
  std::size_t clusters = 0;   // clusters kept (whole)
  double volume = 0;          // of the kept blocks that are not removed
};

struct SubModel {
  BlockSystem blocks;                      // the kept blocks with their /geometry rows
  std::vector<std::int64_t> source_block;  // block k of `blocks` is source block source_block[k]
  ExtractStats stats;
};

/// The sub-model of `bs` (which must have /geometry) in opt.region. Throws Error (where: the
/// file name `source`) without /geometry, on a bad region or ring, or if the region keeps no
/// block that is not removed.
SubModel extract_blocks(const BlockSystem& bs, const ExtractOptions& opt,
                        const std::string& source);

}  // namespace slice

#pragma once
// 2-D sections in (x, z) (docs/2d.md) made in code, without the slicer: a domain polygon cut by
// lines with plain polygon clipping, so the geometry and export tests of 2-D mode have blocks
// whose polygons are known beforehand.
#include <cstdint>
#include <vector>

#include "slice/h5io.hpp"

namespace test {

/// A section's block system and, per block, the polygon it was cut as: vertices (global, y = 0)
/// counter-clockwise in (x, z), polygon[b][k] the start of edge k, whose face is
/// bs.blocks[b].faces[k] (one face per edge, none redundant).
struct Section {
  slice::BlockSystem bs;
  std::vector<std::vector<slice::Vec3>> polygons;
};

/// A joint of a section: the line through `point` (y = 0) with normal (cos a, 0, sin a), made
/// upward; dip and dip direction (90 or 270) to match. Persistent.
slice::Joint section_joint(double angle_deg, const slice::Vec3& point);

/// A segment joint: `j`'s line between `a` and `b` (points of the line, y = 0), stored as
/// docs/2d.md says: the rectangle of its plane spanning y in [-0.5, 0.5].
slice::Joint segment_joint(slice::Joint j, const slice::Vec3& a, const slice::Vec3& b);

/// A section's joint system: the box [lo, hi] in (x, z) as 4 domain planes (-x +x -z +z), the
/// given joints, dimension 2, tolerance 1e-9 of the box's half diagonal.
slice::JointSystem section_system(const slice::Vec3& lo, const slice::Vec3& hi,
                                  const std::vector<slice::Joint>& joints);

/// The domain of js cut by each of its joints' lines in turn (persistent: whole lines). A cut
/// that would leave an edge shorter than `min_edge` or a vertex closer than `min_edge` to the
/// line is not made in that block (the tiling stays exact, the polygons well shaped). Each
/// block's origin is the mean of its vertices; bs.pruned is true, no geometry.
Section cut_section(const slice::JointSystem& js, double min_edge);

/// Uniform in [0, 1) by SplitMix64 on `state` (plain integer arithmetic: the same numbers on
/// every standard library, which std's distributions are not).
double uniform(std::uint64_t& state);

/// Twice the signed area of the polygon in (x, z): positive if counter-clockwise with x to the
/// right and z up.
double twice_area_xz(const std::vector<slice::Vec3>& polygon);

}  // namespace test

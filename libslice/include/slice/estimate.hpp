#pragma once
// How many blocks a joint system will make, bounded before any cutting (issue 12): a scene that
// would need 1e10 blocks is refused in a second with the figure, not after 100 s and 5 GB.
#include <cstdint>

#include "slice/scene.hpp"

namespace slice {

/// The cells of the arrangement of the persistent joints inside the domain: 1 + P + L + V, with
/// P the planes that meet the domain's interior, L the lines of two planes and V the points of
/// three that do (exact for planes in general position, an upper bound otherwise; reference:
/// Table 3 at 1.0 m, P = 385, L = 37,238, V = 926,532, 964,156 blocks). Polygon joints are not
/// counted (they add fewer blocks than planes; slice-cut's running count catches them).
struct BlockEstimate {
  std::int64_t planes = 0;  // P
  double lines = 0;         // L
  double points = 0;        // V
  bool sampled = false;     // L and V extrapolated from a fixed sample of the plane pairs
  double blocks() const { return 1 + double(planes) + lines + points; }
};

/// O(pairs x groups) with pairs of non-parallel planes and groups of parallel ones; past a
/// budget of about 1e8 steps a fixed, evenly strided sample of the pairs stands for all of them.
BlockEstimate estimate_blocks(const JointSystem& js);

}  // namespace slice

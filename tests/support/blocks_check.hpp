#pragma once
// Independent checks of a slicing result (docs/design.md, "Invariants"), shared by the tests.
#include <cstdint>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/lp.hpp"

namespace test {

/// A block's faces as global half-spaces.
std::vector<slice::Plane> global_planes(const slice::Block& b);
/// Volume of a block by vertex enumeration (slice::analyse_polytope), independent of the LPs.
double block_volume(const slice::Block& b, double tol);
/// Volume of the domain of a joint system.
double domain_volume(const slice::JointSystem& js);

struct InvariantReport {
  std::size_t points = 0, points_near_face = 0, points_outside = 0, points_in_two = 0;
  std::size_t overlapping_pairs = 0, pairs_checked = 0;
  double volume_sum = 0, domain_volume = 0;
  double worst_hit_error_sigma = 0;  // |hits - expected| / sqrt(expected), worst block
};

/// Checks, with Catch2 assertions: (a) `points` random points of the domain each lie in exactly
/// one block, except within tol of a face, and each block's hit fraction agrees with its volume
/// (within 6 sigma); (b) no two blocks overlap: for every pair whose spheres overlap, the
/// largest ball inside both (an LP) has radius <= tol; (c) every block has inradius > 0;
/// (d) block volumes add up to the domain volume within 1e-9 relative.
InvariantReport check_invariants(const slice::BlockSystem& bs, std::size_t points,
                                 std::uint64_t seed);

}  // namespace test

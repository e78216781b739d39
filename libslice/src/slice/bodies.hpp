#pragma once
// What moves as one body in a DEM run (docs/design.md, "Clusters and slivers"): blocks joined
// across construction joints (clusters), and what becomes of slivers, the free blocks under the
// size or shape limits that cuts exempt from the limits leave behind. Internal to slice/: called
// by cut_blocks once the blocks have their centres, inradii and removal flags.
#include <cstddef>
#include <vector>

#include "slice/decide.hpp"
#include "slice/scene.hpp"

namespace slice {

struct BodyStats {
  std::size_t clusters = 0;
  std::size_t contact_lps = 0;      // contact tests on shared joint planes (cut-test LPs)
  std::size_t reach_lps = 0;        // depth of a sliver behind an excavated face (one LP each)
  std::size_t slivers_removed = 0;  // free slivers excavated with the removed block they touch
  std::size_t slivers_joined = 0;   // free slivers clustered with a kept neighbour
  std::size_t slivers_left = 0;     // free slivers with no neighbour to go with (expected: 0)
  std::size_t failed = 0;           // LPs that failed (solved again exactly first)
};

/// A free block (kept, in no cluster) is a sliver if it breaks the size or shape limits of the
/// scene by more than the geometry tolerance (so a block a split kept at the limit is none).
bool is_sliver(const Block& b, const SliceOptions& o, const Tolerances& tol);

/// Sets Block::cluster for every block (0, 1, ... in order of each cluster's first block; -1 for
/// a block on its own) and resolves slivers, in this order:
///   1. clusters: kept blocks touching across a construction joint with positive area;
///   2. with [options] slivers = "excavate" only: a free sliver that touches a removed block
///      with positive area, and reaches no deeper than the minimum inscribed diameter behind
///      that contact, is removed with it (an excavated surface moves by less than that size);
///   3. any other free sliver joins the kept neighbour it touches over the largest contact
///      (preferring a neighbour that is no sliver, then one as fixed as itself) as a cluster.
/// Blocks removed by a zone are the ones step 2 looks at, so the result does not depend on the
/// order of the slivers. Deterministic: the same blocks give the same ids and flags.
BodyStats form_bodies(std::vector<Block>& blocks, const JointSystem& js, Referee& referee,
                      const Tolerances& tol);

}  // namespace slice

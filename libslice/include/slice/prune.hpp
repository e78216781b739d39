#pragma once
// Pruning (Boon et al. 2015, eq. 8; docs/design.md, "The linear programs"): each block keeps only
// the faces that touch it. slice-prune, and slice-cut --prune.
#include <cstddef>

#include "slice/decide.hpp"
#include "slice/h5io.hpp"
#include "slice/lp.hpp"
#include "slice/progress.hpp"

namespace slice {

struct PruneStats {
  std::size_t faces_before = 0, faces_after = 0;
  std::size_t lps = 0, failed = 0;
  std::size_t certified = 0;  // faces kept without an LP (a point of the face is inside the rest)
  DecisionCounts decisions;
  double seconds = 0;
};

/// Drops every face of every block that no longer touches it (eq. 8), one LP per face against
/// the faces kept so far (a face a cheap test shows to touch the block needs none); sets bs.pruned.
/// Every block must be a solid (bounded, with an interior): Error names the first that is not.
/// `certify`: as CutOptions::certify, for the redundancy decisions. `threads`: as
/// CutOptions::threads; the result, its figures and the first error reported are the same for every
/// count. `check_solids`: false skips the solid check (seven LPs a block) for blocks cut_blocks has
/// just made, which are solids by construction.
PruneStats prune_blocks(BlockSystem& bs, LpBackend backend, const Progress& progress = {},
                        bool certify = false, int threads = 0, bool check_solids = true);

}  // namespace slice

#pragma once
// Sequential subdivision (Boon et al. 2015, sections 2.1-2.7; docs/design.md, "The linear
// programs"): joints.h5 in, blocks out. A block is only its half-spaces; every decision is one
// small LP (lp.hpp).
#include <cstddef>
#include <cstdint>

#include "slice/decide.hpp"
#include "slice/h5io.hpp"
#include "slice/lp.hpp"
#include "slice/progress.hpp"
#include "slice/prune.hpp"

namespace slice {

struct CutOptions {
  LpBackend backend = LpBackend::native;
  /// Bounding spheres and a loose grid over them decide which blocks a joint may reach
  /// (eq. 17, Fig. 18). false runs the cut LP on every block for every joint: slower, same
  /// blocks; for tests and the scaling benchmark.
  bool use_index = true;
  /// With the index: a pair geometry settles (the plane misses the block's box, the polygon's
  /// box misses it, the polygon clipped by its faces is empty; cut_reject.hpp) needs no cut
  /// LP. false gives every pair the index passes to the LP: slower, same blocks; for tests and
  /// benchmarks.
  bool use_shortcuts = true;
  /// The most blocks the cut may make; 0: the joint system's options.max_blocks. Checked up front
  /// against estimate_blocks (persistent joints) and after every joint (all joints).
  std::int64_t max_blocks = 0;
  /// Decide again exactly every cut, limit and contact decision within the tolerance of its
  /// threshold (decide.hpp); without it, only those within a few hundred rounding errors.
  bool certify = false;
  /// Threads (oneTBB); 0: all cores. The ipopt backend runs on one (its linear solver keeps
  /// global state). Results and figures are the same for every count.
  int threads = 0;
  /// The cut runs on one thread until there are this many blocks, then cuts each of them as an
  /// independent task; 0: one thread throughout. Blocks are the same for every value; the LP
  /// counts are not (a task is only given the joints that reach its first block's sphere).
  std::size_t tasks = 512;
};

/// LPs solved, by kind.
struct LpCounts {
  std::size_t cut_test = 0;    // eq. 7 / 16
  std::size_t extents = 0;     // eq. 17, six LPs each
  std::size_t chebyshev = 0;   // eq. 18
  std::size_t redundancy = 0;  // eq. 8
  std::size_t contact = 0;     // construction-face contacts (a cut-test LP on the shared plane)
  std::size_t failed = 0;      // LPs neither the backend nor the exact one solved (expected: 0)
  // Extremes (eq. 17) found at a vertex proven optimal, without an LP (vertex_extremes); not
  // in total().
  std::size_t vertex_extremes = 0;
  std::size_t total() const { return cut_test + extents + chebyshev + redundancy + contact; }
};

struct CutStats {
  std::size_t joints = 0;
  std::size_t joints_missing = 0;  // joints that cut no block (e.g. outside the domain)
  std::size_t blocks = 0;
  std::size_t splits = 0;
  std::size_t splits_undone = 0;  // a child broke the size or shape limit: parent kept
  std::size_t pairs_skipped = 0;  // joint-block pairs the spheres and the grid ruled out
  // Pairs past them that geometry settled without the cut LP (CutOptions::use_shortcuts), by the
  // test that did: the plane against the block's box, the polygon's box against it, the
  // polygon clipped by the block's faces.
  std::size_t rejected_plane = 0, rejected_box = 0, rejected_faces = 0;
  // Pairs past those whose split the size limit would undo whether or not the plane cuts (a
  // piece between it and a parallel face of the block thinner than min_inscribed_diameter),
  // settled without the cut LP (use_shortcuts; native backend; not a boundary joint). Not in
  // splits_undone, which counts the splits made and then undone.
  std::size_t settled_by_limit = 0;
  // Pairs past those that geometry proves cut (surely_cuts: a point of the polygon deep inside
  // the block), split without the cut LP (use_shortcuts).
  std::size_t cut_without_lp = 0;
  std::size_t boundary = 0, removed = 0, clusters = 0;
  std::size_t fixed = 0;  // blocks on a face named in [options] fixed_faces
  // Slivers: free blocks (kept, in no cluster) under the size or shape limits, left by cuts
  // exempt from them (limits = false: construction joints, tunnel and mesh outlines).
  std::size_t slivers_removed = 0;  // removed with the excavated block they touch (in `removed`)
  std::size_t slivers_joined = 0;   // clustered with the neighbour they touch most
  std::size_t slivers_left = 0;     // with no neighbour to go with (expected: 0)
  LpCounts lps;
  DecisionCounts decisions;   // LPs solved again and decisions re-decided exactly
  double seconds_cut = 0;     // the sequential subdivision
  double seconds_finish = 0;  // Chebyshev centres, zones, clusters
};

struct CutResult {
  BlockSystem blocks;
  CutStats stats;
};

/// Cuts the domain of `js` by its joints in file order. The blocks come out with their origin
/// at their Chebyshev centre, inradius and bounding sphere set, flags (boundary, removed) and
/// cluster ids (construction joints) computed, and no free sliver: a kept block in no cluster
/// under the size or shape limits is removed with the excavated block it touches or joins a
/// neighbour's cluster (see CutStats). Not pruned: see prune_blocks.
CutResult cut_blocks(const JointSystem& js, const CutOptions& opt, const Progress& progress = {});

}  // namespace slice

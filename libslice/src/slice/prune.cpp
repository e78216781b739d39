#include "slice/prune.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/combinable.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <chrono>
#include <exception>
#include <mutex>
#include <string>

#include "../prefetch.hpp"
#include "referees.hpp"
#include "slice/cut_reject.hpp"
#include "slice/error.hpp"

namespace slice {
namespace {

/// A file's block must be a solid: bounded (six extents LPs) with an interior (a Chebyshev
/// radius of at least a quarter of the geometry tolerance). A crafted or damaged blocks.h5 fails
/// here, before a wrong pruning is written.
void check_solid(LpSolver& solver, std::span<const Face> faces, const Tolerances& tol,
                 std::size_t index) {
  const std::string where = "/blocks block " + std::to_string(index);
  const char* fix =
      "the file is damaged or was not made by slice-cut; regenerate it with slice-cut";
  const Extents e = extents(solver, faces, tol);
  if (e.status != LpStatus::optimal)
    throw Error(where, "its faces do not bound a solid (extents LP " + to_string(e.status) + ")",
                fix);
  // The slicer makes no child thinner than the cut tolerance (inscribed diameter >= tol.cut,
  // radius >= tol / 2); a quarter of the tolerance leaves room for rounding.
  const double min_radius = 0.25 * tol.geometry;
  const ChebyshevBall c = chebyshev_ball(solver, faces, tol);
  if (c.status != LpStatus::optimal || c.radius < min_radius)
    throw Error(
        where,
        "its faces do not bound a solid (" +
            (c.status == LpStatus::optimal ? "inscribed radius " + std::to_string(c.radius) +
                                                 " below " + std::to_string(min_radius)
                                           : "Chebyshev LP " + to_string(c.status)) +
            ")",
        fix);
}

}  // namespace

PruneStats prune_blocks(BlockSystem& bs, LpBackend backend, const Progress& progress, bool certify,
                        int threads, bool check_solids) {
  const auto t0 = Clock::now();
  PruneStats st;
  const Tolerances tol = Tolerances::from_scale(bs.joints.length_scale, bs.joints.options.tolerance,
                                                bs.joints.dimension);
  Referees referees(backend, tol, certify);
  tbb::task_arena arena(threads_for(backend, threads));
  // Blocks are independent. The first error in block order is the one reported, whatever the
  // thread that met it (the others are dropped).
  std::mutex mutex;
  std::size_t failed_at = bs.blocks.size();
  std::exception_ptr failure;
  std::atomic<std::size_t> done{0};
  tbb::combinable<PruneStats> partial;
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, bs.blocks.size(), 64),
        [&](const tbb::blocked_range<std::size_t>& range) {
          Referee& referee = referees.local();
          PruneStats& mine = partial.local();
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            try {
              prefetch_faces_ahead(bs.blocks, i);
              auto& faces = bs.blocks[i].faces;
              mine.faces_before += faces.size();
              // Against the faces kept so far: of two identical faces, one stays.
              for (std::size_t f = 0; f < faces.size();) {
                if (surely_irredundant(faces, f, tol)) {
                  ++mine.certified;
                  ++f;
                  continue;
                }
                const FaceRedundancy r = referee.redundancy(faces, f);
                ++mine.lps;
                if (r.redundant)
                  faces.erase(faces.begin() + std::ptrdiff_t(f));
                else
                  ++f;  // also when unbounded (the other faces leave the block open there)
              }
              mine.faces_after += faces.size();
              if (check_solids) check_solid(referee.solver(), faces, tol, i);
            } catch (...) {
              const std::lock_guard lock(mutex);
              if (i < failed_at) {
                failed_at = i;
                failure = std::current_exception();
              }
              return;
            }
          }
          const std::size_t n = done += range.size();
          if (progress) {
            const std::lock_guard lock(mutex);
            progress("prune", n, bs.blocks.size());
          }
        });
  });
  if (failure) std::rethrow_exception(failure);
  partial.combine_each([&](const PruneStats& p) {
    st.faces_before += p.faces_before;
    st.faces_after += p.faces_after;
    st.lps += p.lps;
    st.certified += p.certified;
  });
  bs.pruned = true;
  bs.geometry.reset();  // faces changed: vertices and loops no longer match
  bs.stability.reset();
  st.decisions = referees.counts();
  st.failed = st.decisions.failed;
  st.seconds = seconds_since(t0);
  return st;
}

}  // namespace slice

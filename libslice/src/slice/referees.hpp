#pragma once
// What the cut (cut.cpp) and the prune (prune.cpp) share: a referee per thread, how many
// threads a backend runs on, and their stopwatch.
#include <oneapi/tbb/enumerable_thread_specific.h>

#include <chrono>
#include <memory>

#include "../threads.hpp"
#include "slice/decide.hpp"

namespace slice {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// One Referee (LP backend plus exact fallback) per thread, made on first use.
class Referees {
 public:
  Referees(LpBackend backend, const Tolerances& tol, bool certify)
      : backend_(backend), tol_(tol), certify_(certify) {}
  Referee& local() {
    auto& r = all_.local();
    if (!r) r = std::make_unique<Referee>(backend_, tol_, certify_);
    return *r;
  }
  DecisionCounts counts() const {
    DecisionCounts c;
    for (const auto& r : all_)
      if (r) c += r->counts();
    return c;
  }

 private:
  LpBackend backend_;
  Tolerances tol_;
  bool certify_;
  tbb::enumerable_thread_specific<std::unique_ptr<Referee>> all_;
};

/// The threads to run on: CutOptions::threads up to the cores, but one for Ipopt, whose linear
/// solver (MUMPS, sequential build) keeps global state.
inline int threads_for(LpBackend backend, int threads) {
  return backend == LpBackend::ipopt ? 1 : thread_count(threads);
}

}  // namespace slice

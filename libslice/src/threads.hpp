#pragma once
// How many threads a stage runs on (oneTBB arenas): the count asked for, at most the cores
// (more would only wait, and oneTBB warns that it limits them); 0 for all cores. And the end of
// a task group whose work is no longer wanted.
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>

namespace slice {

inline int thread_count(int requested) {
  const int cores = tbb::info::default_concurrency();
  return requested > 0 ? std::min(requested, cores) : cores;
}

/// Cancels the tasks of `g` and waits for them, dropping their errors: another error, the one
/// to report, is on its way (or the buffers the tasks use are about to go).
void abandon(tbb::task_group& g);

}  // namespace slice

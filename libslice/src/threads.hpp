#pragma once
// How many threads a stage runs on (oneTBB arenas): the count asked for, at most the cores
// (more would only wait, and oneTBB warns that it limits them); 0 for all cores.
#include <oneapi/tbb/info.h>

#include <algorithm>

namespace slice {

inline int thread_count(int requested) {
  const int cores = tbb::info::default_concurrency();
  return requested > 0 ? std::min(requested, cores) : cores;
}

}  // namespace slice

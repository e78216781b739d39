#include "slice/threads.hpp"

#include <oneapi/tbb/task_arena.h>

#include "threads.hpp"

namespace slice {

void with_threads(int threads, const std::function<void()>& body) {
  tbb::task_arena arena(thread_count(threads));
  arena.execute(body);
}

void abandon(tbb::task_group& g) {
  g.cancel();
  try {
    g.wait();
  } catch (...) {
  }
}

}  // namespace slice

#pragma once
// The threads a run may use. Every stage that runs concurrently (the cut, the vertices, the VTU
// writer) takes its thread count; the checks of the readers and writers take the threads of the
// caller's: `with_threads` runs a whole tool (or any caller's work) on at most `threads` threads.
#include <functional>

namespace slice {

/// Runs `body` on at most `threads` threads (0: all cores): the parallel checks of
/// read_joints / read_blocks / write_blocks inside it use no more. Exceptions pass through.
void with_threads(int threads, const std::function<void()>& body);

}  // namespace slice

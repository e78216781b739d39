#pragma once
// Loads ahead of a loop that chases pointers: a block's faces are a heap array of their own, and
// after the cut's parallel moves the blocks' arrays lie in no order the hardware can guess, so a
// pass over a million blocks waits on memory at every block unless it asks a few blocks ahead.
#include <cstddef>
#include <vector>

#include "slice/geometry.hpp"

namespace slice {

/// __builtin_prefetch, kept: GCC 12 (-O2) deletes a loop whose only effects are prefetches.
inline void prefetch(const void* p) {
  __builtin_prefetch(p);
  asm volatile("");
}

/// How many blocks ahead a pass over blocks loads the next block's faces.
inline constexpr std::size_t kPrefetchBlocks = 4;

/// Starts loading the faces of blocks[i + kPrefetchBlocks], if there is one (its first two cache
/// lines: most blocks have six to eight faces of 40 bytes).
inline void prefetch_faces_ahead(const std::vector<Block>& blocks, std::size_t i) {
  if (i + kPrefetchBlocks >= blocks.size()) return;
  const std::vector<Face>& faces = blocks[i + kPrefetchBlocks].faces;
  if (faces.empty()) return;
  const auto* p = reinterpret_cast<const char*>(faces.data());
  prefetch(p);
  prefetch(p + 64);
  prefetch(p + 128);
  prefetch(p + 192);
}

}  // namespace slice

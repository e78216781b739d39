#pragma once
// The kernel of vertex_extremes and vertex_extremes_split (slice/lp.hpp): the extremes of a block
// found where three of its faces meet, for V variants of one block at once. Private to the
// library; the property test (tests/property/vertex_extremes_property_test.cpp) checks the AVX2
// kernel against the portable one, bit for bit.
#include <array>
#include <cstddef>
#include <span>

#include "slice/lp.hpp"

namespace slice::detail {

/// Variant 0 is `faces`, variant 1 (V = 2) the same faces with the last one reversed (the other
/// piece of a split). Each variant's answer is the one the variant alone gives: per direction,
/// the first triple of faces (i < j < k) whose vertex proves it and lies inside. `vector`: the
/// AVX2 kernel where the processor has it (the same bits), else the portable one.
template <std::size_t V>
std::array<VertexExtremes, V> vertex_extremes_of(std::span<const Face> faces,
                                                 std::array<unsigned, V> wanted,
                                                 bool vector = true);

extern template std::array<VertexExtremes, 1> vertex_extremes_of<1>(std::span<const Face>,
                                                                    std::array<unsigned, 1>, bool);
extern template std::array<VertexExtremes, 2> vertex_extremes_of<2>(std::span<const Face>,
                                                                    std::array<unsigned, 2>, bool);

}  // namespace slice::detail

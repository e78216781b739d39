#pragma once
// UTF-8 text: the scene parser keeps toml++ from code points it cannot take, the YADE script
// writes names that are no UTF-8 as escapes.
#include <cstddef>
#include <string_view>
#include <utility>

namespace slice {

/// The UTF-8 sequence at text[i] (i < text.size()): its code point and length, or length 0 if
/// it is malformed (cut short, overlong, a surrogate, past U+10FFFF: what Python and toml++
/// refuse too).
std::pair<char32_t, std::size_t> decode_utf8(std::string_view text, std::size_t i);

}  // namespace slice

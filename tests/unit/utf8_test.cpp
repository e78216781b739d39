// decode_utf8 (utf8.hpp): what Python and toml++ take as UTF-8, and nothing else.
#include "slice/utf8.hpp"

#include <catch2/catch.hpp>
#include <string>
#include <utility>

namespace {
std::pair<char32_t, std::size_t> at0(const std::string& s) { return slice::decode_utf8(s, 0); }
}  // namespace

TEST_CASE("decode_utf8 reads the shortest forms of U+0000..U+10FFFF", "[unit][utf8]") {
  CHECK(at0("a") == std::pair<char32_t, std::size_t>{U'a', 1});
  CHECK(at0(std::string(1, '\0')) == std::pair<char32_t, std::size_t>{0, 1});
  CHECK(at0("\xc3\xa9") == std::pair<char32_t, std::size_t>{0xE9, 2});        // é
  CHECK(at0("\xe2\x80\xa8") == std::pair<char32_t, std::size_t>{0x2028, 3});  // LS
  CHECK(at0("\xef\xbf\xbf") == std::pair<char32_t, std::size_t>{0xFFFF, 3});
  CHECK(at0("\xf0\x9f\x98\x80") == std::pair<char32_t, std::size_t>{0x1F600, 4});
  CHECK(at0("\xf4\x8f\xbf\xbf") == std::pair<char32_t, std::size_t>{0x10FFFF, 4});
  CHECK(slice::decode_utf8("x\xc3\xa9", 1).second == 2);
}

TEST_CASE("decode_utf8 refuses what is no UTF-8: length 0", "[unit][utf8]") {
  for (const std::string bad : {
           "\x80",              // a continuation byte alone
           "\xff", "\xfe",      // never in UTF-8
           "\xc3",              // cut short
           "\xe2\x80",          // cut short
           "\xc3(",             // no continuation byte
           "\xc0\x80",          // overlong NUL
           "\xc1\xbf",          // overlong U+007F
           "\xe0\x80\xaf",      // overlong "/"
           "\xf0\x80\x80\xaf",  // overlong "/"
           "\xed\xa0\x80",      // U+D800, a surrogate
           "\xed\xbf\xbf",      // U+DFFF
           "\xf4\x90\x80\x80",  // U+110000
           "\xf5\x80\x80\x80",  // past U+10FFFF by its first byte
       }) {
    CAPTURE(bad);
    CHECK(at0(bad).second == 0);
  }
}

// fuzz_export's oracle (export_check.hpp). Lines and words are views into the output read back:
// nothing is copied but what a finding's message quotes.
#include "export_check.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

#include "fuzz_input.hpp"
#include "slice/error.hpp"

namespace fuzz {
namespace {

constexpr const char* kTarget = "fuzz_export";

[[noreturn]] void bad(const std::string& file, std::size_t line, std::string_view text,
                      const std::string& what) {
  finding(kTarget, file + " line " + std::to_string(line) + " \"" +
                       slice::escape_control(std::string(text.substr(0, 200))) + "\": " + what);
}

std::vector<std::string_view> lines_of(std::string_view text, const std::string& file) {
  if (text.empty() || text.back() != '\n') finding(kTarget, file + " does not end a line");
  std::vector<std::string_view> lines;
  std::size_t from = 0;
  for (std::size_t to; (to = text.find('\n', from)) != std::string_view::npos; from = to + 1)
    lines.push_back(text.substr(from, to - from));
  for (std::size_t i = 0; i < lines.size(); ++i)
    for (const char c : lines[i])
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
        bad(file, i + 1, lines[i], "a control character");
  return lines;
}

// The words of `s` (split at spaces) into `w`, which is reused from line to line.
void words(std::string_view s, std::vector<std::string_view>& w) {
  w.clear();
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t j = std::min(s.find(' ', i), s.size());
    if (j > i) w.push_back(s.substr(i, j - i));
    i = j + 1;
  }
}

bool finite_number(std::string_view s) {
  double v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(v);
}

// A positive integer ID, or 0.
std::size_t id_of(std::string_view s) {
  std::size_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() ? v : 0;
}

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

// Whether `s` is UTF-8 (what Python reads a source file as).
bool utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = c < 0x80         ? 1
                          : (c >> 5) == 6  ? 2
                          : (c >> 4) == 14 ? 3
                          : (c >> 3) == 30 ? 4
                                           : 0;
    if (n == 0 || i + n > s.size()) return false;
    for (std::size_t k = 1; k < n; ++k)
      if ((static_cast<unsigned char>(s[i + k]) >> 6) != 2) return false;
    i += n;
  }
  return true;
}

}  // namespace

void check_grid(const std::string& text, const slice::ThreeDecStats& st) {
  const std::string file = "3DEC grid";
  const auto lines = lines_of(text, file);
  std::size_t g = 0, f = 0, b = 0, js = 0, last_b = 0;
  std::vector<std::string_view> w;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view l = lines[i];
    if (starts_with(l, "* ")) continue;
    words(l, w);
    const auto fail = [&](const std::string& what) { bad(file, i + 1, l, what); };
    if (w.empty()) fail("an empty line");
    if (w[0] == "TOL") {
      if (w.size() != 2 || !finite_number(w[1])) fail("not TOL <number>");
    } else if (w[0] == "G") {
      if (w.size() != 5 || id_of(w[1]) != ++g) fail("not G <next id> x y z");
      for (std::size_t k = 2; k < 5; ++k)
        if (!finite_number(w[k])) fail("a coordinate that is no finite number");
    } else if (w[0] == "F") {
      if (w.size() < 5 || id_of(w[1]) != ++f) fail("not F <next id> and 3 or more gridpoints");
      for (std::size_t k = 2; k < w.size(); ++k)
        if (id_of(w[k]) == 0 || id_of(w[k]) > g) fail("a gridpoint not written above");
    } else if (w[0] == "B") {
      const std::size_t id = id_of(w[1]);
      if (w.size() < 7 || id <= last_b || w[2] != "1" || w[3] != "F")
        fail("not B <increasing id> 1 F and 3 or more faces");
      last_b = id;
      ++b;
      for (std::size_t k = 4; k < w.size(); ++k)
        if (id_of(w[k]) == 0 || id_of(w[k]) > f) fail("a face not written above");
    } else if (w[0] == "JS") {
      if (w.size() < 3 || id_of(w[1]) == 0) fail("not JS <id> and contacts");
      for (std::size_t k = 2; k < w.size(); ++k) {
        const auto dash = w[k].find('-');
        const std::size_t x = id_of(w[k].substr(0, dash)), y = id_of(w[k].substr(dash + 1));
        if (dash == std::string_view::npos || x == 0 || x >= y || y > last_b)
          fail("a contact that is not <block>-<later block>");
        ++js;
      }
    } else {
      fail("no grid record");
    }
  }
  if (g != st.gridpoints || f != st.faces || b != st.blocks || js != st.contacts)
    finding(kTarget, "the 3DEC grid's counts (G " + std::to_string(g) + ", F " + std::to_string(f) +
                         ", B " + std::to_string(b) + ", JS pairs " + std::to_string(js) +
                         ") differ from the stats");
}

void check_commands(const std::string& text) {
  const std::string file = "3DEC commands";
  static constexpr std::string_view kCommands[] = {
      "model new",    "block import filename \"", "block property density ", "model gravity ",
      "block group ", "block join range group ",  "block fix range ",        "block contact ",
  };
  const auto lines = lines_of(text, file);
  std::vector<std::string_view> w;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view l = lines[i];
    if (starts_with(l, ";")) continue;
    if (std::none_of(std::begin(kCommands), std::end(kCommands),
                     [&](std::string_view c) { return starts_with(l, c); }))
      bad(file, i + 1, l, "no command the writer writes");
    if (starts_with(l, "block import")) continue;  // the quoted file name may hold anything
    words(l, w);
    for (const auto x : w)
      if (x == "nan" || x == "-nan" || x == "inf" || x == "-inf")
        bad(file, i + 1, l, "a " + std::string(x));
  }
}

// Python's tokens, cheaply: comments, strings (with escapes, single- and triple-quoted) and
// brackets must close; a name outside them is never nan or inf (NameError in Python).
void check_python(const std::string& text_, std::size_t bodies, const std::string& file) {
  const std::string_view text = text_;
  if (!utf8(text)) finding(kTarget, file + " is no UTF-8");
  const auto lines = lines_of(text, file);
  std::string open;  // brackets not yet closed
  std::size_t line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const auto fail = [&](const std::string& what) { bad(file, line, lines[line - 1], what); };
    if (c == '\n') {
      ++line;
    } else if (c == '#') {
      i = text.find('\n', i) - 1;
    } else if (c == '\'' || c == '"') {
      const char quotes[3] = {c, c, c};
      const bool triple = text.substr(i, 3) == std::string_view(quotes, 3);
      const std::string_view end(quotes, triple ? 3 : 1);
      std::size_t k = i + end.size();
      for (; k < text.size() && text.substr(k, end.size()) != end; ++k) {
        if (text[k] == '\\') ++k;
        if (k < text.size() && text[k] == '\n') {
          if (!triple) fail("a string not closed on its line");
          ++line;
        }
      }
      if (k >= text.size()) fail("a string never closed");
      i = k + end.size() - 1;
    } else if (c == '(' || c == '[' || c == '{') {
      open += c;
    } else if (c == ')' || c == ']' || c == '}') {
      const char want = c == ')' ? '(' : c == ']' ? '[' : '{';
      if (open.empty() || open.back() != want) fail("a bracket closed that is not open");
      open.pop_back();
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      std::size_t k = i;
      while (k < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[k])) || text[k] == '_'))
        ++k;
      const std::string_view name = text.substr(i, k - i);
      const bool in_number = i > 0 && (std::isdigit(static_cast<unsigned char>(text[i - 1])) ||
                                       text[i - 1] == '.');  // 1e+300: "e" is no name
      if (!in_number && (name == "nan" || name == "inf")) fail("the name " + std::string(name));
      i = k - 1;
    }
  }
  if (!open.empty()) finding(kTarget, file + " leaves brackets open: " + open);
  const auto first = std::find(lines.begin(), lines.end(), "BLOCKS = [");
  const auto last = std::find(first, lines.end(), "]");
  if (first == lines.end() || last == lines.end()) finding(kTarget, file + " has no BLOCKS list");
  if (std::size_t(last - first - 1) != bodies)
    finding(kTarget, file + " has " + std::to_string(last - first - 1) + " BLOCKS rows for " +
                         std::to_string(bodies) + " bodies");
}

}  // namespace fuzz

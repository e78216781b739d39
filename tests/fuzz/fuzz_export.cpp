// libFuzzer target: the 3DEC and YADE writers fed from a (fuzzed) geom.h5. The input is written
// to a file that slice::read_blocks reads, as slice-export does; blocks with /geometry are then
// written as a 3DEC grid and command file (slice::write_3dec) and as YADE scripts of both
// shapes (slice::write_yade_script), each to a file in the temporary directory. slice::Error
// (bad input, exit 1 in the tools) is the expected answer; any other exception, a crash, a
// sanitizer report, a timeout or running out of memory is a finding. So is an output that is
// written but is not what 3DEC or YADE can read (checked cheaply, below):
//   3DEC grid: each line one record ("* comment", TOL, G, F, B, JS) with finite numbers and IDs
//     that count up and refer to records above them, the counts the stats report;
//   3DEC commands: each line a comment (";") or one of the commands the writer writes, without
//     "nan" or "inf" outside comments;
//   YADE script: UTF-8, no control character but newline (Python ends a line at "\r", and NUL
//     is no source), Python's strings, comments and brackets closed, no nan or inf names, and
//     one BLOCKS row per body.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_input.hpp"
#include "slice/error.hpp"
#include "slice/export_3dec.hpp"
#include "slice/export_yade.hpp"
#include "slice/h5io.hpp"

namespace {

constexpr const char* kTarget = "fuzz_export";

struct Outputs {
  std::filesystem::path grid, commands, yade, pb;
};

Outputs& outputs() {
  static Outputs o;
  return o;
}

void remove_outputs() {
  std::error_code ec;
  for (const auto& p : {outputs().grid, outputs().commands, outputs().yade, outputs().pb})
    std::filesystem::remove(p, ec);
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

[[noreturn]] void bad(const std::string& file, std::size_t line, const std::string& text,
                      const std::string& what) {
  fuzz::finding(kTarget, file + " line " + std::to_string(line) + " \"" +
                             slice::escape_control(text.substr(0, 200)) + "\": " + what);
}

std::vector<std::string> lines_of(const std::string& text, const std::string& file) {
  if (text.empty() || text.back() != '\n') fuzz::finding(kTarget, file + " does not end a line");
  std::vector<std::string> lines;
  std::size_t from = 0;
  for (std::size_t to; (to = text.find('\n', from)) != std::string::npos; from = to + 1)
    lines.push_back(text.substr(from, to - from));
  for (std::size_t i = 0; i < lines.size(); ++i)
    for (const char c : lines[i])
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
        bad(file, i + 1, lines[i], "a control character");
  return lines;
}

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> w;
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t j = std::min(s.find(' ', i), s.size());
    if (j > i) w.push_back(s.substr(i, j - i));
    i = j + 1;
  }
  return w;
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

void check_grid(const std::string& text, const slice::ThreeDecStats& st) {
  const std::string file = "3DEC grid";
  const auto lines = lines_of(text, file);
  std::size_t g = 0, f = 0, b = 0, js = 0, last_b = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    if (l.rfind("* ", 0) == 0) continue;
    const auto w = words(l);
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
    fuzz::finding(kTarget, "the 3DEC grid's counts (G " + std::to_string(g) + ", F " +
                               std::to_string(f) + ", B " + std::to_string(b) + ", JS pairs " +
                               std::to_string(js) + ") differ from the stats");
}

void check_commands(const std::string& text) {
  const std::string file = "3DEC commands";
  static const char* const kCommands[] = {
      "model new",    "block import filename \"", "block property density ", "model gravity ",
      "block group ", "block join range group ",  "block fix range ",        "block contact ",
  };
  const auto lines = lines_of(text, file);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    if (l.rfind(';', 0) == 0) continue;
    if (std::none_of(std::begin(kCommands), std::end(kCommands),
                     [&](const char* c) { return l.rfind(c, 0) == 0; }))
      bad(file, i + 1, l, "no command the writer writes");
    if (l.rfind("block import", 0) == 0) continue;  // the quoted file name may hold anything
    for (const auto w : words(l))
      if (w == "nan" || w == "-nan" || w == "inf" || w == "-inf")
        bad(file, i + 1, l, "a " + std::string(w));
  }
}

// Whether `s` is UTF-8 (what Python reads a source file as).
bool utf8(const std::string& s) {
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

// Python's tokens, cheaply: comments, strings (with escapes, single- and triple-quoted) and
// brackets must close; a name outside them is never nan or inf (NameError in Python).
void check_python(const std::string& text, std::size_t bodies, const std::string& file) {
  if (!utf8(text)) fuzz::finding(kTarget, file + " is no UTF-8");
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
      const bool triple = text.compare(i, 3, std::string(3, c)) == 0;
      const std::string end = triple ? std::string(3, c) : std::string(1, c);
      std::size_t k = i + end.size();
      for (; k < text.size() && text.compare(k, end.size(), end) != 0; ++k) {
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
      const std::string name = text.substr(i, k - i);
      const bool in_number = i > 0 && (std::isdigit(static_cast<unsigned char>(text[i - 1])) ||
                                       text[i - 1] == '.');  // 1e+300: "e" is no name
      if (!in_number && (name == "nan" || name == "inf")) fail("the name " + name);
      i = k - 1;
    }
  }
  if (!open.empty()) fuzz::finding(kTarget, file + " leaves brackets open: " + open);
  const auto first = std::find(lines.begin(), lines.end(), "BLOCKS = [");
  const auto last = std::find(first, lines.end(), "]");
  if (first == lines.end() || last == lines.end())
    fuzz::finding(kTarget, file + " has no BLOCKS list");
  if (std::size_t(last - first - 1) != bodies)
    fuzz::finding(kTarget, file + " has " + std::to_string(last - first - 1) + " BLOCKS rows for " +
                               std::to_string(bodies) + " bodies");
}

void export_all(const slice::BlockSystem& bs) {
  const Outputs& o = outputs();
  try {
    const slice::ThreeDecStats st = slice::write_3dec(o.grid, o.commands, bs);
    check_grid(read_file(o.grid), st);
    check_commands(read_file(o.commands));
  } catch (const slice::Error&) {
  }
  for (const auto shape : {slice::YadeShape::polyhedra, slice::YadeShape::potential_blocks}) {
    slice::YadeOptions opt;
    opt.shape = shape;
    opt.source = fuzz::input_path().string();
    const auto& out = shape == slice::YadeShape::polyhedra ? o.yade : o.pb;
    try {
      const slice::YadeStats st = slice::write_yade_script(out, bs, opt);
      if (st.bodies + st.removed != bs.blocks.size())
        fuzz::finding(kTarget, "YADE bodies + removed is not the block count");
      check_python(read_file(out), st.bodies, out.filename().string());
    } catch (const slice::Error&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  fuzz::set_input_name("geom.h5");
  outputs() = {fuzz::scratch_path("m.3dgrid"), fuzz::scratch_path("m.dat"),
               fuzz::scratch_path("m.py"), fuzz::scratch_path("m-pb.py")};
  std::atexit(remove_outputs);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = fuzz::write_input(data, size);
  slice::BlockSystem bs;
  try {
    bs = slice::read_blocks(path);
  } catch (const slice::Error&) {
    return 0;  // refused as any reader refuses it (fuzz_h5's business)
  }
  if (bs.geometry) export_all(bs);
  return 0;
}

#include "toml_read.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "slice/utf8.hpp"

namespace slice::scene_read {

std::string fmt(double x, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << x;
  return s.str();
}

// (Strings are built with += here: GCC 12 gives a false -Wrestrict for "literal" + std::string
// once inlined, GCC bug 105651.)
std::string fmt(const Vec3& v) {
  std::string s = "(";
  s += fmt(v.x());
  s += ", ";
  s += fmt(v.y());
  s += ", ";
  s += fmt(v.z());
  s += ")";
  return s;
}

std::string quote_key(std::string_view k) {
  std::string s = "'";
  s += k;
  s += "'";
  return s;
}

std::string join(Keys keys, std::string_view sep) {
  std::string s;
  for (const auto& k : keys) s += (s.empty() ? "" : std::string(sep)) + std::string(k);
  return s;
}

namespace {

// Optimal string alignment distance (Levenshtein plus adjacent transpositions): "spaceing" and
// "spacnig" are both one edit from "spacing".
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

}  // namespace

// The known name closest to `s`, if it is close enough to be a likely typo; "" otherwise. A name
// that `s` begins ("largest" for "largest-first") counts as closest.
std::string closest(std::string_view s, Keys known) {
  if (s.size() >= 3)
    for (const auto& k : known)
      if (k.substr(0, s.size()) == s) return std::string(k);
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& k : known) {
    const std::size_t dist = edit_distance(s, k);
    if (dist < best_d) best_d = dist, best = std::string(k);
  }
  const std::size_t limit = std::max<std::size_t>(2, s.size() / 3);
  return best_d <= limit ? best : std::string();
}

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a floating-point number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "nothing";
  }
}

namespace {

// toml++ 3.3.0 (Debian 12) asks whether a character is whitespace wherever whitespace may stand,
// and for U+00A1..U+0499, U+2C5E..U+3057 and U+FB26..U+FEFE that question reaches
// __builtin_unreachable(), undefined behaviour (is_non_ascii_horizontal_whitespace;
// marzer/tomlplusplus#190, fixed after 3.3.0; found by fuzzing). Those characters are legal in
// strings and comments, so toml++ never sees them: before parsing they move to private use code
// points U+F0000 higher up, which it handles, and every string read and every message moves them
// back.
constexpr char32_t kShelter = 0xF0000;

// The code points is_non_ascii_horizontal_whitespace() has no answer for: its bit mask leaves
// out blocks 0, 11 and 63 of 0x3FA code points from U+00A0, and its switch handles none of them
// but U+3000 (derived from its source, checked by the fuzzer).
bool toml_unsafe(char32_t c) {
  return (c >= 0xA1 && c <= 0x499) || (c >= 0x2C5E && c <= 0x3057 && c != 0x3000) ||
         (c >= 0xFB26 && c <= 0xFEFE);
}

void append_utf8(std::string& out, char32_t c) {
  if (c < 0x800) {
    out += static_cast<char>(0xC0 | (c >> 6));
  } else if (c < 0x10000) {
    out += static_cast<char>(0xE0 | (c >> 12));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (c >> 18));
    out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
  }
  out += static_cast<char>(0x80 | (c & 0x3F));
}

}  // namespace

// Moves the characters toml++ cannot take to kShelter + c (back = false), or back (true).
// Malformed UTF-8 is copied as is: toml++ refuses it.
std::string shelter(std::string_view text, bool back,
                    const std::function<void(char32_t, std::size_t)>& taken) {
  std::string out;
  out.reserve(text.size() + 16);
  for (std::size_t i = 0; i < text.size();) {
    const auto [c, len] = decode_utf8(text, i);
    if (len <= 1) {
      out += text[i++];
      continue;
    }
    if (!back && c >= kShelter && c < kShelter + 0x10000) taken(c, i);
    if (!back && toml_unsafe(c))
      append_utf8(out, kShelter + c);
    else if (back && c >= kShelter && toml_unsafe(c - kShelter))
      append_utf8(out, c - kShelter);
    else
      out.append(text.substr(i, len));
    i += len;
  }
  return out;
}

std::string unshelter(std::string_view s) { return shelter(s, true, {}); }

double to_number(const Reader& r, const toml::node& n, const std::string& label) {
  double x = 0;
  if (const auto* f = n.as_floating_point())
    x = f->get();
  else if (const auto* i = n.as_integer())
    x = static_cast<double>(i->get());
  else
    r.fail(n, label + " must be a number, not " + type_name(n), "write a number without quotes");
  if (!std::isfinite(x))
    r.fail(n, label + " is " + fmt(x) + ", not a finite number", "give a finite number");
  return x;
}

std::string to_text(const Reader& r, const toml::node& n, const std::string& label) {
  const auto* s = n.as_string();
  if (!s) r.fail(n, label + " must be a string, not " + type_name(n), "write it in quotes");
  return unshelter(s->get());
}

// One of a few names; returns its index in `names`.
std::size_t to_choice(const Reader& r, const toml::node& n, const std::string& label, Keys names) {
  const std::string s = to_text(r, n, label);
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == s) return i;
  const std::string near = closest(s, names);
  r.fail(n, label + " is \"" + s + "\", not one of " + join(names, " | "),
         near.empty() ? "use one of " + join(names, " | ") : "did you mean \"" + near + "\"?");
}

double number(const Tbl& t, std::string_view key, double def) {
  const toml::node* n = t.find(key);
  return n ? to_number(t.r, *n, t.label(key)) : def;
}

double required_number(const Tbl& t, std::string_view key, const std::string& fix) {
  return to_number(t.r, t.require(key, fix), t.label(key));
}

// A number in [lo, hi] (or [lo, hi) when hi_open), explained by `fix` when it is not.
void check_range(const Tbl& t, std::string_view key, double x, double lo, double hi, bool hi_open,
                 const std::string& fix) {
  if (x >= lo && (hi_open ? x < hi : x <= hi)) return;
  std::string range = "[";
  range += fmt(lo);
  range += ", ";
  range += fmt(hi);
  range += hi_open ? ")" : "]";
  t.r.fail(*t.find(key), t.label(key) + " is " + fmt(x) + ", outside " + range, fix);
}

const toml::table& as_table(const Reader& r, const toml::node& n, const std::string& label,
                            const std::string& fix) {
  const auto* t = n.as_table();
  if (!t) r.fail(n, label + " must be a table, not " + type_name(n), fix);
  return *t;
}

// The element tables of an array of tables ([[joints]] or joints = [{...}, ...]).
std::vector<const toml::table*> table_array(const Reader& r, const toml::node& n,
                                            const std::string& label, const std::string& fix) {
  const auto* a = n.as_array();
  if (!a) r.fail(n, label + " must be an array of tables, not " + type_name(n), fix);
  std::vector<const toml::table*> out;
  for (const auto& e : *a) {
    const auto* t = e.as_table();
    if (!t) r.fail(e, label + " must hold tables, not " + type_name(e), fix);
    out.push_back(t);
  }
  return out;
}

// A point or direction of the scene: [x, y, z], or [x, z] in 2-D (y = 0; docs/2d.md).
Vec3 to_point(const Reader& r, const toml::node& n, const std::string& label, int dimension) {
  if (dimension == 3) return to_vector<3>(r, n, label);
  const auto* a = n.as_array();
  if (!a || a->size() != 2)
    r.fail(n,
           label + " must be 2 numbers [x, z] in a 2-D scene, not " +
               (a ? "an array of " + std::to_string(a->size()) : type_name(n)),
           "write it as [x, z]: a 2-D scene is a section in (x, z)");
  return {to_number(r, *a->get(0), label), 0.0, to_number(r, *a->get(1), label)};
}

// A whole number (count, sides, max_joints).
std::int64_t to_integer(const Reader& r, const toml::node& n, const std::string& label) {
  const auto* i = n.as_integer();
  if (!i)
    r.fail(n, label + " must be a whole number, not " + type_name(n),
           "write an integer without quotes or decimals");
  return i->get();
}

// A number > 0 under `key`, explained by `fix` when it is not.
double positive(const Tbl& t, std::string_view key, const std::string& fix) {
  const double x = to_number(t.r, *t.find(key), t.label(key));
  if (!(x > 0)) t.r.fail(*t.find(key), t.label(key) + " is " + fmt(x) + ", not > 0", fix);
  return x;
}

// A stress key >= 0 (Pa), `def` if absent.
double stress(const Tbl& t, std::string_view key, double def) {
  const double v = number(t, key, def);
  if (v < 0)
    t.r.fail(*t.find(key), t.label(key) + " is " + fmt(v) + " < 0",
             "give a " + std::string(key) + " >= 0 (Pa)");
  return v;
}

// The first of `keys` present in the table, by line.
const toml::node* first_present(const Tbl& t, Keys keys, std::string_view* which) {
  const toml::node* best = nullptr;
  for (const auto& k : keys)
    if (const toml::node* n = t.find(k))
      if (!best || n->source().begin.line < best->source().begin.line) {
        best = n;
        if (which) *which = k;
      }
  return best;
}

}  // namespace slice::scene_read

#pragma once
// libslice/src/scene/toml_read.cpp: the TOML layer of the scene parser. Typed access to the
// nodes of a parsed scene (numbers, vectors, strings, choices, tables), every refusal one Error
// naming "<file>:<line>", the key, its table and a fix, with the closest known name for a
// misspelt one; and the UTF-8 shelter that keeps toml++ 3.3.0 from the characters it cannot take.
// Private to libslice/src/scene/.
#include <toml++/toml.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "scene_common.hpp"
#include "slice/error.hpp"
#include "slice/geometry.hpp"

namespace slice::scene_read {

using Keys = std::span<const std::string_view>;

std::string quote_key(std::string_view k);
std::string join(Keys keys, std::string_view sep);
// The known name closest to `s`, if it is close enough to be a likely typo; "" otherwise.
std::string closest(std::string_view s, Keys known);
// "a string", "an integer", ...: what a node is, for messages.
std::string type_name(const toml::node& n);

// Moves the characters toml++ cannot take to private use code points (back = false), or back
// (true); `taken` is called for a private use character the text itself holds.
std::string shelter(std::string_view text, bool back,
                    const std::function<void(char32_t, std::size_t)>& taken);
std::string unshelter(std::string_view s);

// Reads one scene file; every error names "<file>:<line>", the key, its table and a fix.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  std::string where(const toml::source_region& s) const {
    return s.begin.line == 0 ? file_ : file_ + ":" + std::to_string(s.begin.line);
  }
  [[noreturn]] void fail(const toml::source_region& s, const std::string& what,
                         const std::string& fix) const {
    throw Error(where(s), unshelter(what), unshelter(fix));
  }
  [[noreturn]] void fail(const toml::node& n, const std::string& what,
                         const std::string& fix) const {
    fail(n.source(), what, fix);
  }

 private:
  std::string file_;
};

// A table of the scene with the name messages use for it ("[[sets]] \"J2\"", "[[joints]] #3").
struct Tbl {
  const Reader& r;
  const toml::table& t;
  std::string ctx;

  std::string label(std::string_view key) const { return quote_key(key) + " in " + ctx; }

  // Refuses unknown keys (the first in the file), suggesting the closest known one.
  void check_keys(Keys known) const {
    const toml::key* bad = nullptr;
    for (auto&& [k, v] : t) {
      const bool ok = std::find(known.begin(), known.end(), k.str()) != known.end();
      if (ok) continue;
      if (!bad || k.source().begin.line < bad->source().begin.line) bad = &k;
    }
    if (!bad) return;
    const std::string_view k = bad->str();
    const std::string near = closest(k, known);
    r.fail(bad->source(), "unknown key " + quote_key(k) + " in " + ctx,
           near.empty() ? "the keys of " + ctx + " are: " + join(known, ", ")
                        : "did you mean " + quote_key(near) + "?");
  }

  const toml::node* find(std::string_view key) const { return t.get(key); }

  const toml::node& require(std::string_view key, const std::string& fix) const {
    const toml::node* n = find(key);
    if (!n) r.fail(t, "missing key " + quote_key(key) + " in " + ctx, fix);
    return *n;
  }
};

double to_number(const Reader& r, const toml::node& n, const std::string& label);

template <int N>
Eigen::Matrix<double, N, 1> to_vector(const Reader& r, const toml::node& n,
                                      const std::string& label) {
  static_assert(N == 2 || N == 3);
  const std::string form = N == 3 ? "[x, y, z]" : "[u, v]";
  const auto* a = n.as_array();
  if (!a || a->size() != static_cast<std::size_t>(N))
    r.fail(n,
           label + " must be " + std::to_string(N) + " numbers " + form + ", not " +
               (a ? "an array of " + std::to_string(a->size()) : type_name(n)),
           "write it as " + form);
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v(i) = to_number(r, *a->get(static_cast<std::size_t>(i)), label);
  return v;
}

std::string to_text(const Reader& r, const toml::node& n, const std::string& label);
// One of a few names; returns its index in `names`.
std::size_t to_choice(const Reader& r, const toml::node& n, const std::string& label, Keys names);
double number(const Tbl& t, std::string_view key, double def);
double required_number(const Tbl& t, std::string_view key, const std::string& fix);
// A number in [lo, hi] (or [lo, hi) when hi_open), explained by `fix` when it is not.
void check_range(const Tbl& t, std::string_view key, double x, double lo, double hi, bool hi_open,
                 const std::string& fix);
const toml::table& as_table(const Reader& r, const toml::node& n, const std::string& label,
                            const std::string& fix);
// The element tables of an array of tables ([[joints]] or joints = [{...}, ...]).
std::vector<const toml::table*> table_array(const Reader& r, const toml::node& n,
                                            const std::string& label, const std::string& fix);
// A point or direction of the scene: [x, y, z], or [x, z] in 2-D (y = 0; docs/2d.md).
Vec3 to_point(const Reader& r, const toml::node& n, const std::string& label, int dimension);
// A whole number (count, sides, max_joints).
std::int64_t to_integer(const Reader& r, const toml::node& n, const std::string& label);
// A number > 0 under `key`, explained by `fix` when it is not.
double positive(const Tbl& t, std::string_view key, const std::string& fix);
// A stress key >= 0 (Pa), `def` if absent.
double stress(const Tbl& t, std::string_view key, double def);
// The first of `keys` present in the table, by line.
const toml::node* first_present(const Tbl& t, Keys keys, std::string_view* which = nullptr);

}  // namespace slice::scene_read

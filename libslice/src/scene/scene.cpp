#include "slice/scene.hpp"

#include <toml++/toml.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <tuple>
#include <utility>

#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/polytope.hpp"
#include "slice/stochastic.hpp"
#include "slice/tunnel.hpp"
#include "slice/utf8.hpp"

namespace slice {

namespace {
template <typename Enum, std::size_t N>
std::optional<Enum> parse_name(std::string_view s, const std::array<std::string_view, N>& names) {
  for (std::size_t i = 0; i < N; ++i)
    if (s == names[i]) return static_cast<Enum>(i);
  return std::nullopt;
}
}  // namespace

// The tables hold string literals, so data() is NUL-terminated.
const char* to_string(JointKind k) { return kJointKindNames.at(std::size_t(k)).data(); }
const char* to_string(JointOrder o) { return kJointOrderNames.at(std::size_t(o)).data(); }
std::optional<JointKind> parse_joint_kind(std::string_view s) {
  return parse_name<JointKind>(s, kJointKindNames);
}
std::optional<JointOrder> parse_joint_order(std::string_view s) {
  return parse_name<JointOrder>(s, kJointOrderNames);
}
std::vector<Plane> solid_region(const Region& region, int dimension) {
  std::vector<Plane> planes = region.planes;
  if (dimension == 2) {
    planes.push_back({-Vec3::UnitY(), 0.5});
    planes.push_back({Vec3::UnitY(), 0.5});
  }
  return planes;
}

std::string fixed_faces_string(std::uint8_t faces) {
  std::string s;
  for (std::size_t k = 0; k < kBoxFaceNames.size(); ++k)
    if (faces & (1u << k)) {
      if (!s.empty()) s += ',';
      s += kBoxFaceNames[k];
    }
  return s;
}
std::optional<std::uint8_t> parse_fixed_faces(std::string_view text) {
  std::uint8_t faces = 0;
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    const auto k = parse_name<std::size_t>(text.substr(0, comma), kBoxFaceNames);
    if (!k) return std::nullopt;
    faces |= static_cast<std::uint8_t>(1u << *k);
    text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
  }
  return faces;
}
const char* to_string(SetIntensity v) { return kSetIntensityNames.at(std::size_t(v)).data(); }
const char* to_string(SizeDistribution v) {
  return kSizeDistributionNames.at(std::size_t(v)).data();
}
const char* to_string(JointShape v) { return kJointShapeNames.at(std::size_t(v)).data(); }
const char* to_string(EllipseFit v) { return kEllipseFitNames.at(std::size_t(v)).data(); }
std::optional<SetIntensity> parse_set_intensity(std::string_view s) {
  return parse_name<SetIntensity>(s, kSetIntensityNames);
}
std::optional<SizeDistribution> parse_size_distribution(std::string_view s) {
  return parse_name<SizeDistribution>(s, kSizeDistributionNames);
}
std::optional<JointShape> parse_joint_shape(std::string_view s) {
  return parse_name<JointShape>(s, kJointShapeNames);
}
std::optional<EllipseFit> parse_ellipse_fit(std::string_view s) {
  return parse_name<EllipseFit>(s, kEllipseFitNames);
}

namespace {

using Keys = std::span<const std::string_view>;

// The keys of each table of a scene file (DESIGN section 6).
constexpr std::array<std::string_view, 7> kTopTables = {"scene", "domain", "options", "joints",
                                                        "sets",  "zones",  "rock"};
constexpr std::array<std::string_view, 5> kSceneKeys = {"name", "seed", "tolerance", "max_joints",
                                                        "dimension"};
constexpr std::array<std::string_view, 2> kRegionKeys = {"box", "planes"};
// A zone is a region, a tunnel or a mesh; `cut` and `stage` apply to tunnels and meshes.
constexpr std::array<std::string_view, 6> kZoneKeys = {"box",  "planes", "tunnel",
                                                       "mesh", "cut",    "stage"};
constexpr std::array<std::string_view, 6> kTunnelKeys = {"point",  "direction", "length",
                                                         "radius", "sides",     "outline"};
// A tunnel's default number of sides: the 16-gon's area is 1.3 % above its inscribed circle's.
constexpr std::int64_t kDefaultTunnelSides = 16;
constexpr std::array<std::string_view, 2> kBoxKeys = {"min", "max"};
constexpr std::array<std::string_view, 2> kPlaneKeys = {"normal", "d"};
constexpr std::array<std::string_view, 6> kOptionKeys = {
    "order", "min_inscribed_diameter", "max_aspect_ratio", "max_blocks", "fixed_faces", "slivers"};
constexpr std::array<std::string_view, 13> kJointKeys = {
    "dip",      "dip_direction", "point", "polygon", "polygon_uv", "kind",   "friction_angle",
    "cohesion", "keep",          "stage", "limits",  "segment",    "tension"};
constexpr std::array<std::string_view, 24> kSetKeys = {
    "name",           "dip",      "dip_direction", "spacing", "offset", "kind", "keep",
    "friction_angle", "cohesion", "fisher_kappa",  "density", "count",  "p32",  "p10",
    "scanline",       "size",     "shape",         "aspect",  "sides",  "fit",  "rotation",
    "stage",          "limits",   "tension"};
// [rock]: intact rock, for the contacts DEM exports put through rock bridges (RockSpec).
constexpr std::array<std::string_view, 3> kRockKeys = {"friction_angle", "cohesion", "tension"};
// The intensity keys of a set, in the order of SetIntensity: exactly one is given.
constexpr std::array<std::string_view, 5> kIntensityKeys = {"spacing", "density", "count", "p32",
                                                            "p10"};
// Keys that only finite (sized) joints of a stochastic set take.
constexpr std::array<std::string_view, 5> kFiniteKeys = {"shape", "aspect", "sides", "fit",
                                                         "rotation"};
constexpr std::array<std::string_view, 2> kScanlineKeys = {"from", "to"};
// The keys of `size` for each distribution (SizeDistribution order; "none" takes none).
constexpr std::array<std::string_view, 2> kFixedKeys = {"distribution", "value"};
constexpr std::array<std::string_view, 3> kLognormalKeys = {"distribution", "mean", "sd"};
constexpr std::array<std::string_view, 2> kExponentialKeys = {"distribution", "mean"};
constexpr std::array<std::string_view, 4> kPowerLawKeys = {"distribution", "exponent", "min",
                                                           "max"};
// Distributions a scene may name (SizeDistribution without "none").
constexpr std::array<std::string_view, 4> kSizeNames = {"fixed", "lognormal", "exponential",
                                                        "power-law"};
// More corners than this is a slip (a polygon is meant, not a circle drawn point by point).
constexpr std::int64_t kMaxSides = 1000;

constexpr std::array<std::string_view, 2> kKeepNames = {"above", "below"};

// More planes than this in one set is a unit slip (spacing in m, domain in mm), not a scene.
constexpr double kMaxPlanesPerSet = 1e6;

std::string fmt(double x, int digits = 12) {
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

// ---------------------------------------------------------------------------------------------
// Regions (domain, zones)

enum class RegionStatus { ok, unbounded, empty };

struct RegionAnalysis {
  RegionStatus status = RegionStatus::empty;
  PolytopeInfo info;
  double length_scale = 0;  // half the bounding-box diagonal of the vertices
};

// Analyses a region with tolerances relative to its own size. A first pass with a tolerance from
// the planes' offsets finds the vertices roughly; the length scale L of those sets the absolute
// tolerance rel * L of the second pass, so a scene in mm or shifted by 1e6 m gives the same
// answers as the same scene in m at the origin (DESIGN section 10).
// A 2-D section's planes are its slab's (solid_region); its size is measured in (x, z).
RegionAnalysis analyse_region(std::span<const Plane> planes, double rel, int dimension) {
  const bool section = dimension == 2;
  RegionAnalysis a;
  double dmax = 0;
  for (const auto& p : planes) dmax = std::max(dmax, std::abs(p.d));
  const PolytopeInfo rough = analyse_polytope(planes, rel * dmax);
  if (!rough.bounded) {
    a.status = RegionStatus::unbounded;
    return a;
  }
  if (rough.vertices.empty()) return a;
  const double rough_scale = 0.5 * (rough.max - rough.min).norm();
  a.info = analyse_polytope(planes, rel * rough_scale);
  if (!a.info.bounded) {
    a.status = RegionStatus::unbounded;
    return a;
  }
  if (a.info.vertices.empty() || !a.info.has_interior) return a;
  Vec3 size = a.info.max - a.info.min;
  if (section) size.y() = 0;
  a.length_scale = 0.5 * size.norm();
  a.status = a.length_scale > 0 ? RegionStatus::ok : RegionStatus::empty;
  return a;
}

// Range of n . v over the domain's vertices.
std::pair<double, double> extent_along(const std::vector<Vec3>& vertices, const Vec3& n) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& v : vertices) {
    lo = std::min(lo, n.dot(v));
    hi = std::max(hi, n.dot(v));
  }
  return {lo, hi};
}

// The upward unit normal of dip / dip direction; in a 2-D section (dip direction 90 or 270)
// exactly (+-sin dip, 0, cos dip), so that every normal has y = 0 (docs/2d.md).
Vec3 dip_normal(double dip_deg, double dip_direction_deg, int dimension) {
  if (dimension == 3) return normal_from_dip(dip_deg, dip_direction_deg);
  const double dip = dip_deg * std::numbers::pi / 180;
  return {(dip_direction_deg == 270 ? -1.0 : 1.0) * std::sin(dip), 0.0, std::cos(dip)};
}

// The planes n . x = offset + k * spacing of a set that pass through the domain's interior:
// lo + tol < c < hi - tol, so a plane on a domain face (or within tol of it) is not generated.
std::vector<double> set_planes(const JointSetSpec& s, const Vec3& n,
                               const std::vector<Vec3>& vertices, double tol) {
  const auto [lo, hi] = extent_along(vertices, n);
  std::vector<double> c;
  const double k0 = std::ceil((lo + tol - s.offset) / s.spacing) - 1;
  const double k1 = std::floor((hi - tol - s.offset) / s.spacing) + 1;
  // Counted by an integer: past 2^53, k + 1 == k in double and a loop on k never ends.
  const auto steps = static_cast<std::int64_t>(k1 - k0);
  for (std::int64_t i = 0; i <= steps; ++i) {
    const double ck = s.offset + (k0 + double(i)) * s.spacing;
    if (lo + tol < ck && ck < hi - tol) c.push_back(ck);
  }
  return c;
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

// The region of a table with `box` or `planes` (its keys already checked).
Region region_of(const Tbl& t, int dimension) {
  const Reader& r = t.r;
  const toml::node* box = t.find("box");
  const toml::node* planes = t.find("planes");
  const std::string both =
      dimension == 3
          ? "box = { min = [x, y, z], max = [x, y, z] } or planes = [ { normal = [nx, ny, nz], d "
            "= d }, ... ] (outward normals, normal . x <= d inside)"
          : "box = { min = [x, z], max = [x, z] } or planes = [ { normal = [nx, nz], d = d }, "
            "... ] (outward normals, normal . x <= d inside)";
  const std::string corner = dimension == 3 ? "[x, y, z]" : "[x, z]";
  if (box && planes) r.fail(*planes, t.ctx + " gives both 'box' and 'planes'", "keep one of them");
  if (!box && !planes) r.fail(t.t, t.ctx + " has neither 'box' nor 'planes'", "add " + both);
  Region region;
  if (box) {
    const Tbl b{r,
                as_table(r, *box, t.label("box"),
                         "write box = { min = " + corner + ", max = " + corner + " }"),
                "'box' of " + t.ctx};
    b.check_keys(kBoxKeys);
    const Vec3 mn = to_point(r, b.require("min", "add min = " + corner + ", the lower corner"),
                             b.label("min"), dimension);
    const Vec3 mx = to_point(r, b.require("max", "add max = " + corner + ", the upper corner"),
                             b.label("max"), dimension);
    for (int i = 0; i < 3; ++i)
      if (!(mn(i) < mx(i)) && !(dimension == 2 && i == 1)) {
        const std::string axis(1, "xyz"[i]);
        r.fail(*b.find("max"),
               "'box' of " + t.ctx + " has min " + axis + " = " + fmt(mn(i)) + " >= max " + axis +
                   " = " + fmt(mx(i)),
               "make min the lower corner and max the upper corner, min < max in every axis");
      }
    region.planes = box_planes(mn, mx);
    if (dimension == 2)  // no faces normal to y in a section
      std::erase_if(region.planes, [](const Plane& p) { return p.normal.y() != 0; });
    return region;
  }
  const auto elems = table_array(r, *planes, t.label("planes"), "write " + both);
  if (elems.empty()) r.fail(*planes, t.label("planes") + " is empty", "write " + both);
  for (std::size_t i = 0; i < elems.size(); ++i) {
    const Tbl p{r, *elems[i], "plane #" + std::to_string(i + 1) + " of " + t.ctx};
    p.check_keys(kPlaneKeys);
    const toml::node& nn =
        p.require("normal", dimension == 3 ? "add normal = [nx, ny, nz], pointing outward"
                                           : "add normal = [nx, nz], pointing outward");
    const Vec3 n = to_point(r, nn, p.label("normal"), dimension);
    const double d = required_number(p, "d", "add d, so that the plane is normal . x = d");
    const double len = std::isfinite(n.norm()) && n.norm() > 0 ? n.norm() : n.stableNorm();
    if (!(len > 0) || !std::isfinite(len))
      r.fail(nn, p.label("normal") + " is " + fmt(n) + ", which has no direction",
             "give the plane's outward normal, e.g. [0, 0, 1] for a top face");
    // Unit normals: scale d with the normal, so that the half-space itself does not change.
    region.planes.push_back({n / len, d / len});
  }
  return region;
}

Region read_region(const Tbl& t, int dimension) {
  t.check_keys(kRegionKeys);
  return region_of(t, dimension);
}

// ---------------------------------------------------------------------------------------------
// Polygons

// Checks a polygon in its plane's (u, v) coordinates: at least 3 vertices, no repeated or
// collinear consecutive vertices, convex, winding once. Makes it counter-clockwise (seen from the
// side the upward normal points to, as the (u, v, n) frame is right-handed).
void check_polygon(const Reader& r, std::vector<Vec2>& p,
                   const std::vector<const toml::node*>& where, const toml::node& key,
                   const std::string& label, double tol) {
  const std::size_t n = p.size();
  const std::string convex_fix =
      "give the corners of a convex polygon in order around it (either direction)";
  if (n < 3)
    r.fail(key, label + " has " + std::to_string(n) + " vertices; a polygon needs at least 3",
           "give at least 3 corners, or leave the polygon out for a persistent joint");
  auto at = [&](std::size_t i) -> const toml::node& { return *where[i % n]; };
  auto vname = [n](std::size_t i) { return std::to_string(i % n + 1); };
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    if ((p[j] - p[i]).norm() <= tol)
      r.fail(at(j), label + ": vertices " + vname(i) + " and " + vname(j) + " are the same point",
             "remove the repeated vertex (do not repeat the first vertex at the end)");
  }
  // The orientation is that of the signed area, so a reflex vertex is the one named below.
  double area2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = p[i];
    const Vec2& b = p[(i + 1) % n];
    area2 += a.x() * b.y() - a.y() * b.x();
  }
  const int sign = area2 > 0 ? 1 : -1;
  double turning = 0;  // sum of the exterior angles: +-2 pi for a convex polygon
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = p[(i + n - 1) % n], b = p[i], c = p[(i + 1) % n];
    const Vec2 e1 = b - a, e2 = c - b;
    const double cross = e1.x() * e2.y() - e1.y() * e2.x();
    // Distance of the vertex from the line through its neighbours.
    const double off = std::abs(cross) / (c - a).norm();
    if (!((c - a).norm() > tol) || off <= tol)
      r.fail(at(i),
             label + ": vertices " + vname((i + n - 1) % n) + ", " + vname(i) + ", " +
                 vname((i + 1) % n) + " are collinear",
             "remove vertex " + vname(i) + ", which lies on the edge between its neighbours");
    if ((cross > 0 ? 1 : -1) != sign)
      r.fail(at(i), label + " is not convex at vertex " + vname(i), convex_fix);
    turning += std::atan2(cross, e1.dot(e2));
  }
  if (std::abs(turning) > 3 * std::numbers::pi)
    r.fail(key, label + " crosses itself (it winds around more than once)", convex_fix);
  if (sign < 0) std::reverse(p.begin(), p.end());
}

// ---------------------------------------------------------------------------------------------

struct Context {
  const Reader& r;
  int dimension = 3;
  RegionAnalysis domain_info;
  double rel_tol = 1e-9;
  DomainBox box{};  // the domain as the joint generator sees it
  std::int64_t max_joints = kDefaultMaxJoints;
  std::filesystem::path dir{};  // the scene file's directory: relative mesh paths start there
  double tol() const { return rel_tol * domain_info.length_scale; }
};

DomainBox domain_box(const Region& domain, const RegionAnalysis& a, double rel_tol) {
  DomainBox b;
  b.planes = domain.planes;
  b.min = a.info.min;
  b.max = a.info.max;
  b.interior_point = a.info.interior_point;
  b.volume = a.info.volume;
  b.tol = rel_tol * a.length_scale;
  return b;
}

constexpr char kDipFix[] =
    "dip is measured down from the horizontal, 0 to 90 degrees (a plane dipping more than 90 "
    "is the same plane with dip 180 - dip and dip direction +- 180)";
constexpr char kDipDirectionFix[] =
    "give the dip direction clockwise from North in [0, 360) (e.g. 360 -> 0, -30 -> 330)";

struct Common {  // what [[joints]] and [[sets]] share
  double dip = 0, dip_direction = 0, friction = 30, cohesion = 0, tension = 0;
  JointKind kind = JointKind::rock;
  std::int8_t side = 0;
  bool limits = true;
};

// A stress key >= 0 (Pa), `def` if absent.
double stress(const Tbl& t, std::string_view key, double def) {
  const double v = number(t, key, def);
  if (v < 0)
    t.r.fail(*t.find(key), t.label(key) + " is " + fmt(v) + " < 0",
             "give a " + std::string(key) + " >= 0 (Pa)");
  return v;
}

Common read_common(const Tbl& t) {
  Common c;
  c.dip = required_number(t, "dip", "add dip = <degrees from horizontal, 0 to 90>");
  check_range(t, "dip", c.dip, 0, 90, false, kDipFix);
  c.dip_direction =
      required_number(t, "dip_direction", "add dip_direction = <degrees clockwise from North>");
  check_range(t, "dip_direction", c.dip_direction, 0, 360, true, kDipDirectionFix);
  c.friction = number(t, "friction_angle", 30);
  check_range(t, "friction_angle", c.friction, 0, 90, true,
              "give the friction angle in degrees, 0 <= friction_angle < 90");
  c.cohesion = number(t, "cohesion", 0);
  if (c.cohesion < 0)
    t.r.fail(*t.find("cohesion"), t.label("cohesion") + " is " + fmt(c.cohesion) + " < 0",
             "give a cohesion >= 0 (Pa)");
  c.tension = stress(t, "tension", 0);
  if (const toml::node* k = t.find("kind"))
    c.kind = static_cast<JointKind>(to_choice(t.r, *k, t.label("kind"), kJointKindNames));
  if (const toml::node* n = t.find("limits")) {
    const auto* b = n->as_boolean();
    if (!b)
      t.r.fail(*n, t.label("limits") + " must be true or false, not " + type_name(*n),
               "write limits = false to exempt these cuts from the size and shape limits");
    c.limits = b->get();
  }
  const toml::node* keep = t.find("keep");
  if (c.kind == JointKind::boundary) {
    const toml::node& kn = t.require(
        "keep", "add keep = \"above\" or \"below\": the side whose blocks become boundary blocks");
    c.side = to_choice(t.r, kn, t.label("keep"), kKeepNames) == 0 ? 1 : -1;
  } else if (keep) {
    t.r.fail(*keep,
             t.label("keep") + " applies to boundary joints only, and this is a " +
                 to_string(c.kind) + " joint",
             "remove 'keep', or set kind = \"boundary\"");
  }
  return c;
}

// In a section in (x, z) a joint dips towards +x or -x (docs/2d.md); a horizontal one has no
// dip direction, so any is accepted (docs/scenes.md): its normal is +z all the same.
void check_section_dip(const Context& cx, const Tbl& t, const Common& c) {
  if (cx.dimension == 2 && c.dip != 0 && c.dip_direction != 90 && c.dip_direction != 270)
    t.r.fail(*t.find("dip_direction"),
             t.label("dip_direction") + " is " + fmt(c.dip_direction) +
                 "; in a 2-D scene (a section in x, z) a joint dips towards +x or -x",
             "write dip_direction = 90 (dips towards +x) or 270 (towards -x)");
}

// A [[joints]] entry of a 2-D scene: a line through `point`, or the segment `segment` of it,
// stored as the rectangle of its plane that spans y from -0.5 to 0.5 (docs/2d.md).
Joint read_joint_2d(const Context& cx, const Tbl& t, const Common& c, Joint j) {
  const Reader& r = cx.r;
  for (const char* key : {"polygon", "polygon_uv"})
    if (const toml::node* n = t.find(key))
      r.fail(*n, t.label(key) + " is for 3-D scenes",
             "in a 2-D scene give a finite joint as segment = [[x1, z1], [x2, z2]]");
  j.centre = to_point(r, t.require("point", "add point = [x, z], a point on the joint's line"),
                      t.label("point"), 2);
  const Vec3 n = dip_normal(c.dip, c.dip_direction, 2);
  j.plane = {n, n.dot(j.centre)};
  const toml::node* seg = t.find("segment");
  if (!seg) return j;
  const double tol = cx.tol();
  const std::string label = "the segment of " + t.ctx;
  const auto* a = seg->as_array();
  if (!a || a->size() != 2)
    r.fail(*seg,
           t.label("segment") + " must be two points [[x1, z1], [x2, z2]], not " +
               (a ? "an array of " + std::to_string(a->size()) : type_name(*seg)),
           "write segment = [[x1, z1], [x2, z2]], its two ends on the joint's line");
  std::array<Vec3, 2> ends;
  for (std::size_t i = 0; i < 2; ++i) {
    const toml::node& e = *a->get(i);
    ends[i] = to_point(r, e, "end " + std::to_string(i + 1) + " of " + t.label("segment"), 2);
    const double off = std::abs(j.plane.distance(ends[i]));
    if (off > tol)
      r.fail(e,
             label + ": end " + std::to_string(i + 1) + " is " + fmt(off) +
                 " off the joint's line (dip " + fmt(c.dip) + ", dip direction " +
                 fmt(c.dip_direction) + ", through 'point')",
             "put the ends on the line or correct dip / dip_direction / point (tolerance " +
                 fmt(tol, 3) + ")");
  }
  if ((ends[1] - ends[0]).norm() <= tol)
    r.fail(*seg, label + " has no length: its ends are the same point",
           "give two different ends, or leave 'segment' out for a persistent joint");
  const JointFrame frame = plane_frame(c.dip, c.dip_direction);
  std::vector<Vec2> uv;
  std::vector<const toml::node*> where;
  for (const Vec3& e : ends)
    for (const double y : {-0.5, 0.5}) {
      uv.push_back(frame.to_uv(j.centre, e + y * Vec3::UnitY()));
      where.push_back(seg);
    }
  std::swap(uv[2], uv[3]);  // around the rectangle: a-, a+, b+, b-
  check_polygon(r, uv, where, *seg, label, tol);
  j.polygon_uv = std::move(uv);
  return j;
}

Joint read_joint(const Context& cx, const toml::table& tt, std::size_t index) {
  const Reader& r = cx.r;
  const Tbl t{r, tt, "[[joints]] #" + std::to_string(index + 1)};
  t.check_keys(kJointKeys);
  const Common c = read_common(t);
  Joint j;
  j.dip_deg = c.dip;
  j.dip_direction_deg = c.dip_direction;
  j.kind = c.kind;
  j.friction_angle_deg = c.friction;
  j.cohesion = c.cohesion;
  j.tension = c.tension;
  j.boundary_side = c.side;
  j.limits = c.limits;
  check_section_dip(cx, t, c);
  if (cx.dimension == 2) return read_joint_2d(cx, t, c, std::move(j));
  if (const toml::node* n = t.find("segment"))
    r.fail(*n, t.label("segment") + " is for 2-D scenes",
           "in a 3-D scene give a finite joint as polygon = [[x, y, z], ...]");
  const JointFrame frame = plane_frame(c.dip, c.dip_direction);
  const toml::node* point = t.find("point");
  const toml::node* poly = t.find("polygon");
  const toml::node* poly_uv = t.find("polygon_uv");
  if (poly && poly_uv)
    r.fail(*poly_uv, t.ctx + " gives both 'polygon' and 'polygon_uv'",
           "keep one: polygon in global [x, y, z] or polygon_uv in [u, v] about 'point'");
  if (!point && !poly)
    t.require("point", std::string("add point = [x, y, z], a point on the joint's plane") +
                           (poly_uv ? " (polygon_uv is given about it)" : ""));
  const double tol = cx.tol();
  const std::string poly_label = "the polygon of " + t.ctx;
  std::vector<Vec2> uv;
  std::vector<const toml::node*> where;
  if (poly) {
    const auto* a = poly->as_array();
    if (!a)
      r.fail(*poly, t.label("polygon") + " must be an array of [x, y, z], not " + type_name(*poly),
             "write polygon = [[x1, y1, z1], [x2, y2, z2], ...]");
    std::vector<Vec3> xs;
    for (const auto& e : *a) {
      xs.push_back(to_vector<3>(
          r, e, "vertex " + std::to_string(xs.size() + 1) + " of " + t.label("polygon")));
      where.push_back(&e);
    }
    if (xs.size() < 3)
      r.fail(*poly,
             poly_label + " has " + std::to_string(xs.size()) +
                 " vertices; a polygon needs at least 3",
             "give at least 3 corners, or leave the polygon out for a persistent joint");
    Vec3 mean = Vec3::Zero();
    for (const auto& x : xs) mean += x;
    mean /= static_cast<double>(xs.size());
    // Best-fit plane through the vertex mean: normal = the direction of least spread.
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& x : xs) cov += (x - mean) * (x - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Vec3 best = es.eigenvectors().col(0);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const double off = std::abs(best.dot(xs[i] - mean));
      if (off > tol)
        r.fail(*where[i],
               poly_label + " is not planar: vertex " + std::to_string(i + 1) + " is " + fmt(off) +
                   " from the plane that fits the vertices best",
               "give vertices that lie in one plane, the joint's plane (tolerance " + fmt(tol, 3) +
                   ")");
    }
    j.centre = point ? to_vector<3>(r, *point, t.label("point")) : mean;
    j.plane = {frame.n, frame.n.dot(j.centre)};
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const double off = std::abs(j.plane.distance(xs[i]));
      if (off > tol)
        r.fail(*where[i],
               poly_label + ": vertex " + std::to_string(i + 1) + " " + fmt(xs[i]) + " is " +
                   fmt(off) + " off the joint's plane (dip " + fmt(c.dip) + ", dip direction " +
                   fmt(c.dip_direction) +
                   (point ? ", through 'point'" : ", through the vertex mean") + ")",
               "put the vertices on the plane or correct dip / dip_direction" +
                   std::string(point ? " / point" : "") + " (tolerance " + fmt(tol, 3) + ")");
      uv.push_back(frame.to_uv(j.centre, xs[i]));
    }
    check_polygon(r, uv, where, *poly, poly_label, tol);
  } else {
    j.centre = to_vector<3>(r, *point, t.label("point"));
    j.plane = {frame.n, frame.n.dot(j.centre)};
    if (poly_uv) {
      const auto* a = poly_uv->as_array();
      if (!a)
        r.fail(*poly_uv,
               t.label("polygon_uv") + " must be an array of [u, v], not " + type_name(*poly_uv),
               "write polygon_uv = [[u1, v1], [u2, v2], ...]");
      for (const auto& e : *a) {
        uv.push_back(to_vector<2>(
            r, e, "vertex " + std::to_string(uv.size() + 1) + " of " + t.label("polygon_uv")));
        where.push_back(&e);
      }
      check_polygon(r, uv, where, *poly_uv, poly_label, tol);
    }
  }
  j.polygon_uv = std::move(uv);
  return j;
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

// The first of `keys` present in the table, by line.
const toml::node* first_present(const Tbl& t, Keys keys, std::string_view* which = nullptr) {
  const toml::node* best = nullptr;
  for (const auto& k : keys)
    if (const toml::node* n = t.find(k))
      if (!best || n->source().begin.line < best->source().begin.line) {
        best = n;
        if (which) *which = k;
      }
  return best;
}

SizeSpec read_size(const Tbl& set, const toml::node& node) {
  const Reader& r = set.r;
  const Tbl t{r,
              as_table(r, node, set.label("size"),
                       "write size = { distribution = \"lognormal\", mean = 5.0, sd = 1.0 }"),
              "'size' of " + set.ctx};
  const toml::node& dn =
      t.require("distribution",
                "add distribution = \"fixed\" | \"lognormal\" | \"exponential\" | "
                "\"power-law\"");
  SizeSpec s;
  s.distribution =
      static_cast<SizeDistribution>(to_choice(r, dn, t.label("distribution"), kSizeNames) + 1);
  const std::string size_fix = "give a length > 0 (the joints' size in the scene's unit)";
  switch (s.distribution) {
    case SizeDistribution::fixed:
      t.check_keys(kFixedKeys);
      t.require("value", "add value = <the size of every joint>");
      s.value = positive(t, "value", size_fix);
      break;
    case SizeDistribution::lognormal:
      t.check_keys(kLognormalKeys);
      t.require("mean", "add mean = <mean size> (of the size itself, not of its log)");
      t.require("sd", "add sd = <standard deviation of the size> (of the size, not of its log)");
      s.mean = positive(t, "mean", size_fix);
      s.sd = positive(t, "sd",
                      "give the standard deviation of the size itself, > 0 (for one size, use "
                      "distribution = \"fixed\")");
      break;
    case SizeDistribution::exponential:
      t.check_keys(kExponentialKeys);
      t.require("mean", "add mean = <mean size>");
      s.mean = positive(t, "mean", size_fix);
      break;
    case SizeDistribution::power_law:
      t.check_keys(kPowerLawKeys);
      t.require("exponent", "add exponent = a (density proportional to size^-a), e.g. 2.5");
      t.require("min", "add min = <smallest size>");
      t.require("max", "add max = <largest size>");
      s.exponent = required_number(t, "exponent", "");
      s.min = positive(t, "min", size_fix);
      s.max = positive(t, "max", size_fix);
      if (!(s.max > s.min))
        r.fail(*t.find("max"),
               t.label("max") + " = " + fmt(s.max) + " is not above min = " + fmt(s.min),
               "give min < max (for one size, use distribution = \"fixed\")");
      break;
    case SizeDistribution::persistent:
      break;
  }
  return s;
}

// A segment given as { from = [x, y, z], to = [x, y, z] } that must lie inside the domain.
void read_scanline(const Context& cx, const Tbl& set, const toml::node& node, JointSetSpec& s) {
  const Reader& r = set.r;
  const std::string form = "scanline = { from = [x, y, z], to = [x, y, z] }";
  const Tbl t{r, as_table(r, node, set.label("scanline"), "write " + form),
              "'scanline' of " + set.ctx};
  t.check_keys(kScanlineKeys);
  s.scanline_from =
      to_vector<3>(r, t.require("from", "add from = [x, y, z], one end"), t.label("from"));
  s.scanline_to =
      to_vector<3>(r, t.require("to", "add to = [x, y, z], the other end"), t.label("to"));
  s.scanline_given = true;
  const double tol = cx.tol();
  if (!((s.scanline_to - s.scanline_from).norm() > tol))
    r.fail(node, set.label("scanline") + " has no length: from and to are the same point",
           "give two different points inside the domain");
  for (const auto* key : {"from", "to"}) {
    const Vec3 x = std::string_view(key) == "from" ? s.scanline_from : s.scanline_to;
    for (const Plane& p : cx.box.planes)
      if (p.distance(x) > tol)
        r.fail(*t.find(key),
               "the scanline of " + set.ctx + " leaves the domain: '" + key + "' " + fmt(x) +
                   " is " + fmt(p.distance(x), 6) + " outside the domain face with outward " +
                   "normal " + fmt(p.normal),
               "give both ends of the scanline inside the domain");
  }
}

// An entry's place in the sequence: `stage` (a whole number >= 1, default 1) and its line.
EntryPlace read_place(const Reader& r, const toml::table& t, const std::string& ctx,
                      std::int64_t entry) {
  EntryPlace p;
  p.line = t.source().begin.line;
  p.entry = entry;
  if (const toml::node* n = t.get("stage")) {
    p.stage = to_integer(r, *n, quote_key("stage") + " in " + ctx);
    if (p.stage < 1)
      r.fail(*n, quote_key("stage") + " in " + ctx + " is " + std::to_string(p.stage) + ", below 1",
             "give a whole number >= 1: stage 1 is introduced first, then 2, ...");
  }
  return p;
}

JointSetSpec read_set(const Context& cx, const toml::table& tt, std::size_t index,
                      std::set<std::string>& names) {
  const Reader& r = cx.r;
  std::string name = "set-" + std::to_string(index + 1);
  std::string ctx = "[[sets]] #" + std::to_string(index + 1);
  const toml::node* name_node = tt.get("name");
  if (name_node) {
    name = to_text(r, *name_node, quote_key("name") + " in " + ctx);
    ctx = "[[sets]] \"" + name + "\"";
  }
  const Tbl t{r, tt, ctx};
  t.check_keys(kSetKeys);
  if (!names.insert(name).second)
    r.fail(name_node ? *name_node : static_cast<const toml::node&>(tt),
           "two [[sets]] are named \"" + name + "\"", "give each set its own name");
  const Common c = read_common(t);
  JointSetSpec s;
  s.name = name;
  s.dip_deg = c.dip;
  s.dip_direction_deg = c.dip_direction;
  s.kind = c.kind;
  s.friction_angle_deg = c.friction;
  s.cohesion = c.cohesion;
  s.tension = c.tension;
  s.limits = c.limits;
  s.boundary_side = c.side;

  // Exactly one intensity.
  std::vector<std::size_t> given;
  for (std::size_t i = 0; i < kIntensityKeys.size(); ++i)
    if (t.find(kIntensityKeys[i])) given.push_back(i);
  if (given.empty())
    r.fail(tt,
           "missing key 'spacing' (or 'density', 'count', 'p32', 'p10') in " + ctx +
               ": a set needs one intensity",
           "add spacing = <distance> for regular persistent planes, or one of density = "
           "<centres per unit volume>, count = <joints>, p32 = <area per unit volume>, p10 = "
           "<joints per unit length> (with a scanline) for a stochastic set");
  if (given.size() > 1) {
    std::vector<std::string_view> keys;
    for (const std::size_t i : given) keys.push_back(kIntensityKeys[i]);
    std::string_view second;
    const toml::node* first = first_present(t, keys);
    for (const auto& k : keys)
      if (t.find(k) != first &&
          (second.empty() || t.find(k)->source().begin.line < t.find(second)->source().begin.line))
        second = k;
    std::string_view first_key;
    for (const auto& k : keys)
      if (t.find(k) == first) first_key = k;
    r.fail(*t.find(second),
           ctx + " gives both " + quote_key(first_key) + " and " + quote_key(second),
           "keep one intensity: spacing, density, count, p32 or p10");
  }
  s.intensity = static_cast<SetIntensity>(given.front());
  const std::string_view ikey = kIntensityKeys[given.front()];
  check_section_dip(cx, t, c);
  if (cx.dimension == 2) {
    if (s.intensity != SetIntensity::spacing)
      r.fail(*t.find(ikey),
             t.label(ikey) + ": a 2-D scene's sets are regular lines (spacing) for now",
             "give spacing = <distance between the lines>, or the joints one by one as "
             "[[joints]] with segment = [[x1, z1], [x2, z2]]");
    if (const toml::node* n = t.find("fisher_kappa"))
      r.fail(*n, t.label("fisher_kappa") + " is not available in a 2-D scene",
             "remove it: a 2-D set's lines share one orientation");
  }

  if (const toml::node* n = t.find("fisher_kappa")) {
    s.fisher_kappa = to_number(r, *n, t.label("fisher_kappa"));
    if (s.fisher_kappa < 0)
      r.fail(*n, t.label("fisher_kappa") + " is " + fmt(s.fisher_kappa) + ", below 0",
             "give the Fisher concentration, >= 0 (0: every joint at the mean orientation; the "
             "larger, the tighter the poles)");
  }
  if (const toml::node* n = t.find("scanline")) read_scanline(cx, t, *n, s);
  const toml::node* size_node = t.find("size");
  if (size_node) s.size = read_size(t, *size_node);
  const bool finite = s.size.distribution != SizeDistribution::persistent;

  if (s.intensity == SetIntensity::spacing) {
    // Regular persistent planes: one orientation, no size.
    std::string_view bad;
    if (const toml::node* n = first_present(
            t,
            std::array<std::string_view, 6>{"size", "shape", "aspect", "sides", "fit", "rotation"},
            &bad))
      r.fail(*n,
             t.label(bad) +
                 " does not apply to a regular set (spacing), whose joints are "
                 "persistent planes",
             "remove " + quote_key(bad) +
                 ", or replace 'spacing' by density, count, p32 or p10 for a stochastic set");
    if (s.fisher_kappa > 0)
      r.fail(*t.find("fisher_kappa"),
             t.label("fisher_kappa") + " does not apply to a regular set (spacing): its planes " +
                 "share one orientation",
             "remove 'fisher_kappa', or replace 'spacing' by density, count, p32 or p10");
    s.spacing =
        positive(t, "spacing", "give the distance between the set's planes, a positive length");
    s.offset = number(t, "offset", 0);
    const Vec3 n = dip_normal(s.dip_deg, s.dip_direction_deg, cx.dimension);
    const auto [lo, hi] = extent_along(cx.domain_info.info.vertices, n);
    if ((hi - lo) / s.spacing > kMaxPlanesPerSet)
      r.fail(*t.find("spacing"),
             t.label("spacing") + " = " + fmt(s.spacing) + " gives about " +
                 fmt(std::round((hi - lo) / s.spacing)) + " planes across the domain, more than " +
                 fmt(kMaxPlanesPerSet),
             "check the units of spacing and of the domain");
    return s;
  }

  if (const toml::node* n = t.find("offset"))
    r.fail(*n, t.label("offset") + " applies to regular sets (spacing) only",
           "remove 'offset': the joints of a stochastic set are placed at random");
  const toml::node& in = *t.find(ikey);
  switch (s.intensity) {
    case SetIntensity::density:
      s.density = positive(t, "density", "give the number of joint centres per unit volume, > 0");
      break;
    case SetIntensity::count:
      s.count = to_integer(r, in, t.label("count"));
      if (s.count < 1)
        r.fail(in, t.label("count") + " is " + std::to_string(s.count) + ", below 1",
               "give the number of joints, >= 1");
      break;
    case SetIntensity::p32:
      s.p32 = positive(t, "p32", "give the joint area per unit volume, > 0");
      if (!finite)
        r.fail(in, t.label("p32") + " needs finite joints, and the set has no 'size'",
               "add size = { distribution = \"lognormal\", mean = ..., sd = ... } (or fixed, "
               "exponential, power-law), or give density, count or p10 for persistent planes");
      break;
    case SetIntensity::p10:
      s.p10 = positive(t, "p10", "give the number of joints per unit length of the scanline, > 0");
      if (!s.scanline_given)
        t.require("scanline",
                  "add scanline = { from = [x, y, z], to = [x, y, z] }: p10 counts the joints "
                  "crossing it");
      if (std::llround(s.p10 * (s.scanline_to - s.scanline_from).norm()) < 1)
        r.fail(in,
               t.label("p10") + " = " + fmt(s.p10) + " on a scanline " +
                   fmt((s.scanline_to - s.scanline_from).norm(), 6) + " long asks for " +
                   "no joint at all",
               "lengthen the scanline or raise p10");
      break;
    case SetIntensity::spacing:
      break;
  }

  // Shape of finite joints.
  if (!finite) {
    std::string_view bad;
    if (const toml::node* n = first_present(t, kFiniteKeys, &bad))
      r.fail(*n, t.label(bad) + " applies to finite joints, and the set has no 'size'",
             "add size = { distribution = ..., ... }, or remove " + quote_key(bad) +
                 " for persistent planes");
  } else {
    if (const toml::node* n = t.find("shape"))
      s.shape = static_cast<JointShape>(to_choice(r, *n, t.label("shape"), kJointShapeNames));
    const bool takes_aspect = s.shape == JointShape::rectangle || s.shape == JointShape::ellipse;
    const bool takes_sides = s.shape == JointShape::polygon || s.shape == JointShape::ellipse;
    const std::string shape_name = to_string(s.shape);
    if (const toml::node* n = t.find("aspect")) {
      if (!takes_aspect)
        r.fail(*n,
               t.label("aspect") + " applies to rectangles and ellipses, not to a " + shape_name,
               "remove 'aspect', or set shape = \"rectangle\" or \"ellipse\"");
      s.aspect = to_number(r, *n, t.label("aspect"));
      if (!(s.aspect >= 1))
        r.fail(*n, t.label("aspect") + " is " + fmt(s.aspect) + ", below 1",
               "give long / short side (or diameter), >= 1; size is the long one");
    }
    if (s.shape == JointShape::ellipse) s.sides = 16;
    if (s.shape == JointShape::polygon)
      t.require("sides", "add sides = <number of corners>, e.g. 6 (a regular polygon)");
    if (const toml::node* n = t.find("sides")) {
      if (!takes_sides)
        r.fail(*n, t.label("sides") + " applies to polygons and ellipses, not to a " + shape_name,
               "remove 'sides', or set shape = \"polygon\" or \"ellipse\"");
      s.sides = to_integer(r, *n, t.label("sides"));
      if (s.sides < 3 || s.sides > kMaxSides)
        r.fail(*n,
               t.label("sides") + " is " + std::to_string(s.sides) + ", outside [3, " +
                   std::to_string(kMaxSides) + "]",
               "give the number of corners of the polygon, 3 to " + std::to_string(kMaxSides));
    }
    if (const toml::node* n = t.find("fit")) {
      if (s.shape != JointShape::ellipse)
        r.fail(*n, t.label("fit") + " applies to ellipses, not to a " + shape_name,
               "remove 'fit', or set shape = \"ellipse\"");
      s.fit = static_cast<EllipseFit>(to_choice(r, *n, t.label("fit"), kEllipseFitNames));
    }
    if (const toml::node* n = t.find("rotation")) {
      s.rotation_fixed = true;
      s.rotation_deg = to_number(r, *n, t.label("rotation"));
    }
  }

  // A set that would draw more joints than allowed is refused before anything is drawn.
  const double expect = expected_candidates(s, cx.box);
  if (!std::isfinite(expect))
    r.fail(in,
           t.label(ikey) + " cannot be reached: the scanline lies in the plane of the set's " +
               "joints, so none crosses it",
           "give a scanline across the joints, e.g. along their mean normal");
  if (expect > static_cast<double>(cx.max_joints))
    r.fail(in,
           ctx + " would draw about " + fmt(expect, 3) + " joints (" + std::string(ikey) + " = " +
               fmt(to_number(r, in, t.label(ikey))) +
               "), more than max_joints = " + std::to_string(cx.max_joints),
           "lower " + quote_key(ikey) + " (check its units), or raise max_joints in [scene]");
  return s;
}

// ---------------------------------------------------------------------------------------------
// Zones

// What a [[zones]] entry makes: removal regions and, for a tunnel with cut = true, the
// construction joints along its surface, all introduced at `place`.
struct ZoneEntry {
  std::vector<Region> regions;
  std::optional<TriangleMesh> mesh;
  std::filesystem::path mesh_file;
  std::vector<Joint> joints;
  EntryPlace place;
};

// A tunnel's cross-section: the regular polygon about its circle (radius, sides), or `outline`.
std::vector<Vec2> read_section(const Context& cx, const Tbl& t) {
  const Reader& r = t.r;
  const toml::node* radius = t.find("radius");
  const toml::node* outline = t.find("outline");
  if (radius && outline)
    r.fail(*outline, t.ctx + " gives both 'radius' and 'outline'",
           "keep one: radius (and sides) for a round tunnel, outline = [[u, v], ...] for any "
           "other section");
  if (!radius && !outline)
    r.fail(t.t, "missing key 'radius' (or 'outline') in " + t.ctx,
           "add radius = <the round tunnel's radius> (and sides = n, default " +
               std::to_string(kDefaultTunnelSides) +
               "), or outline = [[u, v], ...], the section in the tunnel's (u, v) frame");
  const std::string sides_fix = "give the number of sides of the polygon about the tunnel's " +
                                std::string("circle, 3 to ") + std::to_string(kMaxSides);
  if (radius) {
    const double inradius = positive(t, "radius", "give the tunnel's radius, a length > 0");
    std::int64_t sides = kDefaultTunnelSides;
    if (const toml::node* n = t.find("sides")) {
      sides = to_integer(r, *n, t.label("sides"));
      if (sides < 3 || sides > kMaxSides)
        r.fail(*n,
               t.label("sides") + " is " + std::to_string(sides) + ", outside [3, " +
                   std::to_string(kMaxSides) + "]",
               sides_fix);
    }
    return regular_outline(inradius, sides);
  }
  if (const toml::node* n = t.find("sides"))
    r.fail(*n, t.label("sides") + " applies to a round tunnel (radius), not to an outline",
           "remove 'sides': the outline's vertices are its corners");
  const auto* a = outline->as_array();
  if (!a)
    r.fail(*outline, t.label("outline") + " must be an array of [u, v], not " + type_name(*outline),
           "write outline = [[u1, v1], [u2, v2], ...]");
  if (a->size() > static_cast<std::size_t>(kMaxSides))
    r.fail(*outline,
           t.label("outline") + " has " + std::to_string(a->size()) + " vertices, more than " +
               std::to_string(kMaxSides),
           "give the section's corners, at most " + std::to_string(kMaxSides));
  std::vector<Vec2> uv;
  std::vector<const toml::node*> where;
  for (const auto& e : *a) {
    uv.push_back(to_vector<2>(
        r, e, "vertex " + std::to_string(uv.size() + 1) + " of " + t.label("outline")));
    where.push_back(&e);
  }
  if (const auto bad = check_outline(uv, cx.tol()))
    r.fail(bad->vertex ? *where[*bad->vertex] : *outline, t.label("outline") + " " + bad->what,
           bad->fix);
  return uv;
}

Tunnel read_tunnel(const Context& cx, const Tbl& zone, const toml::node& node) {
  const Reader& r = zone.r;
  const Tbl t{r,
              as_table(r, node, zone.label("tunnel"),
                       "write tunnel = { point = [x, y, z], direction = [dx, dy, dz], length = L, "
                       "radius = R }"),
              "'tunnel' of " + zone.ctx};
  t.check_keys(kTunnelKeys);
  Tunnel tun;
  tun.point = to_vector<3>(r, t.require("point", "add point = [x, y, z], where the axis starts"),
                           t.label("point"));
  const toml::node& dn =
      t.require("direction", "add direction = [dx, dy, dz], the axis direction from 'point'");
  const Vec3 d = to_vector<3>(r, dn, t.label("direction"));
  // Its squares may overflow (1e308) or underflow (1e-200) where the direction does not.
  const double len = std::isfinite(d.norm()) && d.norm() > 0 ? d.norm() : d.stableNorm();
  if (!(len > 0) || !std::isfinite(len))
    r.fail(dn, t.label("direction") + " is " + fmt(d) + ", which has no direction",
           "give the axis direction, e.g. [0, 1, 0] for a tunnel driven North");
  tun.direction = d / len;
  t.require("length", "add length = L, the tunnel's length along its axis from 'point'");
  tun.length = positive(t, "length", "give the tunnel's length along its axis, > 0");
  tun.outline = read_section(cx, t);
  // The sides lie about this far from the axis: their offsets must resolve the tolerance.
  double reach = 0;
  for (const Vec2& v : tun.outline) reach = std::max(reach, v.stableNorm());
  const double step = reach * std::numeric_limits<double>::epsilon();
  if (step > cx.tol())
    r.fail(t.find("radius") ? *t.find("radius") : *t.find("outline"),
           t.ctx + " reaches " + fmt(reach, 3) + " from its axis, where doubles step by " +
               fmt(step, 3) + ", coarser than the tolerance " + fmt(cx.tol(), 3) +
               " (tolerance x the domain's bounding radius)",
           "give the section in the scene's length unit; a box zone larger than the domain "
           "removes all of it");
  return tun;
}

// A cut tunnel's joints reach its ends: refused, as a domain far from the origin is, where
// doubles cannot resolve them (a tunnel 1e18 long through a 20 m cube cut nothing right).
void check_tunnel_precision(const Context& cx, const Tbl& zone, const toml::node& node,
                            const Tunnel& tun) {
  const TunnelFrame f = tunnel_frame(tun.direction);
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const double s : {0.0, tun.length})
    for (const Vec2& uv : tun.outline) {
      const Vec3 x = f.to_global(tun.point, uv, s);
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  if (const std::string why = precision_problem(lo, hi, cx.tol(), "the tunnel"); !why.empty())
    zone.r.fail(node, zone.label("tunnel") + " with cut = true: " + why,
                "shorten it to the part that crosses the domain (its joints span its whole "
                "length), or raise [scene] tolerance");
}

// True if one of the regions has volume inside the domain.
bool meets_domain(const Context& cx, std::span<const Region> regions) {
  return std::any_of(regions.begin(), regions.end(), [&](const Region& z) {
    std::vector<Plane> both = solid_region(z, cx.dimension);
    both.insert(both.end(), cx.box.planes.begin(), cx.box.planes.end());
    return analyse_polytope(both, cx.tol()).has_interior;
  });
}

// A [[zones]] mesh: a closed triangle mesh from an OBJ or STL file (relative paths from the
// scene's directory), checked; with `cut`, one construction joint per triangle in the domain.
void read_mesh_zone(const Context& cx, const Tbl& t, const toml::node& node, bool cut,
                    ZoneEntry& z) {
  const Reader& r = cx.r;
  const std::filesystem::path given = to_text(r, node, t.label("mesh"));
  const std::filesystem::path file = given.is_absolute() ? given : cx.dir / given;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    r.fail(node, t.label("mesh") + " names " + file.string() + ", which is not a file",
           "give the path of an OBJ or STL file, relative to the scene file's directory");
  TriangleMesh mesh;
  try {
    mesh = read_mesh(file);
    check_solid_mesh(mesh, file.string());
  } catch (const Error& e) {  // its own fix: one per line
    r.fail(node, t.label("mesh") + ": " + e.where() + ": " + e.problem(), e.fix());
  }
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const Vec3& x : mesh.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const Region box{{{Vec3::UnitX(), hi.x()},
                    {-Vec3::UnitX(), -lo.x()},
                    {Vec3::UnitY(), hi.y()},
                    {-Vec3::UnitY(), -lo.y()},
                    {Vec3::UnitZ(), hi.z()},
                    {-Vec3::UnitZ(), -lo.z()}}};
  if (!meets_domain(cx, std::span<const Region>(&box, 1)))
    r.fail(node, t.ctx + "'s mesh has no volume inside the domain, so it would remove nothing",
           "check the mesh's coordinates against the domain (same frame and unit)");
  if (cut)
    for (const auto& tri : mesh.triangles) {
      const std::vector<Vec3> corners{mesh.vertices[std::size_t(tri[0])],
                                      mesh.vertices[std::size_t(tri[1])],
                                      mesh.vertices[std::size_t(tri[2])]};
      if (!face_misses_domain(corners, cx.box.planes, cx.tol()))
        z.joints.push_back(construction_face_joint(corners));
    }
  z.mesh = std::move(mesh);
  z.mesh_file = file;
}

// A [[zones]] entry: box, planes or tunnel. `default_stage` is the stage of a cut tunnel's
// joints without `stage`; `entry` orders entries on one line (EntryPlace).
ZoneEntry read_zone(const Context& cx, const toml::table& tt, std::size_t index,
                    std::int64_t default_stage, std::int64_t entry) {
  const Reader& r = cx.r;
  const Tbl t{r, tt, "[[zones]] #" + std::to_string(index + 1)};
  t.check_keys(kZoneKeys);
  ZoneEntry z;
  const toml::node* tunnel = t.find("tunnel");
  const toml::node* mesh = t.find("mesh");
  const toml::node* stage = t.find("stage");
  std::string_view which;
  bool in_domain = false;
  if (!tunnel && !mesh) {
    if (const toml::node* n =
            first_present(t, std::array<std::string_view, 2>{"cut", "stage"}, &which))
      r.fail(*n, t.label(which) + " applies to tunnel and mesh zones only",
             "remove " + quote_key(which) + ", or give the zone as tunnel = { ... } or mesh");
    if (!t.find("box") && !t.find("planes"))
      r.fail(tt, t.ctx + " has none of 'box', 'planes', 'tunnel' and 'mesh'",
             "add box = { min = [x, y, z], max = [x, y, z] }, planes = [ { normal = [nx, ny, "
             "nz], d = d }, ... ], tunnel = { point = [x, y, z], direction = [dx, dy, dz], "
             "length = L, radius = R } or mesh = \"cavern.obj\"");
    z.regions.push_back(region_of(t, cx.dimension));
    in_domain = meets_domain(cx, z.regions);
  } else {
    const std::string_view kind = tunnel ? "tunnel" : "mesh";
    if (cx.dimension == 2)
      r.fail(tunnel ? *tunnel : *mesh, t.ctx + ": a " + std::string(kind) + " zone is 3-D",
             "in a 2-D scene give the zone as box = { min = [x, z], max = [x, z] } or planes");
    if (const toml::node* n = first_present(t, kRegionKeys, &which))
      r.fail(*n, t.ctx + " gives both " + quote_key(kind) + " and " + quote_key(which),
             "keep one of them");
    if (tunnel && mesh)
      r.fail(*mesh, t.ctx + " gives both 'tunnel' and 'mesh'", "keep one of them");
    bool cut = false;
    if (const toml::node* n = t.find("cut")) {
      const auto* b = n->as_boolean();
      if (!b)
        r.fail(*n, t.label("cut") + " must be true or false, not " + type_name(*n),
               "write cut = true to cut the zone's surface into the rock before removal");
      cut = b->get();
    }
    if (stage && !cut)
      r.fail(*stage,
             t.label("stage") + " applies with cut = true: without it the zone adds no joints",
             "add cut = true, or remove 'stage'");
    if (mesh) {
      read_mesh_zone(cx, t, *mesh, cut, z);
      z.place = read_place(r, tt, t.ctx, entry);
      if (!stage) z.place.stage = default_stage;
      return z;
    }
    const Tunnel tun = read_tunnel(cx, t, *tunnel);
    if (cut) check_tunnel_precision(cx, t, *tunnel, tun);
    z.regions = tunnel_regions(tun, cx.tol());
    if (cut) z.joints = tunnel_joints(tun, cx.box.planes, cx.tol());
    // The fan's prisms have a few planes each; a convex region of up to 1000 sides is too many
    // for analyse_polytope (O(planes^4)).
    in_domain = meets_domain(cx, tunnel_fan(tun, 0));
  }
  // A zone may be unbounded (e.g. "everything above z = 50"): only its part inside the domain
  // matters, and that must have volume, else it removes nothing and is surely a slip.
  if (!in_domain)
    r.fail(tt, t.ctx + " has no volume inside the domain, so it would remove nothing",
           "check its coordinates against the domain (and that plane normals point out of "
           "the zone)");
  z.place = read_place(r, tt, t.ctx, entry);
  if (!stage) z.place.stage = default_stage;
  return z;
}

// [scene]: name, seed, max_joints, tolerance.
void read_scene_table(const Reader& r, const toml::table& st, Scene& scene) {
  const Tbl t{r, st, "[scene]"};
  t.check_keys(kSceneKeys);
  if (const toml::node* n = t.find("name")) scene.name = to_text(r, *n, t.label("name"));
  if (const toml::node* n = t.find("seed")) {
    const auto* i = n->as_integer();
    if (!i)
      r.fail(*n, t.label("seed") + " must be an integer, not " + type_name(*n),
             "write a whole number >= 0 without quotes or decimals");
    if (i->get() < 0)
      r.fail(*n, t.label("seed") + " is " + std::to_string(i->get()) + ", below 0",
             "give a seed >= 0");
    scene.seed = static_cast<std::uint64_t>(i->get());
  }
  if (const toml::node* n = t.find("max_joints")) {
    scene.max_joints = to_integer(r, *n, t.label("max_joints"));
    if (scene.max_joints < 1)
      r.fail(*n, t.label("max_joints") + " is " + std::to_string(scene.max_joints) + ", below 1",
             "give the most joints one stochastic set may draw, >= 1 (default " +
                 std::to_string(kDefaultMaxJoints) + ")");
  }
  if (const toml::node* n = t.find("dimension")) {
    const std::int64_t d = to_integer(r, *n, t.label("dimension"));
    if (d != 2 && d != 3)
      r.fail(*n, t.label("dimension") + " is " + std::to_string(d) + ", not 2 or 3",
             "write dimension = 2 for a section in (x, z) (docs/2d.md), or leave it out for 3-D");
    scene.dimension = static_cast<int>(d);
  }
  scene.options.tolerance = number(t, "tolerance", 1e-9);
  if (!(scene.options.tolerance > 0 && scene.options.tolerance < 1))
    r.fail(*t.find("tolerance"),
           t.label("tolerance") + " is " + fmt(scene.options.tolerance) + ", outside (0, 1)",
           "give a small positive number relative to the domain size, e.g. 1e-9");
}

// [rock]: friction_angle, cohesion, tension of intact rock.
void read_rock(const Reader& r, const toml::table& rt, Scene& scene) {
  const Tbl t{r, rt, "[rock]"};
  t.check_keys(kRockKeys);
  scene.rock.given = true;
  scene.rock.friction_angle_deg = number(t, "friction_angle", 30);
  check_range(t, "friction_angle", scene.rock.friction_angle_deg, 0, 90, true,
              "give the friction angle in degrees, 0 <= friction_angle < 90");
  scene.rock.cohesion = stress(t, "cohesion", 0);
  scene.rock.tension = stress(t, "tension", 0);
}

// [options]: order, limits, max_blocks, fixed_faces, slivers.
void read_options(const Reader& r, const toml::table& ot, Scene& scene) {
  const Tbl t{r, ot, "[options]"};
  t.check_keys(kOptionKeys);
  if (const toml::node* n = t.find("order"))
    scene.options.order =
        static_cast<JointOrder>(to_choice(r, *n, t.label("order"), kJointOrderNames));
  const double dmin = number(t, "min_inscribed_diameter", 0);
  if (dmin < 0)
    r.fail(*t.find("min_inscribed_diameter"),
           t.label("min_inscribed_diameter") + " is " + fmt(dmin) + ", below 0",
           "give a length >= 0 (0: no size limit)");
  scene.options.min_inscribed_diameter = dmin;
  const double amax = number(t, "max_aspect_ratio", 0);
  if (amax < 0 || (amax > 0 && amax < 1))
    r.fail(*t.find("max_aspect_ratio"),
           t.label("max_aspect_ratio") + " is " + fmt(amax) + "; it must be 0 (none) or >= 1",
           "give 0 for no shape limit, or a ratio >= 1 (bounding radius / inscribed radius)");
  scene.options.max_aspect_ratio = amax;
  if (const toml::node* n = t.find("slivers"))
    scene.options.slivers =
        static_cast<SliverRule>(to_choice(r, *n, t.label("slivers"), kSliverRuleNames));
  if (const toml::node* n = t.find("max_blocks")) {
    scene.options.max_blocks = to_integer(r, *n, t.label("max_blocks"));
    if (scene.options.max_blocks < 1)
      r.fail(
          *n,
          t.label("max_blocks") + " is " + std::to_string(scene.options.max_blocks) + ", below 1",
          "give the most blocks slice-cut may make, >= 1 (default " +
              std::to_string(kDefaultMaxBlocks) + ")");
  }
  if (const toml::node* n = t.find("fixed_faces")) {
    const std::string label = t.label("fixed_faces");
    const auto* a = n->as_array();
    if (!a)
      r.fail(*n, label + " must be an array of face names, not " + type_name(*n),
             "write e.g. fixed_faces = [\"-z\", \"+x\"]");
    for (const toml::node& f : *a) {
      const std::size_t k = to_choice(r, f, label, kBoxFaceNames);
      if (scene.dimension == 2 && (k == 2 || k == 3))
        r.fail(f, label + " names \"" + std::string(kBoxFaceNames[k]) + "\" in a 2-D scene",
               "a section in (x, z) has the faces -x, +x, -z and +z");
      if (scene.options.fixed_faces & (1u << k))
        r.fail(f, label + " names \"" + std::string(kBoxFaceNames[k]) + "\" twice",
               "name each face once");
      scene.options.fixed_faces |= static_cast<std::uint8_t>(1u << k);
    }
  }
}

}  // namespace

std::vector<SceneKeys> scene_keys() {
  const auto list = [](Keys keys) {
    return std::vector<std::string_view>(keys.begin(), keys.end());
  };
  // `size` takes the keys of its distribution: all of them, each once.
  std::vector<std::string_view> size;
  for (const Keys keys :
       {Keys(kFixedKeys), Keys(kLognormalKeys), Keys(kExponentialKeys), Keys(kPowerLawKeys)})
    for (const auto& k : keys)
      if (std::find(size.begin(), size.end(), k) == size.end()) size.push_back(k);
  return {{"", "", list(kTopTables)},
          {"scene", "", list(kSceneKeys)},
          {"domain", "", list(kRegionKeys)},
          {"domain", "box", list(kBoxKeys)},
          {"domain", "planes", list(kPlaneKeys)},
          {"options", "", list(kOptionKeys)},
          {"joints", "", list(kJointKeys)},
          {"sets", "", list(kSetKeys)},
          {"sets", "size", std::move(size)},
          {"sets", "scanline", list(kScanlineKeys)},
          {"zones", "", list(kZoneKeys)},
          {"zones", "box", list(kBoxKeys)},
          {"zones", "planes", list(kPlaneKeys)},
          {"zones", "tunnel", list(kTunnelKeys)},
          {"rock", "", list(kRockKeys)}};
}

Scene parse_scene(const std::string& text, const std::filesystem::path& name) {
  const std::string file = name.string();
  const Reader r(file);
  toml::table root;
  // The text with the characters toml++ 3.3 cannot take moved out of its way (shelter).
  const std::string safe = shelter(text, false, [&](char32_t c, std::size_t at) {
    char code[16];
    std::snprintf(code, sizeof code, "U+%05X", static_cast<unsigned>(c));
    toml::source_region where{};
    where.begin.line = static_cast<toml::source_index>(
        1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    r.fail(where, std::string("character ") + code + " (private use) is not accepted in a scene",
           "remove it");
  });
  try {
    root = toml::parse(std::string_view(safe), std::string_view(file));
  } catch (const toml::parse_error& e) {
    r.fail(e.source(), "TOML syntax error: " + std::string(e.description()),
           "fix the syntax on this line (see https://toml.io)");
  }

  // Top level: only the known tables, each of its kind.
  const toml::key* bad = nullptr;
  for (auto&& [k, v] : root)
    if (std::find(kTopTables.begin(), kTopTables.end(), k.str()) == kTopTables.end())
      if (!bad || k.source().begin.line < bad->source().begin.line) bad = &k;
  if (bad) {
    const toml::node& v = *root.get(bad->str());
    const bool is_array = v.is_array_of_tables();
    auto form = [](std::string_view n) {
      const bool arr = n == "joints" || n == "sets" || n == "zones";
      return (arr ? "[[" : "[") + std::string(n) + (arr ? "]]" : "]");
    };
    const std::string near = closest(bad->str(), kTopTables);
    std::string home;  // a key of a table written outside it: say which table
    const std::pair<std::string_view, Keys> homes[] = {
        {"[scene]", kSceneKeys}, {"[domain]", kRegionKeys}, {"[options]", kOptionKeys}};
    for (const auto& [table, keys] : homes)
      if (!v.is_table() && !is_array &&
          std::find(keys.begin(), keys.end(), bad->str()) != keys.end())
        home = table;
    const std::string what = v.is_table() ? "unknown table [" + std::string(bad->str()) + "]"
                             : is_array
                                 ? "unknown table [[" + std::string(bad->str()) + "]]"
                                 : "unknown key " + quote_key(bad->str()) + " outside any table";
    std::string known;
    for (const auto& k : kTopTables) known += (known.empty() ? "" : ", ") + form(k);
    r.fail(bad->source(), what,
           !home.empty()  ? "put it under " + home
           : near.empty() ? "the tables of a scene are " + known
                          : "did you mean " + form(near) + "?");
  }
  auto single = [&](std::string_view key) -> const toml::table* {
    const toml::node* n = root.get(key);
    if (!n) return nullptr;
    const std::string s(key);
    return &as_table(r, *n, "[" + s + "]", "write it as a table: a line [" + s + "] and its keys");
  };
  auto multi = [&](std::string_view key) {
    const toml::node* n = root.get(key);
    if (!n) return std::vector<const toml::table*>{};
    const std::string s(key);
    if (n->is_table())
      r.fail(*n, "[" + s + "] must be an array of tables, [[" + s + "]]",
             "write [[" + s + "]] (double brackets) before each entry");
    return table_array(r, *n, "'" + s + "'", "write [[" + s + "]] before each entry");
  };

  Scene scene;
  scene.source = name;
  scene.name = name.stem().string();
  if (const toml::table* st = single("scene")) read_scene_table(r, *st, scene);

  // Domain first: every tolerance below scales with its size.
  const toml::table* dt = single("domain");
  if (!dt)
    r.fail(root, "the scene has no [domain]",
           "add [domain] with box = { min = [x, y, z], max = [x, y, z] } or planes = [...]");
  const Tbl dtbl{r, *dt, "[domain]"};
  scene.domain = read_region(dtbl, scene.dimension);
  const Region solid{solid_region(scene.domain, scene.dimension)};
  Context cx{r, scene.dimension,
             analyse_region(solid.planes, scene.options.tolerance, scene.dimension),
             scene.options.tolerance};
  cx.dir = name.parent_path();
  {
    const toml::node& at = dt->get("planes") ? *dt->get("planes") : *dt;
    if (cx.domain_info.status == RegionStatus::unbounded)
      r.fail(at, "the 'planes' of [domain] do not enclose a bounded region",
             "add planes (outward normals, normal . x <= d inside) that close it in every "
             "direction");
    if (cx.domain_info.status == RegionStatus::empty && dt->get("box")) {
      // min < max on every axis (region_of): only the tolerance flattens a box.
      Vec3 size = Vec3::Zero();  // box_planes: axis normals, the two d of an axis add up
      for (const Plane& p : scene.domain.planes) size += p.d * p.normal.cwiseAbs();
      int thin = 0;  // the thinnest axis (a section has no y)
      (scene.dimension == 2 ? Vec3(size.x(), INFINITY, size.z()) : size).minCoeff(&thin);
      const double scale = 0.5 * size.norm(), tol = scene.options.tolerance * scale;
      r.fail(
          *dt->get("box"),
          "the 'box' of [domain] is only " + fmt(size(thin), 4) + " thick in " +
              std::string(1, "xyz"[thin]) + ": the tolerance, " + fmt(scene.options.tolerance, 4) +
              " x the length scale " + fmt(scale, 4) + " = " + fmt(tol, 4) +
              ", leaves it no volume",
          "make the box thicker than a few times " + fmt(tol, 4) + ", or lower [scene] tolerance");
    }
    if (cx.domain_info.status == RegionStatus::empty)
      r.fail(at,
             "the 'planes' of [domain] enclose no volume (the half-spaces normal . x <= d "
             "have no common interior)",
             "check that every normal points outward and every d puts the plane on the "
             "domain's face");
  }
  if (const std::string why =
          precision_problem(cx.domain_info.info.min, cx.domain_info.info.max, cx.tol());
      !why.empty())
    r.fail(*dt, "[domain]: " + why,
           "move the scene nearer the origin (subtract a local origin from every coordinate) or "
           "raise [scene] tolerance");
  cx.box = domain_box(solid, cx.domain_info, scene.options.tolerance);
  cx.max_joints = scene.max_joints;

  if (const toml::table* ot = single("options")) read_options(r, *ot, scene);
  if (const toml::table* rt = single("rock")) read_rock(r, *rt, scene);

  const auto joints = multi("joints");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    scene.joints.push_back(read_joint(cx, *joints[i], i));
    scene.joint_places.push_back(read_place(r, *joints[i], "[[joints]] #" + std::to_string(i + 1),
                                            static_cast<std::int64_t>(i)));
  }

  std::set<std::string> names;
  const auto sets = multi("sets");
  for (std::size_t i = 0; i < sets.size(); ++i) {
    scene.sets.push_back(read_set(cx, *sets[i], i, names));
    scene.set_places.push_back(read_place(r, *sets[i],
                                          "[[sets]] \"" + scene.sets.back().name + "\"",
                                          static_cast<std::int64_t>(joints.size() + i)));
  }

  // A cut tunnel's joints come after every [[joints]] and [[sets]] entry unless given a stage:
  // the paper's order, construction joints after the rock joints (section 3.4).
  std::int64_t last_stage = 0;
  for (const auto* places : {&scene.joint_places, &scene.set_places})
    for (const EntryPlace& p : *places) last_stage = std::max(last_stage, p.stage);
  const auto zones = multi("zones");
  for (std::size_t i = 0; i < zones.size(); ++i) {
    ZoneEntry z = read_zone(cx, *zones[i], i, last_stage + 1,
                            static_cast<std::int64_t>(joints.size() + sets.size() + i));
    std::move(z.regions.begin(), z.regions.end(), std::back_inserter(scene.zones));
    if (z.mesh) {
      scene.zone_meshes.push_back(std::move(*z.mesh));
      scene.mesh_files.push_back(z.mesh_file);
    }
    for (Joint& j : z.joints) {
      scene.joints.push_back(std::move(j));
      scene.joint_places.push_back(z.place);
    }
  }
  return scene;
}

Scene load_scene(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec))
    throw Error(file.string(), "scene file not found", "check the path");
  if (std::filesystem::is_directory(file, ec))
    throw Error(file.string(), "is a directory, not a scene file", "give the .toml file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string(), "cannot open the scene file", "check its permissions");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw Error(file.string(), "reading the scene file failed", "check the file");
  return parse_scene(text, file);
}

JointSystem generate_joints(const Scene& scene) {
  JointSystem js;
  js.name = scene.name;
  js.seed = scene.seed;
  js.dimension = scene.dimension;
  js.domain = scene.domain;
  js.options = scene.options;
  js.sets = scene.sets;
  js.rock = scene.rock;
  js.zones = scene.zones;
  js.zone_meshes = scene.zone_meshes;
  const std::string where = scene.source.string();
  const Region solid{solid_region(scene.domain, scene.dimension)};
  const RegionAnalysis dom = analyse_region(solid.planes, scene.options.tolerance, scene.dimension);
  if (dom.status != RegionStatus::ok)
    throw Error(where,
                dom.status == RegionStatus::unbounded ? "the domain is unbounded"
                                                      : "the domain has no volume",
                "give a bounded domain with an interior (load the scene with load_scene)");
  js.length_scale = dom.length_scale;
  const double tol = scene.options.tolerance * dom.length_scale;
  if (const std::string why = precision_problem(dom.info.min, dom.info.max, tol); !why.empty())
    throw Error(where, why, "move the scene nearer the origin or raise its tolerance");
  const Vec3 mean = dom.info.interior_point;  // the domain's vertex mean
  const DomainBox box = domain_box(solid, dom, scene.options.tolerance);

  // [[joints]], then the sets; order_joints then puts them in sequence. A joint that misses the
  // domain entirely is kept: the slicer finds that it cuts nothing.
  // place[i]: the entry joint i comes from. A Scene built in code may have no places: then each
  // [[joints]] entry is its own entry, all before the sets (group 0, then 1), as order_joints
  // without places has it.
  std::vector<EntryPlace> place;
  const auto place_of = [](const std::vector<EntryPlace>& places, std::size_t i,
                           std::int64_t group) {
    return i < places.size() ? places[i] : EntryPlace{1, group, static_cast<std::int64_t>(i)};
  };
  for (std::size_t i = 0; i < scene.joints.size(); ++i) {
    js.joints.push_back(scene.joints[i]);
    js.joints.back().set = -1;
    place.push_back(place_of(scene.joint_places, i, 0));
  }
  for (std::size_t s = 0; s < js.sets.size(); ++s) {
    JointSetSpec& spec = js.sets[s];
    const Vec3 n = dip_normal(spec.dip_deg, spec.dip_direction_deg, scene.dimension);
    if (!spec.scanline_given) std::tie(spec.scanline_from, spec.scanline_to) = chord(box, mean, n);
    const std::size_t first = js.joints.size();
    if (spec.intensity != SetIntensity::spacing) {
      std::vector<Joint> joints =
          generate_stochastic_set(spec, s, scene.seed, box, scene.max_joints, where);
      std::move(joints.begin(), joints.end(), std::back_inserter(js.joints));
    } else {
      if (!(spec.spacing > 0) || !std::isfinite(spec.spacing) || !std::isfinite(spec.offset))
        throw Error(where,
                    "set \"" + spec.name + "\" has spacing " + fmt(spec.spacing) + " and offset " +
                        fmt(spec.offset),
                    "give a finite spacing > 0 and a finite offset");
      const auto [lo, hi] = extent_along(dom.info.vertices, n);
      if ((hi - lo) / spec.spacing > kMaxPlanesPerSet)
        throw Error(
            where,
            "set \"" + spec.name + "\" would have more than " + fmt(kMaxPlanesPerSet) + " planes",
            "check the units of spacing and of the domain");
      const std::vector<double> planes = set_planes(spec, n, dom.info.vertices, tol);
      for (const double c : planes) {
        Joint j;
        j.plane = {n, c};
        j.centre = mean - (n.dot(mean) - c) * n;  // the vertex mean projected on the plane
        j.dip_deg = spec.dip_deg;
        j.dip_direction_deg = spec.dip_direction_deg;
        j.kind = spec.kind;
        j.set = static_cast<std::int32_t>(s);
        j.friction_angle_deg = spec.friction_angle_deg;
        j.cohesion = spec.cohesion;
        j.tension = spec.tension;
        j.limits = spec.limits;
        j.boundary_side = spec.boundary_side;
        js.joints.push_back(std::move(j));
      }
      spec.stream_seed = set_stream_seed(scene.seed, s);  // recorded, though unused
      spec.candidates = static_cast<std::int64_t>(planes.size());
    }
    std::vector<const Joint*> mine;
    for (std::size_t i = first; i < js.joints.size(); ++i) mine.push_back(&js.joints[i]);
    measure_set(spec, mine, box);
    place.resize(js.joints.size(), place_of(scene.set_places, s, 1));
  }
  order_joints(js.joints, scene.options.order, place);
  return js;
}

std::vector<Vec3> joint_polygon(const Joint& j) {
  std::vector<Vec3> p;
  if (j.persistent()) return p;
  const JointFrame f = plane_frame(j.dip_deg, j.dip_direction_deg);
  for (const Vec2& uv : j.polygon_uv) p.push_back(f.to_global(j.centre, uv));
  return p;
}

double polygon_area(const Joint& j) {
  if (j.persistent()) return std::numeric_limits<double>::infinity();
  const auto& p = j.polygon_uv;
  double a = 0;  // shoelace formula
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& q = p[i];
    const Vec2& r = p[(i + 1) % p.size()];
    a += q.x() * r.y() - q.y() * r.x();
  }
  return 0.5 * std::abs(a);
}

void order_joints(std::vector<Joint>& joints, JointOrder order, std::span<const EntryPlace> place) {
  if (place.size() != joints.size())
    throw std::invalid_argument("order_joints: one place per joint expected");
  const auto key = [&](std::size_t i) {
    return std::make_tuple(place[i].stage, place[i].line, place[i].entry);
  };
  std::vector<std::size_t> idx(joints.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  // Stages in order, each stage's entries in file order, a set's joints as generated.
  std::stable_sort(idx.begin(), idx.end(),
                   [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  if (order == JointOrder::as_given || order == JointOrder::by_set) {
    // by-set is the same sequence: every entry (a set or a single joint) in one piece.
  } else {
    std::vector<double> area(joints.size());
    for (std::size_t i = 0; i < joints.size(); ++i) area[i] = polygon_area(joints[i]);
    const auto larger = [&](std::size_t a, std::size_t b) { return area[a] > area[b]; };
    std::vector<std::size_t> out;
    out.reserve(idx.size());
    for (auto stage = idx.begin(); stage != idx.end();) {
      const auto end = std::find_if(
          stage, idx.end(), [&](std::size_t i) { return place[i].stage != place[*stage].stage; });
      if (order == JointOrder::largest_first) {
        std::stable_sort(stage, end, larger);
        out.insert(out.end(), stage, end);
      } else {  // alternating: one joint of each entry in turn, each entry largest first
        std::vector<std::vector<std::size_t>> groups;
        for (auto it = stage; it != end; ++it) {
          if (groups.empty() || key(groups.back().front()) != key(*it)) groups.emplace_back();
          groups.back().push_back(*it);
        }
        std::size_t longest = 0;
        for (auto& g : groups) {
          std::stable_sort(g.begin(), g.end(), larger);
          longest = std::max(longest, g.size());
        }
        for (std::size_t round = 0; round < longest; ++round)
          for (const auto& g : groups)
            if (round < g.size()) out.push_back(g[round]);
      }
      stage = end;
    }
    idx = std::move(out);
  }
  std::vector<Joint> sorted;
  sorted.reserve(joints.size());
  for (const std::size_t i : idx) sorted.push_back(std::move(joints[i]));
  joints = std::move(sorted);
}

void order_joints(std::vector<Joint>& joints, JointOrder order) {
  if (order == JointOrder::as_given) return;
  std::vector<EntryPlace> place(joints.size());
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const auto n = static_cast<std::int64_t>(i);
    if (order == JointOrder::largest_first || joints[i].set < 0)
      place[i] = {1, 0, n};  // ties in the given order; a single joint is its own entry
    else
      place[i] = {1, 1, std::int64_t{joints[i].set}};  // the sets after, by index
  }
  order_joints(joints, order, place);
}

}  // namespace slice

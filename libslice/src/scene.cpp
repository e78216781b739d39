#include "slice/scene.hpp"

#include <toml++/toml.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <string_view>
#include <utility>

#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/polytope.hpp"

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

namespace {

using Keys = std::span<const std::string_view>;

// The keys of each table of a scene file (DESIGN section 6).
constexpr std::array<std::string_view, 6> kTopTables = {"scene",  "domain", "options",
                                                        "joints", "sets",   "zones"};
constexpr std::array<std::string_view, 3> kSceneKeys = {"name", "seed", "tolerance"};
constexpr std::array<std::string_view, 2> kRegionKeys = {"box", "planes"};
constexpr std::array<std::string_view, 2> kBoxKeys = {"min", "max"};
constexpr std::array<std::string_view, 2> kPlaneKeys = {"normal", "d"};
constexpr std::array<std::string_view, 3> kOptionKeys = {"order", "min_inscribed_diameter",
                                                         "max_aspect_ratio"};
constexpr std::array<std::string_view, 9> kJointKeys = {
    "dip",  "dip_direction",  "point",    "polygon", "polygon_uv",
    "kind", "friction_angle", "cohesion", "keep"};
constexpr std::array<std::string_view, 9> kSetKeys = {
    "name", "dip",  "dip_direction",  "spacing", "offset",
    "kind", "keep", "friction_angle", "cohesion"};
// Keys of stochastic sets (DESIGN section 8): recognised, so that they get a clear "not yet"
// rather than "unknown key", until the issue that implements them.
constexpr std::array<std::string_view, 8> kStochasticKeys = {
    "fisher_kappa", "density", "p32", "p10", "scanline", "count", "size", "shape"};

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

// Reads one scene file; every error names "<file>:<line>", the key, its table and a fix.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  std::string where(const toml::source_region& s) const {
    return s.begin.line == 0 ? file_ : file_ + ":" + std::to_string(s.begin.line);
  }
  [[noreturn]] void fail(const toml::source_region& s, const std::string& what,
                         const std::string& fix) const {
    throw Error(where(s), what, fix);
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

  // Refuses unknown keys (the first in the file), suggesting the closest known one, and the
  // keys of features not implemented yet (`refused`).
  void check_keys(Keys known, Keys refused = {}) const {
    const toml::key* bad = nullptr;
    for (auto&& [k, v] : t) {
      const bool ok = std::find(known.begin(), known.end(), k.str()) != known.end();
      if (ok) continue;
      if (!bad || k.source().begin.line < bad->source().begin.line) bad = &k;
    }
    if (!bad) return;
    const std::string_view k = bad->str();
    if (std::find(refused.begin(), refused.end(), k) != refused.end())
      r.fail(bad->source(),
             quote_key(k) + " (stochastic joint sets) is not supported yet, in " + ctx,
             "give the set a regular 'spacing' (and 'offset'), or list its joints one by one "
             "as [[joints]]");
    std::vector<std::string_view> all(known.begin(), known.end());
    all.insert(all.end(), refused.begin(), refused.end());
    const std::string near = closest(k, all);
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
  return s->get();
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
RegionAnalysis analyse_region(std::span<const Plane> planes, double rel) {
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
  a.length_scale = 0.5 * (a.info.max - a.info.min).norm();
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

// The planes n . x = offset + k * spacing of a set that pass through the domain's interior:
// lo + tol < c < hi - tol, so a plane on a domain face (or within tol of it) is not generated.
std::vector<double> set_planes(const JointSetSpec& s, const std::vector<Vec3>& vertices,
                               double tol) {
  const Vec3 n = normal_from_dip(s.dip_deg, s.dip_direction_deg);
  const auto [lo, hi] = extent_along(vertices, n);
  std::vector<double> c;
  const double k0 = std::ceil((lo + tol - s.offset) / s.spacing) - 1;
  const double k1 = std::floor((hi - tol - s.offset) / s.spacing) + 1;
  for (double k = k0; k <= k1; k += 1) {
    const double ck = s.offset + k * s.spacing;
    if (lo + tol < ck && ck < hi - tol) c.push_back(ck);
  }
  return c;
}

Region read_region(const Tbl& t) {
  const Reader& r = t.r;
  t.check_keys(kRegionKeys);
  const toml::node* box = t.find("box");
  const toml::node* planes = t.find("planes");
  const std::string both =
      "box = { min = [x, y, z], max = [x, y, z] } or planes = [ { normal = [nx, ny, nz], d = d "
      "}, ... ] (outward normals, normal . x <= d inside)";
  if (box && planes) r.fail(*planes, t.ctx + " gives both 'box' and 'planes'", "keep one of them");
  if (!box && !planes) r.fail(t.t, t.ctx + " has neither 'box' nor 'planes'", "add " + both);
  Region region;
  if (box) {
    const Tbl b{
        r, as_table(r, *box, t.label("box"), "write box = { min = [x, y, z], max = [x, y, z] }"),
        "'box' of " + t.ctx};
    b.check_keys(kBoxKeys);
    const Vec3 mn =
        to_vector<3>(r, b.require("min", "add min = [x, y, z], the lower corner"), b.label("min"));
    const Vec3 mx =
        to_vector<3>(r, b.require("max", "add max = [x, y, z], the upper corner"), b.label("max"));
    for (int i = 0; i < 3; ++i)
      if (!(mn(i) < mx(i))) {
        const std::string axis(1, "xyz"[i]);
        r.fail(*b.find("max"),
               "'box' of " + t.ctx + " has min " + axis + " = " + fmt(mn(i)) + " >= max " + axis +
                   " = " + fmt(mx(i)),
               "make min the lower corner and max the upper corner, min < max in every axis");
      }
    region.planes = box_planes(mn, mx);
    return region;
  }
  const auto elems = table_array(r, *planes, t.label("planes"), "write " + both);
  if (elems.empty()) r.fail(*planes, t.label("planes") + " is empty", "write " + both);
  for (std::size_t i = 0; i < elems.size(); ++i) {
    const Tbl p{r, *elems[i], "plane #" + std::to_string(i + 1) + " of " + t.ctx};
    p.check_keys(kPlaneKeys);
    const toml::node& nn = p.require("normal", "add normal = [nx, ny, nz], pointing outward");
    const Vec3 n = to_vector<3>(r, nn, p.label("normal"));
    const double d = required_number(p, "d", "add d, so that the plane is normal . x = d");
    const double len = n.norm();
    if (!(len > 0) || !std::isfinite(len))
      r.fail(nn, p.label("normal") + " is " + fmt(n) + ", which has no direction",
             "give the plane's outward normal, e.g. [0, 0, 1] for a top face");
    // Unit normals: scale d with the normal, so that the half-space itself does not change.
    region.planes.push_back({n / len, d / len});
  }
  return region;
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
  RegionAnalysis domain_info;
  double rel_tol = 1e-9;
  double tol() const { return rel_tol * domain_info.length_scale; }
};

constexpr char kDipFix[] =
    "dip is measured down from the horizontal, 0 to 90 degrees (a plane dipping more than 90 "
    "is the same plane with dip 180 - dip and dip direction +- 180)";
constexpr char kDipDirectionFix[] =
    "give the dip direction clockwise from North in [0, 360) (e.g. 360 -> 0, -30 -> 330)";

struct Common {  // what [[joints]] and [[sets]] share
  double dip = 0, dip_direction = 0, friction = 30, cohesion = 0;
  JointKind kind = JointKind::rock;
  std::int8_t side = 0;
};

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
  if (const toml::node* k = t.find("kind"))
    c.kind = static_cast<JointKind>(to_choice(t.r, *k, t.label("kind"), kJointKindNames));
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
  j.boundary_side = c.side;
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
  t.check_keys(kSetKeys, kStochasticKeys);
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
  s.boundary_side = c.side;
  s.spacing = required_number(t, "spacing",
                              "add spacing = <distance between the set's planes> (stochastic "
                              "sets are not supported yet)");
  if (!(s.spacing > 0))
    r.fail(*t.find("spacing"), t.label("spacing") + " is " + fmt(s.spacing) + ", not > 0",
           "give the distance between the set's planes, a positive length");
  s.offset = number(t, "offset", 0);
  const Vec3 n = normal_from_dip(s.dip_deg, s.dip_direction_deg);
  const auto [lo, hi] = extent_along(cx.domain_info.info.vertices, n);
  if ((hi - lo) / s.spacing > kMaxPlanesPerSet)
    r.fail(*t.find("spacing"),
           t.label("spacing") + " = " + fmt(s.spacing) + " gives about " +
               fmt(std::round((hi - lo) / s.spacing)) + " planes across the domain, more than " +
               fmt(kMaxPlanesPerSet),
           "check the units of spacing and of the domain");
  return s;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::filesystem::path& name) {
  const std::string file = name.string();
  const Reader r(file);
  toml::table root;
  try {
    root = toml::parse(std::string_view(text), std::string_view(file));
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
  if (const toml::table* st = single("scene")) {
    const Tbl t{r, *st, "[scene]"};
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
    scene.options.tolerance = number(t, "tolerance", 1e-9);
    if (!(scene.options.tolerance > 0 && scene.options.tolerance < 1))
      r.fail(*t.find("tolerance"),
             t.label("tolerance") + " is " + fmt(scene.options.tolerance) + ", outside (0, 1)",
             "give a small positive number relative to the domain size, e.g. 1e-9");
  }

  // Domain first: every tolerance below scales with its size.
  const toml::table* dt = single("domain");
  if (!dt)
    r.fail(root, "the scene has no [domain]",
           "add [domain] with box = { min = [x, y, z], max = [x, y, z] } or planes = [...]");
  const Tbl dtbl{r, *dt, "[domain]"};
  scene.domain = read_region(dtbl);
  Context cx{r, analyse_region(scene.domain.planes, scene.options.tolerance),
             scene.options.tolerance};
  {
    const toml::node& at = dt->get("planes") ? *dt->get("planes") : *dt;
    if (cx.domain_info.status == RegionStatus::unbounded)
      r.fail(at, "the 'planes' of [domain] do not enclose a bounded region",
             "add planes (outward normals, normal . x <= d inside) that close it in every "
             "direction");
    if (cx.domain_info.status == RegionStatus::empty)
      r.fail(at,
             "the 'planes' of [domain] enclose no volume (the half-spaces normal . x <= d "
             "have no common interior)",
             "check that every normal points outward and every d puts the plane on the "
             "domain's face");
  }

  if (const toml::table* ot = single("options")) {
    const Tbl t{r, *ot, "[options]"};
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
  }

  const auto joints = multi("joints");
  for (std::size_t i = 0; i < joints.size(); ++i)
    scene.joints.push_back(read_joint(cx, *joints[i], i));

  std::set<std::string> names;
  const auto sets = multi("sets");
  for (std::size_t i = 0; i < sets.size(); ++i)
    scene.sets.push_back(read_set(cx, *sets[i], i, names));

  const auto zones = multi("zones");
  for (std::size_t i = 0; i < zones.size(); ++i) {
    const Tbl t{r, *zones[i], "[[zones]] #" + std::to_string(i + 1)};
    Region zone = read_region(t);
    // A zone may be unbounded (e.g. "everything above z = 50"): only its part inside the domain
    // matters, and that must have volume, else it removes nothing and is surely a slip.
    std::vector<Plane> both = zone.planes;
    both.insert(both.end(), scene.domain.planes.begin(), scene.domain.planes.end());
    const PolytopeInfo in = analyse_polytope(both, cx.tol());
    if (!in.has_interior)
      r.fail(*zones[i], t.ctx + " has no volume inside the domain, so it would remove nothing",
             "check its coordinates against the domain (and that plane normals point out of "
             "the zone)");
    scene.zones.push_back(std::move(zone));
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
  js.domain = scene.domain;
  js.options = scene.options;
  js.sets = scene.sets;
  js.zones = scene.zones;
  const RegionAnalysis dom = analyse_region(scene.domain.planes, scene.options.tolerance);
  if (dom.status != RegionStatus::ok)
    throw Error(scene.source.string(),
                dom.status == RegionStatus::unbounded ? "the domain is unbounded"
                                                      : "the domain has no volume",
                "give a bounded domain with an interior (load the scene with load_scene)");
  js.length_scale = dom.length_scale;
  const double tol = scene.options.tolerance * dom.length_scale;
  const Vec3 mean = dom.info.interior_point;  // the domain's vertex mean

  // [[joints]] first, in file order. A joint that misses the domain entirely is kept: the
  // slicer finds that it cuts nothing, and the joint indices stay those of the file.
  for (const Joint& j : scene.joints) {
    js.joints.push_back(j);
    js.joints.back().set = -1;
  }
  for (std::size_t s = 0; s < js.sets.size(); ++s) {
    JointSetSpec& spec = js.sets[s];
    if (!(spec.spacing > 0) || !std::isfinite(spec.spacing) || !std::isfinite(spec.offset))
      throw Error(scene.source.string(),
                  "set \"" + spec.name + "\" has spacing " + fmt(spec.spacing) + " and offset " +
                      fmt(spec.offset),
                  "give a finite spacing > 0 and a finite offset");
    const Vec3 n = normal_from_dip(spec.dip_deg, spec.dip_direction_deg);
    const auto [lo, hi] = extent_along(dom.info.vertices, n);
    if ((hi - lo) / spec.spacing > kMaxPlanesPerSet)
      throw Error(
          scene.source.string(),
          "set \"" + spec.name + "\" would have more than " + fmt(kMaxPlanesPerSet) + " planes",
          "check the units of spacing and of the domain");
    const std::vector<double> planes = set_planes(spec, dom.info.vertices, tol);
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
      j.boundary_side = spec.boundary_side;
      js.joints.push_back(std::move(j));
    }
    spec.joint_count = static_cast<std::int64_t>(planes.size());
  }
  order_joints(js.joints, scene.options.order);
  return js;
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

void order_joints(std::vector<Joint>& joints, JointOrder order) {
  if (order == JointOrder::as_given) return;
  std::vector<std::size_t> idx(joints.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::vector<double> area(joints.size());
  for (std::size_t i = 0; i < joints.size(); ++i) area[i] = polygon_area(joints[i]);
  auto larger = [&](std::size_t a, std::size_t b) { return area[a] > area[b]; };

  if (order == JointOrder::largest_first) {
    std::stable_sort(idx.begin(), idx.end(), larger);
  } else {
    // Groups: each deterministic joint on its own, in the given order, then the sets by index.
    std::vector<std::vector<std::size_t>> groups;
    std::map<std::int32_t, std::vector<std::size_t>> by_set;
    for (std::size_t i = 0; i < joints.size(); ++i) {
      if (joints[i].set < 0)
        groups.push_back({i});
      else
        by_set[joints[i].set].push_back(i);
    }
    for (auto& [s, g] : by_set) groups.push_back(std::move(g));
    idx.clear();
    if (order == JointOrder::by_set) {
      for (const auto& g : groups) idx.insert(idx.end(), g.begin(), g.end());
    } else {  // alternating: one joint of each group in turn, each group largest first
      std::size_t longest = 0;
      for (auto& g : groups) {
        std::stable_sort(g.begin(), g.end(), larger);
        longest = std::max(longest, g.size());
      }
      for (std::size_t round = 0; round < longest; ++round)
        for (const auto& g : groups)
          if (round < g.size()) idx.push_back(g[round]);
    }
  }
  std::vector<Joint> out;
  out.reserve(joints.size());
  for (const std::size_t i : idx) out.push_back(std::move(joints[i]));
  joints = std::move(out);
}

}  // namespace slice

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene_read.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "slice/stochastic.hpp"

// The [[joints]] and [[sets]] entries of a scene file (docs/scenes.md).
namespace slice::scene_read {

namespace {

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
  std::vector<Vec2> uv =
      segment_polygon(plane_frame(c.dip, c.dip_direction), j.centre, ends[0], ends[1]);
  const std::vector<const toml::node*> where(uv.size(), seg);
  check_polygon(r, uv, where, *seg, label, tol);
  j.polygon_uv = std::move(uv);
  return j;
}

}  // namespace

Joint read_joint(const Context& cx, const toml::table& tt, std::size_t index) {
  const Reader& r = cx.r;
  const Tbl t{r, tt, "[[joints]] #" + std::to_string(index + 1)};
  t.check_keys(kJointKeys);
  Common c = read_common(t);
  if (cx.section) {  // a 3-D orientation: its trace in the section
    const SectionTrace tr = trace_in_section(cx, t, c.dip, c.dip_direction);
    c.dip = tr.apparent_dip_deg;
    c.dip_direction = tr.apparent_dip_direction_deg;
  }
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

namespace {

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

// The set's mapping window, { point, dip, dip_direction, width, height }, inside the domain, and
// the trace lengths mapped in it, trace_length = { mean, sd }.
void read_mapping(const Context& cx, const Tbl& set, JointSetSpec& s) {
  const Reader& r = set.r;
  const toml::node* node = set.find("mapping");
  const toml::node* traces = set.find("trace_length");
  if (!node) {
    if (traces)
      r.fail(*traces, set.label("trace_length") + " needs the window it was mapped in",
             "add mapping = { point = [x, y, z], dip = ..., dip_direction = ..., width = ..., "
             "height = ... }");
    return;
  }
  const std::string form =
      "mapping = { point = [x, y, z], dip = 90, dip_direction = 0, width = 20, height = 5 }";
  if (cx.dimension == 2)
    r.fail(*node, set.label("mapping") + " is not available in a 2-D scene",
           "remove it: a section is itself a mapping plane");
  const Tbl t{r, as_table(r, *node, set.label("mapping"), "write " + form),
              "'mapping' of " + set.ctx};
  t.check_keys(kMappingKeys);
  TraceMapping& m = s.mapping;
  m.given = true;
  m.centre = to_vector<3>(r, t.require("point", "add point = [x, y, z], the window's centre"),
                          t.label("point"));
  m.dip_deg = required_number(t, "dip", "add dip = <degrees>, the mapping plane's dip");
  check_range(t, "dip", m.dip_deg, 0, 90, false, kDipFix);
  m.dip_direction_deg = required_number(t, "dip_direction",
                                        "add dip_direction = <degrees>, the plane's dip direction");
  check_range(t, "dip_direction", m.dip_direction_deg, 0, 360, true, kDipDirectionFix);
  t.require("width", "add width = <the window's length along the plane's strike>");
  t.require("height", "add height = <the window's length along the plane's dip line>");
  m.width = positive(t, "width", "give the window's length along strike, > 0");
  m.height = positive(t, "height", "give the window's length along the dip line, > 0");
  const JointFrame f = plane_frame(m.dip_deg, m.dip_direction_deg);
  const double tol = cx.tol();
  for (const double su : {-0.5, 0.5})
    for (const double sv : {-0.5, 0.5}) {
      const Vec3 x = f.to_global(m.centre, Vec2(su * m.width, sv * m.height));
      for (const Plane& p : cx.box.planes)
        if (p.distance(x) > tol)
          r.fail(*node,
                 "the mapping window of " + set.ctx + " leaves the domain: its corner " + fmt(x) +
                     " is " + fmt(p.distance(x), 6) + " outside the domain face with outward " +
                     "normal " + fmt(p.normal),
                 "move the window's point or shrink its width or height so that it lies inside "
                 "the domain");
    }
  if (!traces) return;
  const Tbl tl{r,
               as_table(r, *traces, set.label("trace_length"),
                        "write trace_length = { mean = 2.5, sd = 1.2 }"),
               "'trace_length' of " + set.ctx};
  tl.check_keys(kTraceLengthKeys);
  tl.require("mean", "add mean = <the mean trace length mapped in the window>");
  m.field_mean = positive(tl, "mean", "give the mean mapped trace length, > 0");
  if (tl.find("sd"))
    m.field_sd = positive(tl, "sd", "give the standard deviation of the mapped trace lengths, > 0");
}

// The index in kIntensityKeys of the set's one intensity key (exactly one is given).
std::size_t read_intensity(const Tbl& t) {
  const Reader& r = t.r;
  std::vector<std::size_t> given;
  for (std::size_t i = 0; i < kIntensityKeys.size(); ++i)
    if (t.find(kIntensityKeys[i])) given.push_back(i);
  if (given.empty())
    r.fail(t.t,
           "missing key 'spacing' (or 'density', 'count', 'p32', 'p10') in " + t.ctx +
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
           t.ctx + " gives both " + quote_key(first_key) + " and " + quote_key(second),
           "keep one intensity: spacing, density, count, p32 or p10");
  }
  return given.front();
}

// A regular set (spacing): persistent planes at the mean orientation, or each scattered about
// it (fisher_kappa); no size. In a section, `trace` carries the 3-D set's spacing and offset over
// to its lines.
void read_regular(const Context& cx, const Tbl& t, JointSetSpec& s, const SectionTrace* trace) {
  const Reader& r = t.r;
  std::string_view bad;
  if (const toml::node* n = first_present(
          t, std::array<std::string_view, 6>{"size", "shape", "aspect", "sides", "fit", "rotation"},
          &bad))
    r.fail(*n,
           t.label(bad) +
               " does not apply to a regular set (spacing), whose joints are "
               "persistent planes",
           "remove " + quote_key(bad) +
               ", or replace 'spacing' by density, count, p32 or p10 for a stochastic set");
  s.spacing =
      positive(t, "spacing", "give the distance between the set's planes, a positive length");
  s.offset = number(t, "offset", 0);
  if (trace) {
    s.spacing = trace->spacing(s.spacing);
    s.offset = trace->offset(s.offset);
  }
  const Vec3 n = dip_normal(s.dip_deg, s.dip_direction_deg, cx.dimension);
  const auto [lo, hi] = extent_along(cx.domain_info.info.vertices, n);
  if ((hi - lo) / s.spacing > kMaxPlanesPerSet)
    r.fail(*t.find("spacing"),
           t.label("spacing") + " = " + fmt(s.spacing) + " gives about " +
               fmt(std::round((hi - lo) / s.spacing)) + " planes across the domain, more than " +
               fmt(kMaxPlanesPerSet),
           "check the units of spacing and of the domain");
}

// The intensity `in` of a stochastic set; `finite`: the set has a size.
// traced: a 3-D set in a section, whose p10 counts along its mean pole in 3-D (no scanline).
void read_stochastic_intensity(const Tbl& t, const toml::node& in, bool finite, JointSetSpec& s,
                               bool traced) {
  const Reader& r = t.r;
  if (const toml::node* n = t.find("offset"))
    r.fail(*n, t.label("offset") + " applies to regular sets (spacing) only",
           "remove 'offset': the joints of a stochastic set are placed at random");
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
      if (traced) {
        if (s.scanline_given)
          r.fail(*t.find("scanline"),
                 t.label("scanline") +
                     ": the p10 of a 3-D set in a section counts the joints along its mean pole "
                     "in 3-D, not along a scanline",
                 "remove 'scanline' (p10 is the number of joints per unit length along the "
                 "set's mean pole, docs/2d.md), or give the set's intensity as p32 or density");
        break;
      }
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
    case SetIntensity::deterministic:  // not a [[sets]] intensity
      break;
  }
}

// The shape of a stochastic set's joints: finite ones only (`finite`) take one.
void read_joint_shape(const Tbl& t, bool finite, JointSetSpec& s) {
  const Reader& r = t.r;
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
}

// A set that would draw more joints than allowed is refused before anything is drawn.
void check_expected_count(const Context& cx, const Tbl& t, const toml::node& in,
                          std::string_view ikey, const JointSetSpec& s) {
  const Reader& r = t.r;
  const double expect = expected_candidates(s, cx.box);
  if (!std::isfinite(expect))
    r.fail(in,
           t.label(ikey) + " cannot be reached: the scanline lies in the plane of the set's " +
               "joints, so none crosses it",
           "give a scanline across the joints, e.g. along their mean normal");
  if (expect > static_cast<double>(cx.max_joints))
    r.fail(in,
           t.ctx + " would draw about " + fmt(expect, 3) + " joints (" + std::string(ikey) + " = " +
               fmt(to_number(r, in, t.label(ikey))) +
               "), more than max_joints = " + std::to_string(cx.max_joints),
           "lower " + quote_key(ikey) + " (check its units), or raise max_joints in [scene]");
}

}  // namespace

JointSetSpec read_set(const Context& cx, const toml::table& tt, std::size_t index,
                      std::set<std::string>& names, SectionTrace* trace) {
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
  Common c = read_common(t);
  SectionTrace tr;
  if (cx.section) {  // a 3-D set: its trace in the section
    tr = trace_in_section(cx, t, c.dip, c.dip_direction);
    c.dip = tr.apparent_dip_deg;
    c.dip_direction = tr.apparent_dip_direction_deg;
    if (trace) *trace = tr;
  }
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

  const std::size_t which = read_intensity(t);
  s.intensity = static_cast<SetIntensity>(which);
  const std::string_view ikey = kIntensityKeys[which];
  check_section_dip(cx, t, c);
  // In a section a 3-D set may be stochastic (density, p32, count or p10, with a size): its
  // joints' traces (docs/2d.md).
  const bool traced = cx.section && s.intensity != SetIntensity::spacing;
  if (cx.dimension == 2 && !traced) {
    if (s.intensity != SetIntensity::spacing)
      r.fail(*t.find(ikey),
             t.label(ikey) +
                 ": a 2-D scene's sets are regular lines (spacing) unless the scene has a "
                 "[section]",
             "give spacing = <distance between the lines>, or the joints one by one as "
             "[[joints]] with segment = [[x1, z1], [x2, z2]]");
    if (const toml::node* n = t.find("fisher_kappa"))
      r.fail(*n, t.label("fisher_kappa") + " is not available for a 2-D scene's regular set",
             "remove it: a 2-D set's lines share one orientation (a stochastic 3-D set in a "
             "[section] takes it)");
  }

  if (const toml::node* n = t.find("fisher_kappa")) {
    s.fisher_kappa = to_number(r, *n, t.label("fisher_kappa"));
    if (s.fisher_kappa < 0)
      r.fail(*n, t.label("fisher_kappa") + " is " + fmt(s.fisher_kappa) + ", below 0",
             "give the Fisher concentration, >= 0 (0: every joint at the mean orientation; the "
             "larger, the tighter the poles)");
  }
  if (const toml::node* n = t.find("scanline")) read_scanline(cx, t, *n, s);
  read_mapping(cx, t, s);
  const toml::node* size_node = t.find("size");
  if (size_node) s.size = read_size(t, *size_node);
  const bool finite = s.size.distribution != SizeDistribution::persistent;

  if (s.intensity == SetIntensity::spacing) {
    read_regular(cx, t, s, cx.section ? &tr : nullptr);
    return s;
  }

  const toml::node& in = *t.find(ikey);
  if (traced && !finite)
    r.fail(in,
           t.label(ikey) +
               ": a stochastic 3-D set in a section needs a size: its joints are "
               "discs or polygons, whose traces are segments",
           "add size = { distribution = ..., ... }, or give spacing for persistent planes");
  read_stochastic_intensity(t, in, finite, s, traced);
  read_joint_shape(t, finite, s);
  // A traced set draws in a slab of the 3-D region, not in the section's: the generator checks
  // its count (generate_section_set).
  if (!traced) check_expected_count(cx, t, in, ikey, s);
  return s;
}

}  // namespace slice::scene_read

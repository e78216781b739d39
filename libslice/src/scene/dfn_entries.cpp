#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "scene_read.hpp"
#include "slice/dfn.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"

// The [[dfn]] entries of a scene file (docs/scenes.md, docs/dfn.md): the fractures of a FAB or
// CSV file as polygon joints, the file's sets as sets; and the `set` key of [[joints]].
namespace slice::scene_read {

namespace {

// What a [[dfn]] entry or one of its `sets` gives its joints.
struct DfnProps {
  JointKind kind = JointKind::rock;
  std::int8_t side = 0;
  double friction = 30, cohesion = 0, tension = 0;
  bool limits = true;
  std::int64_t stage = 1;
};

// The keys of `t` over `p` (a file's values over the defaults, a set's over the file's).
DfnProps read_props(const Tbl& t, DfnProps p) {
  const Reader& r = t.r;
  if (t.find("friction_angle")) {
    p.friction = number(t, "friction_angle", 30);
    check_range(t, "friction_angle", p.friction, 0, 90, true,
                "give the friction angle in degrees, 0 <= friction_angle < 90");
  }
  p.cohesion = stress(t, "cohesion", p.cohesion);
  p.tension = stress(t, "tension", p.tension);
  if (const toml::node* k = t.find("kind"))
    p.kind = static_cast<JointKind>(to_choice(r, *k, t.label("kind"), kJointKindNames));
  if (const toml::node* n = t.find("limits")) {
    const auto* b = n->as_boolean();
    if (!b)
      r.fail(*n, t.label("limits") + " must be true or false, not " + type_name(*n),
             "write limits = false to exempt these cuts from the size and shape limits");
    p.limits = b->get();
  }
  if (const toml::node* keep = t.find("keep")) {
    if (p.kind != JointKind::boundary)
      r.fail(*keep, t.label("keep") + " applies to boundary joints only",
             "remove 'keep', or set kind = \"boundary\"");
    p.side = to_choice(r, *keep, t.label("keep"), kKeepNames) == 0 ? 1 : -1;
  } else if (p.kind == JointKind::boundary && p.side == 0) {
    t.require("keep",
              "add keep = \"above\" or \"below\": the side whose blocks become boundary "
              "blocks");
  }
  if (p.kind != JointKind::boundary) p.side = 0;
  if (t.find("stage")) p.stage = read_place(r, t.t, t.ctx, 0).stage;
  return p;
}

void give(const DfnProps& p, Joint& j) {
  j.kind = p.kind;
  j.boundary_side = p.side;
  j.friction_angle_deg = p.friction;
  j.cohesion = p.cohesion;
  j.tension = p.tension;
  j.limits = p.limits;
}

// A set of given joints (intensity deterministic) with the properties of `like`, which its
// joints share.
JointSetSpec given_set(const std::string& name, const Joint& like) {
  JointSetSpec spec;
  spec.name = name;
  spec.intensity = SetIntensity::deterministic;
  spec.kind = like.kind;
  spec.boundary_side = like.boundary_side;
  spec.friction_angle_deg = like.friction_angle_deg;
  spec.cohesion = like.cohesion;
  spec.tension = like.tension;
  spec.limits = like.limits;
  return spec;
}

// Convexity of a polygon in its plane: repeated corners and corners on the edge between their
// neighbours (within tol) are dropped, as clipped fractures have them; what is left must be a
// convex polygon winding once. Made counter-clockwise. "" or why not.
// The corners are a ring of links: a dropped corner puts its two neighbours back in the queue,
// so a fracture of 1,000,000 nodes takes linear time (erasing them from a vector one at a time
// took 96 s: issue 42 item 11).
std::string make_convex(std::vector<Vec2>& p, double tol) {
  const std::size_t n0 = p.size();
  std::vector<std::size_t> prev(n0), next(n0), queue(n0);
  std::vector<char> alive(n0, 1), queued(n0, 1);
  for (std::size_t i = 0; i < n0; ++i) {
    prev[i] = (i + n0 - 1) % n0;
    next[i] = (i + 1) % n0;
    queue[i] = i;
  }
  std::size_t left = n0;
  for (std::size_t q = 0; q < queue.size() && left >= 3; ++q) {
    const std::size_t i = queue[q];
    queued[i] = 0;
    if (!alive[i]) continue;
    const Vec2 a = p[prev[i]], b = p[i], c = p[next[i]];
    const Vec2 e1 = b - a, e2 = c - b;
    const double chord = (c - a).norm();
    const bool repeated = e1.norm() <= tol;
    // On the edge from a to c: only when c is not a repeat of b (within tol), else b would be
    // measured against its own repeat, and a dense outline (nodes closer than tol all along)
    // would lose its corners one by one; c is dropped as b's repeat instead.
    const bool on_edge = chord > tol && e2.norm() > tol &&
                         std::abs(e1.x() * e2.y() - e1.y() * e2.x()) / chord <= tol;
    if (!repeated && !on_edge) continue;
    alive[i] = 0;
    --left;
    next[prev[i]] = next[i];
    prev[next[i]] = prev[i];
    for (const std::size_t k : {prev[i], next[i]})
      if (!queued[k]) {
        queued[k] = 1;
        queue.push_back(k);
      }
  }
  std::vector<Vec2> kept;
  if (left >= 3) {
    const auto first =
        static_cast<std::size_t>(std::find(alive.begin(), alive.end(), 1) - alive.begin());
    kept.reserve(left);
    std::size_t i = first;
    do {
      kept.push_back(p[i]);
      i = next[i];
    } while (i != first);
  }
  p = std::move(kept);
  if (p.size() < 3) return "has no area (its corners lie on one line)";
  const std::size_t n = p.size();
  double area2 = 0, turning = 0;
  for (std::size_t i = 0; i < n; ++i)
    area2 += p[i].x() * p[(i + 1) % n].y() - p[i].y() * p[(i + 1) % n].x();
  const int sign = area2 > 0 ? 1 : -1;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e1 = p[i] - p[(i + n - 1) % n], e2 = p[(i + 1) % n] - p[i];
    const double cross = e1.x() * e2.y() - e1.y() * e2.x();
    if ((cross > 0 ? 1 : -1) != sign) return "is not convex at its corner " + std::to_string(i + 1);
    turning += std::atan2(cross, e1.dot(e2));
  }
  if (std::abs(turning) > 3 * std::numbers::pi) return "crosses itself";
  if (sign < 0) std::reverse(p.begin(), p.end());
  return "";
}

// The plane of a FAB fracture's nodes: the plane that fits them best (through their mean, normal
// the direction of least spread, as for a [[joints]] polygon), its nodes within `planarity` x
// its radius (and at least the scene's tolerance) of it; j.polygon_uv gets the nodes in its
// frame, `ptol` that distance. "" or why not.
std::string fit_plane(const std::vector<Vec3>& xs, double tol, double planarity, Joint& j,
                      double& ptol) {
  // Nodes so far out that doubles there step by more than the tolerance (1e155 made a normal of
  // NaN, refused only when written: issue 42 item 14) are refused here, by the file's line.
  Vec3 lo = xs.front(), hi = xs.front();
  for (const auto& x : xs) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  if (std::string why = precision_problem(lo, hi, tol, "a node"); !why.empty())
    return "is too far out: " + why;
  Vec3 mean = Vec3::Zero();
  for (const auto& x : xs) mean += x;
  mean /= static_cast<double>(xs.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  double radius = 0;
  for (const auto& x : xs) {
    cov += (x - mean) * (x - mean).transpose();
    radius = std::max(radius, (x - mean).norm());
  }
  if (!cov.allFinite() || !std::isfinite(radius))
    return "is too large: the squares of its nodes' distances from their mean overflow";
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  const Vec3 best = es.eigenvectors().col(0);
  ptol = std::max(tol, planarity * radius);
  for (std::size_t i = 0; i < xs.size(); ++i)
    if (const double off = std::abs(best.dot(xs[i] - mean)); off > ptol)
      return "is not planar: node " + std::to_string(i + 1) + " is " + fmt(off, 6) +
             " from the plane that fits its nodes best, more than the tolerance " + fmt(ptol, 3) +
             " (planarity " + fmt(planarity, 3) + " x its radius " + fmt(radius, 6) + ")";
  const DipAndDirection dd = dip_from_normal(best);
  const JointFrame frame = plane_frame(dd.dip_deg, dd.dip_direction_deg);
  j.dip_deg = dd.dip_deg;
  j.dip_direction_deg = dd.dip_direction_deg;
  j.centre = mean;
  j.plane = {frame.n, frame.n.dot(mean)};
  for (const auto& x : xs) j.polygon_uv.push_back(frame.to_uv(mean, x));
  return "";
}

// The joint of a FAB fracture: its nodes, in order, are a planar convex polygon.
std::string polygon_joint(const std::vector<Vec3>& xs, double tol, double planarity, Joint& j) {
  double ptol = 0;
  if (std::string why = fit_plane(xs, tol, planarity, j, ptol); !why.empty()) return why;
  return make_convex(j.polygon_uv, ptol);  // the digits that bent it may also bend an edge
}

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// The convex hull of points, counter-clockwise (Andrew's monotone chain).
std::vector<Vec2> convex_hull(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Vec2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross2(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k > 1 ? k - 1 : k);
  return h;
}

// Whether two triangles' interiors overlap by more than `tol` (separating axes: convex shapes
// are apart, or touch along an edge or at a corner, when their projections on the normal of one
// of their edges overlap by tol at most; otherwise that least overlap is how deep they
// interpenetrate). Orientation and degenerate (flat) triangles do not matter: a flat one has
// no depth across its own edges.
bool triangles_overlap(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b, double tol) {
  for (const auto* t : {&a, &b})
    for (std::size_t e = 0; e < 3; ++e) {
      const Vec2 d = (*t)[(e + 1) % 3] - (*t)[e];
      const double len = d.norm();
      if (!(len > 0)) continue;
      const Vec2 axis(-d.y() / len, d.x() / len);
      double lo_a = axis.dot(a[0]), hi_a = lo_a, lo_b = axis.dot(b[0]), hi_b = lo_b;
      for (std::size_t k = 1; k < 3; ++k) {
        lo_a = std::min(lo_a, axis.dot(a[k])), hi_a = std::max(hi_a, axis.dot(a[k]));
        lo_b = std::min(lo_b, axis.dot(b[k])), hi_b = std::max(hi_b, axis.dot(b[k]));
      }
      if (std::min(hi_a, hi_b) - std::max(lo_a, lo_b) <= tol) return false;
    }
  return true;
}

// Two triangles (indices into tri) whose interiors overlap by more than `tol`, or nothing.
// Candidates come from a uniform grid over the triangles' bounding boxes, about one cell per
// triangle: a tiling has a few triangles per cell, so the check is about linear in their number.
// A pair is tested in one cell only, the one holding the lower corner of the overlap of their
// boxes. Triangles crowded into one cell (a fan of thousands of slivers about one node) cost
// their number squared there; the first overlap found ends the search.
std::optional<std::pair<std::size_t, std::size_t>> overlapping_triangles(
    const std::vector<std::array<Vec2, 3>>& tri, double tol) {
  // A triangle no wider than tol across its longest edge overlaps nothing by more than tol
  // (its own depth along that edge's normal): left out, so that slivers and flat triangles
  // spanning the whole fracture cannot crowd the grid.
  std::vector<std::size_t> wide;
  for (std::size_t i = 0; i < tri.size(); ++i) {
    const auto& t = tri[i];
    const double twice = std::abs(cross2(t[1] - t[0], t[2] - t[0]));
    const double longest =
        std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    if (twice > tol * longest) wide.push_back(i);
  }
  const std::size_t m = wide.size();
  if (m < 2) return std::nullopt;
  std::vector<Vec2> lo(m), hi(m);
  Vec2 all_lo = tri[wide[0]][0], all_hi = all_lo;
  for (std::size_t w = 0; w < m; ++w) {
    const auto& t = tri[wide[w]];
    lo[w] = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
    hi[w] = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
    all_lo = all_lo.cwiseMin(lo[w]), all_hi = all_hi.cwiseMax(hi[w]);
  }
  const Vec2 size = (all_hi - all_lo).cwiseMax(Vec2::Constant(1e-300));
  // Cells about square, about m of them, at most 4096 a side.
  const double cell = std::sqrt(size.x() * size.y() / static_cast<double>(m));
  const auto cells = [&](double extent) {
    const double c = cell > 0 ? std::ceil(extent / cell) : 1;
    return static_cast<std::size_t>(std::clamp(std::isfinite(c) ? c : 1.0, 1.0, 4096.0));
  };
  std::size_t nx = cells(size.x()), ny = cells(size.y());
  const auto at = [&](double v, double origin, double extent, std::size_t n) {
    const double f = (v - origin) / extent * static_cast<double>(n);
    return static_cast<std::size_t>(
        std::clamp(std::isfinite(f) ? f : 0.0, 0.0, static_cast<double>(n - 1)));
  };
  const auto range = [&](std::size_t i) {
    return std::array<std::size_t, 4>{
        at(lo[i].x(), all_lo.x(), size.x(), nx), at(hi[i].x(), all_lo.x(), size.x(), nx),
        at(lo[i].y(), all_lo.y(), size.y(), ny), at(hi[i].y(), all_lo.y(), size.y(), ny)};
  };
  // Boxes over many cells (long triangles) would fill memory: the grid is made coarser until
  // the triangles take at most 16 cells each on average.
  for (;;) {
    double taken = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const auto r = range(i);
      taken += double(r[1] - r[0] + 1) * double(r[3] - r[2] + 1);
    }
    if (taken <= 16.0 * double(m) + double(1 << 20) || nx * ny == 1) break;
    nx = (nx + 1) / 2, ny = (ny + 1) / 2;
  }
  // The cells' triangles, compressed rows: start[c] .. start[c + 1] in `in`.
  std::vector<std::size_t> start(nx * ny + 1, 0);
  for (std::size_t i = 0; i < m; ++i) {
    const auto r = range(i);
    for (std::size_t y = r[2]; y <= r[3]; ++y)
      for (std::size_t x = r[0]; x <= r[1]; ++x) ++start[y * nx + x + 1];
  }
  for (std::size_t c = 0; c < nx * ny; ++c) start[c + 1] += start[c];
  std::vector<std::size_t> in(start.back()), fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < m; ++i) {
    const auto r = range(i);
    for (std::size_t y = r[2]; y <= r[3]; ++y)
      for (std::size_t x = r[0]; x <= r[1]; ++x) in[fill[y * nx + x]++] = i;
  }
  for (std::size_t y = 0; y < ny; ++y)
    for (std::size_t x = 0; x < nx; ++x) {
      const std::size_t c = y * nx + x;
      for (std::size_t p = start[c]; p < start[c + 1]; ++p)
        for (std::size_t q = p + 1; q < start[c + 1]; ++q) {
          const std::size_t i = in[p], k = in[q];
          // Boxes apart by more than tol: no overlap; the pair's own cell only.
          if (lo[i].x() > hi[k].x() - tol || lo[k].x() > hi[i].x() - tol ||
              lo[i].y() > hi[k].y() - tol || lo[k].y() > hi[i].y() - tol)
            continue;
          const Vec2 corner = lo[i].cwiseMax(lo[k]);
          if (at(corner.x(), all_lo.x(), size.x(), nx) != x ||
              at(corner.y(), all_lo.y(), size.y(), ny) != y)
            continue;
          if (triangles_overlap(tri[wide[i]], tri[wide[k]], tol))
            return std::pair{wide[i], wide[k]};
        }
    }
  return std::nullopt;
}

// The joint of a FAB tessellated fracture: planar as a polygon's nodes, its joint the convex
// hull of its nodes, provided that its triangles tile that hull: their areas (all of one
// orientation) add up to the hull's, within a band of `ptol` along its outline. A face line's
// node indices are its values 2-4, or 3-5 when value 2 is 3 (docs/dfn.md): either layout that
// tiles the hull is taken. "" or why not.
std::string tessellated_joint(const DfnFracture& f, double tol, double planarity, Joint& j) {
  double ptol = 0;
  if (std::string why = fit_plane(f.nodes, tol, planarity, j, ptol); !why.empty()) return why;
  const std::vector<Vec2> uv = std::move(j.polygon_uv);
  j.polygon_uv = convex_hull(uv);
  if (std::string why = make_convex(j.polygon_uv, ptol); !why.empty()) return why;
  double hull = 0, perimeter = 0;
  for (std::size_t i = 0; i < j.polygon_uv.size(); ++i) {
    const Vec2 &a = j.polygon_uv[i], &b = j.polygon_uv[(i + 1) % j.polygon_uv.size()];
    hull += cross2(a, b) / 2;
    perimeter += (b - a).norm();
  }
  const auto n = static_cast<std::int64_t>(uv.size());
  std::string found;
  for (const std::size_t first : {std::size_t{1}, std::size_t{2}}) {
    double sum = 0, sum_abs = 0;
    bool indices = true;
    for (const auto& face : f.faces) {
      if (first == 2 && face[1] != 3) indices = false;
      for (std::size_t c = first; c < first + 3; ++c)
        indices = indices && face[c] >= 1 && face[c] <= n;
      if (!indices) break;
      const Vec2 &a = uv[std::size_t(face[first] - 1)], &b = uv[std::size_t(face[first + 1] - 1)],
                 &c = uv[std::size_t(face[first + 2] - 1)];
      const double area = cross2(b - a, c - a) / 2;
      sum += area;
      sum_abs += std::abs(area);
    }
    if (!indices) continue;
    // Areas alone pass a triangle given twice (half the outline bare, the other half covered
    // twice: issue 42 item 6). In a tiling of one orientation no two triangles lie on the same
    // side of an edge, so no edge is run twice the same way; a repeated or folded triangle runs
    // one so.
    std::vector<std::pair<std::int64_t, std::int64_t>> edges;
    edges.reserve(3 * f.faces.size());
    for (const auto& face : f.faces)
      for (std::size_t c = 0; c < 3; ++c)
        edges.emplace_back(face[first + c], face[first + (c + 1) % 3]);
    std::sort(edges.begin(), edges.end());
    const auto twice = std::adjacent_find(edges.begin(), edges.end());
    if (twice != edges.end()) {
      found += std::string(found.empty() ? "" : "; ") + "with node indices in values " +
               (first == 1 ? "2-4" : "3-5") + " two triangles lie on the same side of the edge " +
               "from node " + std::to_string(twice->first) + " to node " +
               std::to_string(twice->second) + " (they overlap)";
      continue;
    }
    if (std::abs(sum_abs - hull) <= ptol * perimeter &&
        sum_abs - std::abs(sum) <= ptol * perimeter) {
      // Areas that add up pass triangles that overlap where others leave a gap of the same area
      // (issue 42 item 6): their interiors must not overlap, pairwise, in the fracture's plane.
      std::vector<std::array<Vec2, 3>> tri;
      tri.reserve(f.faces.size());
      for (const auto& face : f.faces)
        tri.push_back({uv[std::size_t(face[first] - 1)], uv[std::size_t(face[first + 1] - 1)],
                       uv[std::size_t(face[first + 2] - 1)]});
      const auto both = overlapping_triangles(tri, ptol);
      if (!both) return "";
      found += std::string(found.empty() ? "" : "; ") + "with node indices in values " +
               (first == 1 ? "2-4" : "3-5") + " the triangles of its face lines " +
               std::to_string(both->first + 1) + " and " + std::to_string(both->second + 1) +
               " overlap";
      continue;
    }
    found += std::string(found.empty() ? "" : "; ") + "with node indices in values " +
             (first == 1 ? "2-4" : "3-5") + " its triangles cover " + fmt(sum_abs, 6) +
             " (turning both ways: " + fmt(sum_abs - std::abs(sum), 3) + ")";
  }
  if (found.empty())
    return "has face lines whose node indices (values 2-4, or 3-5 after a 3) are not all "
           "within 1.." +
           std::to_string(n);
  return "is not one convex polygon: the convex hull of its nodes has the area " + fmt(hull, 6) +
         ", but " + found + " (a non-convex or holed outline, or overlapping triangles)";
}

DfnFile read_file_of(const Context& cx, const Tbl& t, const toml::node& node,
                     const std::filesystem::path& file) {
  const Reader& r = cx.r;
  std::string format;
  if (const toml::node* n = t.find("format"))
    format = kDfnFormats[to_choice(r, *n, t.label("format"), kDfnFormats)];
  else {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext != ".fab" && ext != ".csv")
      r.fail(node, t.label("file") + " names " + file.string() + ", neither .fab nor .csv",
             "add format = \"fab\" or \"csv\"");
    format = ext.substr(1);
  }
  DfnCsvOptions csv;
  if (const toml::node* n = t.find("sides")) {
    csv.sides = to_integer(r, *n, t.label("sides"));
    if (csv.sides < 3 || csv.sides > kMaxSides)
      r.fail(*n,
             t.label("sides") + " is " + std::to_string(csv.sides) + ", outside [3, " +
                 std::to_string(kMaxSides) + "]",
             "give the number of corners of a disc's polygon");
  }
  if (const toml::node* n = t.find("fit"))
    csv.fit = static_cast<EllipseFit>(to_choice(r, *n, t.label("fit"), kEllipseFitNames));
  if (format == "fab")
    for (const char* key : {"sides", "fit"})
      if (const toml::node* n = t.find(key))
        r.fail(*n, t.label(key) + " applies to CSV files of discs; a FAB file gives polygons",
               "remove " + quote_key(key));
  try {
    return format == "fab" ? read_fab(file) : read_dfn_csv(file, csv, file.stem().string());
  } catch (const Error& e) {  // its own fix: one per line
    r.fail(node, t.label("file") + ": " + e.where() + ": " + e.problem(), e.fix());
  }
}

}  // namespace

DfnEntry read_dfn(const Context& cx, const toml::table& tt, std::size_t index, std::int64_t entry,
                  std::set<std::string>& names, std::size_t first_set) {
  const Reader& r = cx.r;
  const Tbl t{r, tt, "[[dfn]] #" + std::to_string(index + 1)};
  t.check_keys(kDfnKeys);
  const toml::node& node = t.require("file", "add file = \"network.fab\" (or a .csv of discs)");
  if (cx.dimension == 2)
    r.fail(node, t.ctx + ": a DFN file holds 3-D fractures, and this is a 2-D scene",
           "give a 2-D scene's joints as [[joints]] segments or [[sets]]");
  const std::string file_text = to_text(r, node, t.label("file"));
  if (file_text.find('\0') != std::string::npos)  // the system would read the path up to it
    r.fail(node, t.label("file") + " holds a NUL character", "remove the \\u0000 from the path");
  const std::filesystem::path given = file_text;
  DfnEntry d;
  d.file = given.is_absolute() ? given : cx.dir / given;
  const DfnFile dfn = read_file_of(cx, t, node, d.file);
  const std::string in_file = t.label("file") + ": " + d.file.string();

  const DfnProps base = read_props(t, DfnProps{});
  std::vector<DfnProps> props(dfn.sets.size(), base);
  if (const toml::node* sn = t.find("sets")) {
    const Tbl st{r,
                 as_table(r, *sn, t.label("sets"), "write sets = { J1 = { friction_angle = 25 } }"),
                 "'sets' of " + t.ctx};
    std::vector<std::string_view> known(dfn.sets.begin(), dfn.sets.end());
    st.check_keys(known);
    for (std::size_t s = 0; s < dfn.sets.size(); ++s)
      if (const toml::node* one = st.find(dfn.sets[s])) {
        const Tbl set{r, as_table(r, *one, st.label(dfn.sets[s]), "write { friction_angle = 25 }"),
                      "set \"" + dfn.sets[s] + "\" of " + t.ctx};
        set.check_keys(kDfnSetKeys);
        props[s] = read_props(set, base);
      }
  }
  const double planarity =
      t.find("planarity")
          ? positive(
                t, "planarity",
                "give the largest distance of a node from its fracture's plane, relative to the "
                "fracture's radius, e.g. 1e-4")
          : kDefaultPlanarity;

  // The file's sets, with their properties; each joint takes its set's.
  std::vector<JointSetSpec> specs;
  for (std::size_t s = 0; s < dfn.sets.size(); ++s) {
    Joint like;
    give(props[s], like);
    specs.push_back(given_set(dfn.sets[s], like));
  }
  for (const DfnFracture& f : dfn.fractures) {
    Joint j;
    if (f.disc) {
      const JointFrame frame = plane_frame(f.dip_deg, f.dip_direction_deg);
      j.dip_deg = f.dip_deg;
      j.dip_direction_deg = f.dip_direction_deg;
      j.centre = f.centre;
      j.plane = {frame.n, frame.n.dot(f.centre)};
      j.polygon_uv = f.polygon_uv;
      double reach = 0;  // the disc's polygon's size: a radius of 1e-300 or 1e308 is a slip
      bool finite = true;
      for (const Vec2& uv : j.polygon_uv) {
        finite = finite && uv.allFinite();
        reach = std::max(reach, uv.stableNorm());  // no overflow of the squares at 1e160
      }
      if (!finite || !(reach > cx.tol()))
        r.fail(node,
               in_file + ":" + std::to_string(f.line) + ": disc " + f.id + " reaches " +
                   fmt(reach, 3) + " from its centre, not a size between the tolerance " +
                   fmt(cx.tol(), 3) + " and a finite length",
               "check the radius and its unit against the domain's");
      // A radius of 1e160 is finite, but its polygon's edges are not (issue 42 item 14): a disc
      // so far out or so large that doubles step by more than the tolerance is refused here.
      const Vec3 far = Vec3::Constant(reach);
      if (const std::string why = precision_problem(f.centre - far, f.centre + far, cx.tol(),
                                                    "the disc (its centre x, y, z and radius)");
          !why.empty())
        r.fail(node,
               in_file + ":" + std::to_string(f.line) + ": disc " + f.id +
                   " is too large or too far out: " + why,
               "check its radius and centre, and their unit, against the domain's");
    } else if (const std::string why = f.tessellated
                                           ? tessellated_joint(f, cx.tol(), planarity, j)
                                           : polygon_joint(f.nodes, cx.tol(), planarity, j);
               !why.empty()) {
      r.fail(node,
             in_file + ":" + std::to_string(f.line) + ": " +
                 (f.tessellated ? "tessellated fracture " : "fracture ") + f.id + " " + why,
             why.rfind("is too", 0) == 0
                 ? "check the fracture's coordinates and their unit against the domain's"
             : f.tessellated && why.rfind("is not planar", 0) != 0
                 ? "split it into convex polygons (the FRACTURE section), whose joints rockslice "
                   "cuts"
                 : "correct the fracture's nodes, or raise 'planarity' in " + t.ctx +
                       " if they carry few digits");
    }
    set_joint_properties(j, specs[f.set], static_cast<std::int32_t>(first_set + f.set));
    d.joints.push_back(std::move(j));
  }
  // The file's own order (as-given), or sorted within the entry by `order`.
  if (const toml::node* n = t.find("order")) {
    const auto order =
        static_cast<JointOrder>(to_choice(r, *n, t.label("order"), kJointOrderNames));
    std::vector<EntryPlace> by(d.joints.size());
    for (std::size_t i = 0; i < d.joints.size(); ++i)
      by[i] = {1, order == JointOrder::largest_first ? 0 : std::int64_t{d.joints[i].set}, 0};
    order_joints(d.joints, order, by);
  }
  const EntryPlace place = read_place(r, tt, t.ctx, entry);
  for (const Joint& j : d.joints)
    d.places.push_back({props[std::size_t(j.set) - first_set].stage, place.line, place.entry});
  for (std::size_t s = 0; s < dfn.sets.size(); ++s) {
    if (!names.insert(dfn.sets[s]).second)
      r.fail(node, in_file + ": its set \"" + dfn.sets[s] + "\" has the name of another set",
             "rename one of them (in the file, or the other set's name)");
    d.sets.push_back(specs[s]);
    d.set_places.push_back({props[s].stage, place.line, place.entry});
  }
  return d;
}

void assign_joint_sets(const Context& cx, const std::vector<const toml::table*>& tables,
                       Scene& scene) {
  const Reader& r = cx.r;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const toml::node* n = tables[i]->get("set");
    if (!n) continue;
    const std::string label = quote_key("set") + " in [[joints]] #" + std::to_string(i + 1);
    const std::string name = to_text(r, *n, label);
    if (name.find('\0') != std::string::npos)  // HDF5 strings end at a NUL
      r.fail(*n, label + " holds a NUL character", "remove the \\u0000 from the set's name");
    Joint& j = scene.joints[i];
    auto it = std::find_if(scene.sets.begin(), scene.sets.end(),
                           [&](const JointSetSpec& s) { return s.name == name; });
    if (it != scene.sets.end() && it->intensity != SetIntensity::deterministic)
      r.fail(*n, label + " names the [[sets]] entry \"" + name + "\", whose joints are generated",
             "give the joint a set of its own name, or the name of a [[dfn]] file's set");
    if (it == scene.sets.end()) {  // the first joint of a new set gives it its properties
      scene.sets.push_back(given_set(name, j));
      scene.set_places.push_back(scene.joint_places[i]);
      it = scene.sets.end() - 1;
    }
    // 3DEC gives a joint set one set of properties (export_3dec.hpp): its joints share them.
    const JointSetSpec& s = *it;
    std::string differs;
    if (j.kind != s.kind)
      differs =
          "kind " + std::string(to_string(j.kind)) + " (the set's: " + to_string(s.kind) + ")";
    else if (j.friction_angle_deg != s.friction_angle_deg)
      differs = "friction_angle " + fmt(j.friction_angle_deg) +
                " (the set's: " + fmt(s.friction_angle_deg) + ")";
    else if (j.cohesion != s.cohesion)
      differs = "cohesion " + fmt(j.cohesion) + " (the set's: " + fmt(s.cohesion) + ")";
    else if (j.tension != s.tension)
      differs = "tension " + fmt(j.tension) + " (the set's: " + fmt(s.tension) + ")";
    else if (j.boundary_side != s.boundary_side)
      differs = "keep (the set's differs)";
    if (!differs.empty())
      r.fail(*n, label + ": the joint's " + differs + " differs from set \"" + name + "\"",
             "a set's joints share kind, keep, friction_angle, cohesion and tension (3DEC gives "
             "each joint set one set of properties): make them equal, or name another set");
    j.set = static_cast<std::int32_t>(it - scene.sets.begin());
  }
}

}  // namespace slice::scene_read

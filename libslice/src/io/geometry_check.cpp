#include "geometry_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace slice {
namespace {

constexpr const char* kInertiaNames[] = {"xx", "yy", "zz", "xy", "yz", "zx"};

std::string g6(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v + 0.0);  // + 0.0: "0", not "-0"
  return buf;
}

std::string g6(const Vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", v.x(), v.y(), v.z());
  return buf;
}

// Whether the loop [lo, hi) of face_vertices names a vertex twice: pairwise for the short loops
// of real blocks, sorted for a long one (a damaged file must not cost quadratic time).
bool repeats(const std::vector<std::int64_t>& fv, std::size_t lo, std::size_t hi) {
  if (hi - lo > 16) {
    std::vector<std::int64_t> s;
    s.reserve(hi - lo);
    for (std::size_t i = lo; i < hi; ++i) s.push_back(fv[i]);
    std::sort(s.begin(), s.end());
    return std::adjacent_find(s.begin(), s.end()) != s.end();
  }
  for (std::size_t i = lo; i < hi; ++i)
    for (std::size_t k = i + 1; k < hi; ++k)
      if (fv[i] == fv[k]) return true;
  return false;
}

// An edge's length for the tolerances of areas, which grow with the perimeter: `exact`, the
// length; otherwise its largest component, no more than the length as computed (sqrt(fl(x^2)) is
// |x|, and rounding keeps sums in order), and no square root to wait for. A check that passes with
// it passes with the length.
double edge_length(const Vec3& e, bool exact) { return exact ? e.norm() : e.cwiseAbs().maxCoeff(); }

// geometry_value_problem; `exact` false: perimeters from edge_length's lower bounds, and a check
// they fail is made again with the lengths (problem(..., true)), which decides and words it.
std::string problem(const Geometry& g, const Block& blk, std::size_t b, std::size_t face_row,
                    const GeometryBase& base, double tol, bool section, bool exact) {
  // Labels are made only for a message: this runs on every block of million-block files.
  const auto block = [&] { return "block " + std::to_string(base.block + b); };
  const auto v0 = static_cast<std::size_t>(g.vertex_offset[b]);
  const auto v1 = static_cast<std::size_t>(g.vertex_offset[b + 1]);
  // Everything relative to the block's origin (its Chebyshev centre): small coordinates.
  const auto x = [&](std::int64_t local) -> Vec3 {
    return g.vertices[v0 + std::size_t(local)] - blk.origin;
  };
  double reach2 = 0;  // the farthest vertex from the origin, squared
  for (std::size_t v = v0; v < v1; ++v) {
    if (section && std::abs(g.vertices[v].y()) > tol)
      return "/geometry/vertices row " + std::to_string(std::size_t(base.vertex) + v) +
             " has y = " + g6(g.vertices[v].y()) +
             "; a 2-D file (root attribute dimension 2) has y = 0 everywhere";
    reach2 = std::max(reach2, (g.vertices[v] - blk.origin).squaredNorm());
  }
  const double reach = std::sqrt(reach2);  // the largest norm: the square root is monotonic

  // Per face: the loop's area vector s (3-D: half of Newell's vector; 2-D: the edge turned
  // outward, y x e, its length the edge's), whose component along the outward normal is the
  // face's signed area; and the cone from the origin over the loop, for volume and centroid
  // (3-D: tetrahedra D = x0 . (xk x xk+1) = 6 V; 2-D: triangles c = x0 . s = 2 A).
  // Summed with the weights c (2-D) or D (3-D) and divided once at the end (no division per
  // triangle or tetrahedron): the volume (c / 2, D / 6), its moment (c / 6, D / 24) and the second
  // moments about the origin, the integral of r r^T (c / 24, D / 120), in Inertia's order xx yy zz
  // xy yz zx. The check's tolerances are far above the roundings this moves.
  double enclosed = 0, area_sum = 0, perimeter_sum = 0;
  Vec3 moment = Vec3::Zero(), closure = Vec3::Zero();
  Inertia second{};
  // r r^T in Inertia's order, and second += w (sum of such).
  const auto outer = [](const Vec3& r) -> Inertia {
    return {r.x() * r.x(), r.y() * r.y(), r.z() * r.z(),
            r.x() * r.y(), r.y() * r.z(), r.z() * r.x()};
  };
  const auto add = [&](double w, const Inertia& sum) {
    for (std::size_t k = 0; k < 6; ++k) second[k] += w * sum[k];
  };
  for (std::size_t f = 0; f < blk.faces.size(); ++f) {
    const std::size_t face = face_row + f, file_face = base.face + face;
    const auto lo = static_cast<std::size_t>(g.face_vertex_offset[face]);
    const auto hi = static_cast<std::size_t>(g.face_vertex_offset[face + 1]);
    const auto loop = [&] {
      return "the loop of face " + std::to_string(file_face) + " of " + block() +
             " (/geometry/face_vertices rows " +
             std::to_string(std::size_t(base.face_vertex) + lo) + " to " +
             std::to_string(std::size_t(base.face_vertex) + hi - 1) + ")";
    };
    if (repeats(g.face_vertices, lo, hi))
      return loop() + " visits a vertex twice; a face's loop visits each of its vertices once";
    Vec3 s = Vec3::Zero();
    double perimeter = 0;
    const Vec3 a = x(g.face_vertices[lo]);
    if (section) {
      const Vec3 e = x(g.face_vertices[lo + 1]) - a;
      s = {e.z(), 0, -e.x()};
      perimeter = edge_length(e, exact);
      const double c = a.dot(s);
      enclosed += c;
      moment += c * (a + a + e);
      // A triangle (0, a, b) of area A: integral r r^T = A / 12 (a a^T + b b^T + s s^T).
      const Inertia ra = outer(a), rb = outer(a + e), rs = outer(a + a + e);
      Inertia sum;
      for (std::size_t k = 0; k < 6; ++k) sum[k] = ra[k] + rb[k] + rs[k];
      add(c, sum);
    } else {
      // The fan from a: each vertex's r r^T once, a's for every tetrahedron.
      const Inertia ra = outer(a);
      Vec3 p = a;
      Inertia rp = ra;
      for (std::size_t k = lo; k < hi; ++k) {
        const Vec3 q = x(g.face_vertices[k + 1 < hi ? k + 1 : lo]);
        const Vec3 pq = p.cross(q);
        s += pq / 2;
        perimeter += edge_length(q - p, exact);
        const Inertia rq = outer(q);
        if (k > lo && k + 1 < hi) {
          const double d = a.dot(pq);
          enclosed += d;
          moment += d * (a + p + q);
          // A tetrahedron (0, a, p, q): integral r r^T = D / 120 (a a^T + ... + s s^T).
          const Inertia rs = outer(a + p + q);
          Inertia sum;
          for (std::size_t m = 0; m < 6; ++m) sum[m] = ((ra[m] + rp[m]) + rq[m]) + rs[m];
          add(d, sum);
        }
        p = q;
        rp = rq;
      }
    }
    const double area = blk.faces[f].normal.dot(s);
    // A vertex may lie `tol` off its place: an area moves by up to tol x perimeter.
    const double area_tol = tol * perimeter;
    if (!exact && (area < -area_tol || std::abs(area - g.face_area[face]) > area_tol))
      return problem(g, blk, b, face_row, base, tol, section, true);
    if (area < -area_tol)
      return loop() + " runs clockwise seen from outside (its area " + g6(area) +
             " is negative about the face normal); a loop runs counter-clockwise, right-handed "
             "about the outward normal";
    if (std::abs(area - g.face_area[face]) > area_tol)
      return "/geometry/face_area row " + std::to_string(file_face) + " is " +
             g6(g.face_area[face]) + ", but " + loop() + " encloses " + g6(area) + " (tolerance " +
             g6(area_tol) + ")";
    closure += s;
    area_sum += std::abs(area);
    perimeter_sum += perimeter;
  }
  enclosed /= section ? 2 : 6;
  moment /= section ? 6 : 24;
  for (double& v : second) v /= section ? 24 : 120;
  // A closed surface's area vectors sum to zero: a missing or extra loop shows here.
  if (!exact && closure.norm() > 2 * tol * perimeter_sum)
    return problem(g, blk, b, face_row, base, tol, section, true);
  if (closure.norm() > 2 * tol * perimeter_sum)
    return "the loops of " + block() + " do not close: their area vectors sum to " + g6(closure) +
           " (tolerance " + g6(2 * tol * perimeter_sum) + "); each face's loop must bound it";
  // The volume moves by up to tol x the surface area as the vertices move by tol.
  const double volume_tol = 2 * tol * area_sum;
  if (std::abs(enclosed - g.volume[b]) > volume_tol)
    return "/geometry/volume row " + std::to_string(base.block + b) + " is " + g6(g.volume[b]) +
           ", but the vertices and loops of " + block() + " enclose " + g6(enclosed) +
           " (tolerance " + g6(volume_tol) + ")";

  const Vec3& c = g.centroid[b];
  const auto centroid = [&] {
    return "/geometry/centroid row " + std::to_string(base.block + b) + " " + g6(c);
  };
  if (section && std::abs(c.y()) > tol)
    return centroid() + " has y = " + g6(c.y()) +
           "; a 2-D file (root attribute dimension 2) has y = 0 everywhere";
  for (std::size_t f = 0; f < blk.faces.size(); ++f) {
    const double off = blk.faces[f].normal.dot(c - blk.origin) - blk.faces[f].d;
    if (off > tol)
      return centroid() + " lies " + g6(off) + " outside face " +
             std::to_string(base.face + face_row + f) + " of " + block() + " (tolerance " +
             g6(tol) + "); a centroid lies inside its block";
  }
  // The centroid moves by (moment error + |c| x volume error) / volume, each error up to
  // tol x area x reach.
  if (enclosed > 0) {
    const Vec3 want = blk.origin + moment / enclosed;
    const double centroid_tol = tol + 4 * tol * area_sum * reach / enclosed;
    if ((c - want).norm() > centroid_tol)
      return centroid() + " is not the centroid of " + block() + ": its vertices and loops give " +
             g6(want) + " (tolerance " + g6(centroid_tol) + ")";
    // About the centroid, I = trace(C) Id - C with C = second - V m m^T (m = moment / V): in
    // 2-D, where C has no y, that is docs/2d.md's section moments. Each entry moves by up to
    // about 12 tol x area x reach^2 (second and V m m^T, each up to 3 tol x area x reach^2).
    const Vec3 m = moment / enclosed;
    const Inertia cov{second[0] - enclosed * m.x() * m.x(), second[1] - enclosed * m.y() * m.y(),
                      second[2] - enclosed * m.z() * m.z(), second[3] - enclosed * m.x() * m.y(),
                      second[4] - enclosed * m.y() * m.z(), second[5] - enclosed * m.z() * m.x()};
    const double trace = cov[0] + cov[1] + cov[2];
    const Inertia inertia{trace - cov[0], trace - cov[1], trace - cov[2],
                          -cov[3],        -cov[4],        -cov[5]};
    const double inertia_tol = 16 * tol * area_sum * reach * reach;
    for (std::size_t k = 0; k < 6; ++k)
      if (std::abs(g.inertia[b][k] - inertia[k]) > inertia_tol)
        return "/geometry/inertia row " + std::to_string(base.block + b) + " column " +
               std::to_string(k) + " (" + kInertiaNames[k] + ") is " + g6(g.inertia[b][k]) +
               ", but the vertices and loops of " + block() + " give " + g6(inertia[k]) +
               " (tolerance " + g6(inertia_tol) + ")";
  }
  return {};
}

}  // namespace

std::string geometry_value_problem(const Geometry& g, const Block& blk, std::size_t b,
                                   std::size_t face_row, const GeometryBase& base, double tol,
                                   bool section) {
  return problem(g, blk, b, face_row, base, tol, section, false);
}

}  // namespace slice

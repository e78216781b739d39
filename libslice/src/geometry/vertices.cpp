#include "slice/vertices.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cfenv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <span>
#include <string>
#include <utility>

#include "../prefetch.hpp"
#include "../threads.hpp"
#include "slice/error.hpp"
#include "slice/lp.hpp"

namespace slice {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = std::array<std::size_t, 3>;
using Clock = std::chrono::steady_clock;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string block_name(std::size_t id) { return "block " + std::to_string(id); }

std::string face_name(const Block& b, std::size_t f) {
  const std::int64_t j = b.faces[f].joint;
  return "face " + std::to_string(f) +
         (j < 0 ? std::string(" (a domain face)") : " (joint " + std::to_string(j) + ")");
}

/// Throws unless every vertex (relative to `centre`, block frame) lies inside every face of
/// the block to within the geometry tolerance.
void check_inside(const Block& b, const std::vector<Vec3>& local, const Vec3& centre,
                  const Tolerances& tol, std::size_t id) {
  // A pass with each face's offset from the centre worked out once; the one that names the
  // first vertex outside (the same values) only where there is one.
  bool outside = false;
  for (const Face& fc : b.faces) {
    const double d = fc.d - fc.normal.dot(centre);
    for (const Vec3& x : local) outside |= fc.normal.dot(x) - d > tol.geometry;
  }
  if (!outside) return;
  for (std::size_t v = 0; v < local.size(); ++v)
    for (std::size_t f = 0; f < b.faces.size(); ++f) {
      const Face& fc = b.faces[f];
      const double out = fc.normal.dot(local[v]) - (fc.d - fc.normal.dot(centre));
      if (out > tol.geometry)
        throw Error(block_name(id),
                    "vertex " + std::to_string(v) + " lies " + num(out) + " outside " +
                        face_name(b, f) + " (tolerance " + num(tol.geometry) + ")",
                    "the block is too ill-conditioned for its tolerance; please report it");
    }
}

constexpr const char* kSlicerFix =
    "the slicer left a face without area (a defect of slice-cut / slice-prune at this "
    "tolerance); please report it with the scene file";

/// The vertex where the three planes n . x = d meet (the facet of the dual hull through
/// n_i / d_i, n_j / d_j, n_k / d_k). Not finite if the normals are linearly dependent.
Vec3 meet(const Face& a, const Face& b, const Face& c, const Vec3& centre) {
  const double da = a.d - a.normal.dot(centre);
  const double db = b.d - b.normal.dot(centre);
  const double dc = c.d - c.normal.dot(centre);
  const Vec3 bc = b.normal.cross(c.normal);
  const double det = a.normal.dot(bc);
  return (da * bc + db * c.normal.cross(a.normal) + dc * a.normal.cross(b.normal)) / det;
}

/// The area of a face's loop about its normal, and in `bound` a bound on its perimeter without
/// square roots: the sum of its edges' L1 lengths (with rounding, loop_perimeter stays below
/// bound * (1 + 1e-9) for any loop of fewer than a million vertices).
double loop_area(const std::vector<Vec3>& v, const std::vector<std::int64_t>& loop,
                 const Vec3& normal, double* bound) {
  Vec3 s = Vec3::Zero();
  double p = 0;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const Vec3& a = v[std::size_t(loop[k])];
    const Vec3& b = v[std::size_t(loop[(k + 1) % loop.size()])];
    s += a.cross(b);
    p += (b - a).cwiseAbs().sum();
  }
  *bound = p;
  return normal.dot(s) / 2;
}

double loop_perimeter(const std::vector<Vec3>& v, const std::vector<std::int64_t>& loop) {
  double p = 0;
  for (std::size_t k = 0; k < loop.size(); ++k)
    p += (v[std::size_t(loop[(k + 1) % loop.size()])] - v[std::size_t(loop[k])]).norm();
  return p;
}

// ---- The dual hull's orientation predicate, exact on floating-point expansions (J. R. Shewchuk,
// "Adaptive precision floating-point arithmetic and fast robust geometric predicates", Discrete
// Comput. Geom. 18 (1997) 305-363): a number held exactly as a sum of doubles, nonoverlapping,
// in increasing magnitude, without zeros; its sign is that of its last (largest) component.

/// x + y = a + b exactly, x = fl(a + b) (Knuth's two-sum).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

/// x + y = a * b exactly, x = fl(a * b), for a, b in exact_range: by a fused multiply-add where
/// the compiler has one, else by Dekker's split (halves of 26 bits, whose products are exact).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
#ifdef __FMA__
  y = std::fma(a, b, -x);
#else
  const auto split = [](double v, double& hi, double& lo) {
    const double c = 134217729.0 * v;  // 2^27 + 1
    hi = c - (c - v);
    lo = v - hi;
  };
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  y = al * bl - (((x - ah * bh) - al * bh) - ah * bl);
#endif
}

/// Adds b to the expansion e[0, n) in place (Shewchuk's Grow-Expansion, zeros dropped); e has
/// room for n + 1. Returns the new length.
inline int grow(double* e, int n, double b) {
  double q = b;
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double s, t;
    two_sum(q, e[i], s, t);
    if (t != 0) e[m++] = t;
    q = s;
  }
  if (q != 0) e[m++] = q;
  return m;
}

/// Adds sign times the expansion f[0, nf) to e[0, n) in place (sign +-1; e has room for n + nf).
/// Returns the new length.
inline int add(double* e, int n, const double* f, int nf, double sign) {
  for (int i = 0; i < nf; ++i) n = grow(e, n, sign * f[i]);
  return n;
}

/// Adds b times the expansion f[0, nf) to e[0, n) in place, exactly (e has room for n + 2 nf; the
/// products' rounding errors are normal doubles: exact_range). Returns the new length.
inline int add_scaled(double* e, int n, const double* f, int nf, double b) {
  for (int i = 0; i < nf; ++i) {
    double x, y;
    two_product(f[i], b, x, y);
    n = grow(e, n, y);
    n = grow(e, n, x);
  }
  return n;
}

/// A 2x2 minor u_i v_j - v_i u_j of two points, exactly (at most 4 components).
struct Minor {
  double e[4];
  int n = 0;
  Minor(const Point& u, const Point& v, int i, int j) {
    double p, pe, q, qe;
    two_product(u[i], v[j], p, pe);
    two_product(v[i], u[j], q, qe);
    n = grow(e, grow(e, grow(e, grow(e, 0, pe), p), -qe), -q);
  }
};

/// Nonzero coordinates in this range keep every product of three of them, and the rounding
/// errors of such products, normal doubles: the expansions are exact and the filter's bound holds.
constexpr double kExactMin = 0x1p-250, kExactMax = 0x1p+250;

bool exact_range(const Point& p) {
  for (int k = 0; k < 3; ++k) {
    const double a = std::abs(p[k]);
    if (a != 0 && !(a >= kExactMin && a <= kExactMax)) return false;
  }
  return true;
}

/// The sign of the 4x4 determinant D of the rows (x, y, z, 1) of a, b, c, d, exactly, by the 2x2
/// minors of (x, y) (uv = u_x v_y - v_x u_y; Shewchuk's orient3dexact):
/// D = z_a (bc + cd - bd) + z_b (ad - ac - cd) + z_c (ab + bd - ad) - z_d (ab + bc - ac).
int determinant_sign(const Point& a, const Point& b, const Point& c, const Point& d) {
  const Minor ab(a, b, 0, 1), ac(a, c, 0, 1), ad(a, d, 0, 1), bc(b, c, 0, 1), bd(b, d, 0, 1),
      cd(c, d, 0, 1);
  double sum[96];  // four terms of at most 2 x 12 components
  int n = 0;
  // Adds z (u + v - w) to the sum.
  const auto term = [&](double z, const Minor& u, const Minor& v, const Minor& w) {
    if (z == 0) return;
    double t[12];
    int m = add(t, 0, u.e, u.n, 1);
    m = add(t, m, v.e, v.n, 1);
    m = add(t, m, w.e, w.n, -1);
    n = add_scaled(sum, n, t, m, z);
  };
  term(a.z(), bc, cd, bd);
  term(-b.z(), ac, cd, ad);
  term(c.z(), ab, bd, ad);
  term(-d.z(), ab, bc, ac);
  return n == 0 ? 0 : sum[n - 1] > 0 ? 1 : -1;
}

/// The sign of det [a; b; c] = a . (b x c), exactly (the 4x4 determinant of a, b, c and the
/// origin, by the 2x2 minors of b and c).
int determinant_sign_3(const Point& a, const Point& b, const Point& c) {
  double sum[24];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const Minor m(b, c, (k + 1) % 3, (k + 2) % 3);  // (b x c)_k
    if (a[k] != 0) n = add_scaled(sum, n, m.e, m.n, a[k]);
  }
  return n == 0 ? 0 : sum[n - 1] > 0 ? 1 : -1;
}

bool antipodal(const Point& a, const Point& b) {
  return a.x() == -b.x() && a.y() == -b.y() && a.z() == -b.z();
}

/// The sign of D (above) where two of the points are antipodal (each the other's negation: the
/// dual points of parallel faces as far from the centre, which is where slice-cut puts a block's
/// origin). Moved to a and b = -a (a sign per swap), D = 2 det [a; c; d]: 0 if c and d are
/// antipodal too (four points in a plane through the origin). 2 (no sign) if no two are.
int antipodal_sign(const Point& p, const Point& q, const Point& r, const Point& s) {
  const Point* v[4] = {&p, &q, &r, &s};
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 4; ++j) {
      if (!antipodal(*v[i], *v[j])) continue;
      int sign = 1;
      if (i != 0) std::swap(v[0], v[i]), sign = -sign;
      if (j != 1) std::swap(v[1], v[j]), sign = -sign;
      if (antipodal(*v[2], *v[3])) return 0;
      return sign * determinant_sign_3(*v[0], *v[2], *v[3]);
    }
  return 2;
}

/// CGAL::orientation(p, q, r, s) (the sign of det [q - p; r - p; s - p], which is -D above) for
/// points in exact_range, exactly: Shewchuk's orient3d error bound first, the expansions only
/// for (nearly) coplanar points.
CGAL::Orientation orientation_3(const Point& p, const Point& q, const Point& r, const Point& s) {
  const double adx = p.x() - s.x(), bdx = q.x() - s.x(), cdx = r.x() - s.x();
  const double ady = p.y() - s.y(), bdy = q.y() - s.y(), cdy = r.y() - s.y();
  const double adz = p.z() - s.z(), bdz = q.z() - s.z(), cdz = r.z() - s.z();
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                           (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                           (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
  constexpr double kEps = 0x1p-53;
  constexpr double kBound = (7 + 56 * kEps) * kEps;  // Shewchuk's o3derrboundA
  const double bound = kBound * permanent;
  if (det > bound) return CGAL::NEGATIVE;
  if (-det > bound) return CGAL::POSITIVE;
  int sign = antipodal_sign(p, q, r, s);
  if (sign == 2) sign = determinant_sign(p, q, r, s);
  return sign > 0 ? CGAL::NEGATIVE : sign < 0 ? CGAL::POSITIVE : CGAL::COPLANAR;
}

/// The orientation predicate of a point set: orientation_3 if every point is in exact_range
/// (and rounding is to nearest, as the expansions need), else CGAL's (filtered, with a
/// multiprecision fallback). Both are exact: the same signs.
struct Orientation3 {
  bool expansions = true;
  explicit Orientation3(const std::vector<Point>& pts)
      : expansions(std::fegetround() == FE_TONEAREST &&
                   std::all_of(pts.begin(), pts.end(), exact_range)) {}
  CGAL::Orientation operator()(const Point& p, const Point& q, const Point& r,
                               const Point& s) const {
    return expansions ? orientation_3(p, q, r, s) : CGAL::orientation(p, q, r, s);
  }
};

/// The convex hull of `pts` as triangles (indices into pts), counter-clockwise seen from
/// outside. Incremental, with an exact orientation predicate (Orientation3: exact arithmetic
/// only for (nearly) coplanar points; most of those, two pairs of parallel faces, without any),
/// so the result is a consistent closed surface whatever
/// the rounding: coplanar points give a triangulated polygon, points inside or on the hull are
/// left out. Empty if the points do not span a solid. Meant for the tens of points of a block:
/// O(n^2). (CGAL::convex_hull_3 gives the same hull but spends 20-30 us per block in list
/// allocations and exact fallbacks of its distance comparisons.)
/// Its working arrays, kept by the caller from block to block (no allocation per block).
struct HullScratch {
  std::vector<char> visible;
  std::vector<std::array<std::size_t, 2>> horizon;
};

void convex_hull(const std::vector<Point>& pts, const Orientation3& orientation,
                 std::vector<Triangle>& hull, HullScratch& s) {
  hull.clear();
  const std::size_t n = pts.size();
  // A first tetrahedron: p0, p1 != p0, p2 off the line p0 p1, p3 off the plane p0 p1 p2.
  std::size_t i1 = 1, i2 = 0, i3 = 0;
  while (i1 < n && pts[i1] == pts[0]) ++i1;
  for (i2 = i1 + 1; i2 < n && CGAL::collinear(pts[0], pts[i1], pts[i2]); ++i2) {
  }
  CGAL::Orientation o = CGAL::COPLANAR;
  for (i3 = i2 + 1; i3 < n; ++i3)
    if ((o = orientation(pts[0], pts[i1], pts[i2], pts[i3])) != CGAL::COPLANAR) break;
  if (i1 >= n || i2 >= n || i3 >= n) return;
  std::size_t a = 0, b = i1, c = i2;
  if (o == CGAL::POSITIVE) std::swap(b, c);  // now i3 is below the plane a b c
  const std::size_t d = i3;
  hull = {{a, b, c}, {a, d, b}, {b, d, c}, {c, d, a}};

  auto& visible = s.visible;
  auto& horizon = s.horizon;
  for (std::size_t p = 1; p < n; ++p) {
    if (p == i1 || p == i2 || p == i3) continue;
    visible.assign(hull.size(), 0);
    bool any = false;
    for (std::size_t t = 0; t < hull.size(); ++t)
      if (orientation(pts[hull[t][0]], pts[hull[t][1]], pts[hull[t][2]], pts[p]) == CGAL::POSITIVE)
        visible[t] = any = true;
    if (!any) continue;  // inside or on the hull
    // Horizon: directed edges of visible triangles whose reverse is not in a visible one.
    horizon.clear();
    for (std::size_t t = 0; t < hull.size(); ++t) {
      if (!visible[t]) continue;
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t u = hull[t][k], v = hull[t][(k + 1) % 3];
        bool inner = false;
        for (std::size_t q = 0; q < hull.size() && !inner; ++q)
          if (visible[q] && q != t)
            for (std::size_t m = 0; m < 3; ++m)
              if (hull[q][m] == v && hull[q][(m + 1) % 3] == u) inner = true;
        if (!inner) horizon.push_back({u, v});
      }
    }
    std::size_t keep = 0;
    for (std::size_t t = 0; t < hull.size(); ++t)
      if (!visible[t]) hull[keep++] = hull[t];
    hull.resize(keep);
    for (const auto& e : horizon) hull.push_back({e[0], e[1], p});
  }
}

/// The block's interior point the dual hull is built about, block frame: the origin when it is
/// well inside (slice-cut puts it at the Chebyshev centre), else the Chebyshev centre (of the
/// polygon, y = 0, in a section: tol.dimension).
Vec3 hull_centre(const Block& b, const Tolerances& tol, std::size_t id) {
  double min_d = b.faces.front().d;
  for (const Face& f : b.faces) min_d = std::min(min_d, f.d);
  if (min_d > tol.geometry && min_d >= 0.5 * b.inradius) return Vec3::Zero();
  const auto solver = make_solver(LpBackend::native);
  const ChebyshevBall c = chebyshev_ball(*solver, b.faces, tol);
  if (c.status != LpStatus::optimal || c.radius <= tol.geometry)
    throw Error(block_name(id),
                "its faces leave no interior (Chebyshev LP: " + to_string(c.status) + ", radius " +
                    num(c.radius) + ")",
                "regenerate the blocks with slice-cut");
  return c.centre;
}

// ---- 2-D: a block of a section in (x, z) (docs/2d.md) is a convex polygon, one face per edge.

using Point2 = Kernel::Point_2;

/// The section's coordinates of a vector: (x, z), so that counter-clockwise in CGAL's plane is
/// counter-clockwise in the section drawn with x to the right and z up.
Point2 section_point(const Vec3& v) { return {v.x(), v.z()}; }

/// A face normal of a section has y = 0 (sind/cosd make it exactly 0; see Numerics in
/// STYLE.md); this much is allowed for normals written by other tools.
constexpr double kSectionNormalY = 1e-12;

/// The convex hull of `pts` as indices, counter-clockwise, without points on its edges
/// (Andrew's monotone chain with CGAL's exact orientation predicate, so (nearly) collinear
/// points cannot make an inconsistent hull). Fewer than 3 if the points span no area.
std::vector<std::size_t> convex_hull_2(const std::vector<Point2>& pts) {
  std::vector<std::size_t> order(pts.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  // Ties by index: duplicates keep a fixed order, so the hull is the same on every run.
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (pts[a].x() != pts[b].x()) return pts[a].x() < pts[b].x();
    if (pts[a].y() != pts[b].y()) return pts[a].y() < pts[b].y();
    return a < b;
  });
  std::vector<std::size_t> hull;
  if (order.size() < 3) return hull;
  const auto chain = [&](auto first, auto last) {
    const std::size_t base = hull.size();
    for (auto it = first; it != last; ++it) {
      while (hull.size() >= base + 2 &&
             CGAL::orientation(pts[hull[hull.size() - 2]], pts[hull.back()], pts[*it]) !=
                 CGAL::LEFT_TURN)
        hull.pop_back();
      hull.push_back(*it);
    }
    hull.pop_back();  // the last point starts the other chain
  };
  chain(order.begin(), order.end());    // lower chain, left to right
  chain(order.rbegin(), order.rend());  // upper chain, right to left
  return hull;
}

/// The vertex where the lines n . x = d of two faces meet, relative to `centre` (y = 0).
Vec3 meet_2d(const Face& a, const Face& b, const Vec3& centre) {
  const double da = a.d - a.normal.dot(centre), db = b.d - b.normal.dot(centre);
  const double det = a.normal.x() * b.normal.z() - a.normal.z() * b.normal.x();
  return {(da * b.normal.z() - db * a.normal.z()) / det, 0,
          (a.normal.x() * db - b.normal.x() * da) / det};
}

/// Area, centroid and second moments of a counter-clockwise polygon in (x, z) (y = 0), by
/// triangles from the origin of `v` (the block's interior point: small coordinates).
/// Inertia as docs/2d.md stores it: xx = integral z^2 dA, zz = integral x^2 dA, yy = xx + zz
/// (the polar moment), zx = -integral x z dA, xy = yz = 0, about the centroid. The product's
/// minus sign is the 3-D convention (mass_properties: I = integral (|r|^2 Id - r r^T), so
/// zx = -integral z x dV; a unit-thickness prism of the polygon has the same zx). Unlike the
/// prism's, xx and zz leave out its integral of y^2 (1/12 per unit area): they are the
/// section's moments.
MassProperties polygon_mass_properties(const std::vector<Vec3>& v) {
  double a2 = 0, sx = 0, sz = 0, sxx = 0, szz = 0, sxz = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const double x0 = v[k].x(), z0 = v[k].z();
    const double x1 = v[(k + 1) % v.size()].x(), z1 = v[(k + 1) % v.size()].z();
    const double c = x0 * z1 - x1 * z0;  // twice the signed area of (origin, k, k + 1)
    a2 += c;
    sx += (x0 + x1) * c;
    sz += (z0 + z1) * c;
    sxx += (x0 * x0 + x0 * x1 + x1 * x1) * c;
    szz += (z0 * z0 + z0 * z1 + z1 * z1) * c;
    sxz += (x0 * z1 + 2 * x0 * z0 + 2 * x1 * z1 + x1 * z0) * c;
  }
  MassProperties mp;
  mp.volume = a2 / 2;
  if (!(mp.volume > 0)) return mp;
  const double cx = sx / (3 * a2), cz = sz / (3 * a2);
  const double ixx = szz / 12 - mp.volume * cz * cz;  // integral of z^2 about the centroid
  const double izz = sxx / 12 - mp.volume * cx * cx;  // integral of x^2 about the centroid
  const double ixz = sxz / 24 - mp.volume * cx * cz;
  mp.centroid = {cx, 0, cz};
  mp.inertia = {ixx, ixx + izz, izz, 0, 0, -ixz};
  return mp;
}

/// The part of the edge a -> b (block frame) that lies between the ends of joint j's segment:
/// its rectangle (docs/2d.md: the segment times y in [-0.5, 0.5]) projected onto the edge.
double segment_fraction(const Joint& j, const Vec3& a, const Vec3& b, const Vec3& origin) {
  const double len = (b - a).norm();
  const Vec3 t = (b - a) / len;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Vec3& p : joint_polygon(j)) {
    const double s = t.dot(p - origin - a);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  return std::clamp((std::min(hi, len) - std::max(lo, 0.0)) / len, 0.0, 1.0);
}

/// The polygon's vertices: the dual hull's edges (hull[k], hull[k + 1]), relative to `centre`,
/// each checked inside every face.
std::vector<Vec3> polygon_vertices(const Block& b, const std::vector<std::size_t>& hull,
                                   const Vec3& centre, const Tolerances& tol, std::size_t id) {
  const std::size_t nv = hull.size();
  std::vector<Vec3> local(nv);
  for (std::size_t k = 0; k < nv; ++k) {
    local[k] = meet_2d(b.faces[hull[k]], b.faces[hull[(k + 1) % nv]], centre);
    if (!local[k].allFinite())
      throw Error(block_name(id), "its faces do not bound it (a vertex at infinity)",
                  "regenerate the blocks with slice-cut");
  }
  check_inside(b, local, centre, tol, id);
  return local;
}

/// block_geometry of a block of a section (docs/2d.md): by the dual hull as in 3-D, in the
/// plane. The faces n_i . (x - c) <= d_i about an interior point c are dual to the points
/// n_i / d_i in (x, z); their convex hull, counter-clockwise, lists the faces in the order of
/// the polygon's edges (the polar map keeps the angular order of the normals), and each hull
/// edge (i, j) is the vertex where faces i and j meet. A face whose dual point is not a hull
/// vertex (inside or on a hull edge, by the exact predicate) touches the block in a point at
/// most: it has no edge.
BlockGeometry block_geometry_2d(const Block& b, const JointSystem& js, const Tolerances& tol,
                                std::size_t id) {
  const std::size_t nf = b.faces.size();
  if (nf < 3)
    throw Error(block_name(id),
                "has " + std::to_string(nf) + " faces; a bounded polygon has 3 or more",
                "regenerate the blocks with slice-cut");
  for (std::size_t f = 0; f < nf; ++f)
    if (std::abs(b.faces[f].normal.y()) > kSectionNormalY)
      throw Error(block_name(id),
                  face_name(b, f) + " has a normal with y component " + num(b.faces[f].normal.y()) +
                      "; faces of a 2-D section have y = 0",
                  "regenerate the blocks with slice-cut from a dimension = 2 scene");
  const Vec3 centre = hull_centre(b, tol, id);  // a 2-D Chebyshev LP: tol.dimension is 2

  std::vector<Point2> dual;
  dual.reserve(nf);
  for (const Face& f : b.faces)
    dual.push_back(section_point(f.normal / (f.d - f.normal.dot(centre))));
  const std::vector<std::size_t> hull = convex_hull_2(dual);
  if (hull.size() < 3)
    throw Error(block_name(id), "its faces do not bound a polygon (the dual hull is flat)",
                "regenerate the blocks with slice-cut");
  // Bounded iff the centre (the dual origin) is strictly inside the hull.
  const Point2 origin(CGAL::ORIGIN);
  for (std::size_t k = 0; k < hull.size(); ++k)
    if (CGAL::orientation(dual[hull[k]], dual[hull[(k + 1) % hull.size()]], origin) !=
        CGAL::LEFT_TURN)
      throw Error(block_name(id), "its faces do not bound it (the block is unbounded)",
                  "regenerate the blocks with slice-cut");

  // Vertex k is where hull faces k and k + 1 meet: edge hull[k] runs from vertex k - 1 to k.
  const std::vector<Vec3> local = polygon_vertices(b, hull, centre, tol, id);
  const std::size_t nv = local.size();
  BlockGeometry g;
  g.loops.resize(nf);
  g.face_area.assign(nf, 0);
  g.face_joint_fraction.assign(nf, 1.0);
  for (std::size_t k = 0; k < nv; ++k) {
    const std::size_t f = hull[k], start = (k + nv - 1) % nv;
    g.loops[f] = {std::int64_t(start), std::int64_t(k)};
    g.face_area[f] = (local[k] - local[start]).norm();
  }
  for (std::size_t f = 0; f < nf; ++f) {
    if (g.loops[f].empty())
      throw Error(block_name(id),
                  face_name(b, f) + " does not touch the block along an edge (it is redundant)",
                  kSlicerFix);
    // Vertices closer than the tolerance would be one vertex (as in 3-D): the edge has no length.
    if (g.face_area[f] <= tol.geometry)
      throw Error(block_name(id),
                  face_name(b, f) + " has no length: " + num(g.face_area[f]) +
                      " (below tolerance " + num(tol.geometry) + ")",
                  kSlicerFix);
    const std::int64_t j = b.faces[f].joint;
    if (j >= 0 && std::size_t(j) < js.joints.size() && !js.joints[std::size_t(j)].persistent())
      g.face_joint_fraction[f] =
          segment_fraction(js.joints[std::size_t(j)], local[std::size_t(g.loops[f][0])],
                           local[std::size_t(g.loops[f][1])], b.origin + centre);
  }

  const MassProperties mp = polygon_mass_properties(local);
  SLICE_ASSERT(mp.volume > 0);  // a counter-clockwise polygon about an interior point
  g.volume = mp.volume;
  g.centroid = b.origin + centre + mp.centroid;
  g.inertia = mp.inertia;
  g.vertices.reserve(nv);
  for (const Vec3& x : local) g.vertices.push_back(b.origin + centre + x);
  return g;
}

}  // namespace

MassProperties mass_properties(const std::vector<Vec3>& vertices,
                               const std::vector<std::vector<std::int64_t>>& loops,
                               const Vec3& about) {
  // Tetrahedra (about, a, b, c) over a fan of each face, D = a . (b x c) (six times the signed
  // volume, relative to `about`): integral of x = D/24 (a + b + c) and integral of x x^T =
  // D/120 (a a^T + b b^T + c c^T + s s^T), s = a + b + c.
  // x x^T is symmetric (a_i a_j = a_j a_i exactly): its six entries xx, yy, zz, xy, yz, zx are
  // summed, each as the whole matrix would be.
  constexpr int kRow[6] = {0, 1, 2, 0, 1, 2}, kCol[6] = {0, 1, 2, 1, 2, 0};
  double six_v = 0;
  Vec3 m1 = Vec3::Zero();
  double x2[6] = {0, 0, 0, 0, 0, 0};
  for (const auto& loop : loops) {
    if (loop.size() < 3) continue;
    const Vec3 a = vertices[std::size_t(loop[0])] - about;
    for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
      const Vec3 b = vertices[std::size_t(loop[k])] - about;
      const Vec3 c = vertices[std::size_t(loop[k + 1])] - about;
      const double d = a.dot(b.cross(c));
      const Vec3 s = a + b + c;
      six_v += d;
      m1 += d / 24 * s;
      const double w = d / 120;
      for (int e = 0; e < 6; ++e) {
        const int i = kRow[e], j = kCol[e];
        x2[e] += w * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
      }
    }
  }
  Eigen::Matrix3d m2;
  for (int e = 0; e < 6; ++e) m2(kRow[e], kCol[e]) = m2(kCol[e], kRow[e]) = x2[e];
  MassProperties mp;
  mp.volume = six_v / 6;
  if (!(mp.volume > 0)) return mp;
  const Vec3 c = m1 / mp.volume;
  const Eigen::Matrix3d cov = m2 - mp.volume * c * c.transpose();  // about the centroid
  const Eigen::Matrix3d inertia = cov.trace() * Eigen::Matrix3d::Identity() - cov;
  mp.centroid = about + c;
  mp.inertia = {inertia(0, 0), inertia(1, 1), inertia(2, 2),
                inertia(0, 1), inertia(1, 2), inertia(2, 0)};
  return mp;
}

namespace {

/// A polygon joint's edges as outward in-plane half-planes (global frame).
std::vector<Plane> polygon_edges(const Joint& joint) {
  const std::vector<Vec3> poly = joint_polygon(joint);
  const Vec3& n = joint.plane.normal;
  std::vector<Plane> edges;
  edges.reserve(poly.size());
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec3 m = (poly[(k + 1) % poly.size()] - poly[k]).cross(n).normalized();
    edges.push_back({m, m.dot(poly[k])});
  }
  return edges;
}

/// polygon_edges of every polygon joint, in one array: joint j's are [offset[j], offset[j + 1])
/// (none for a persistent one). Blocks meet their joints in no order: the few bytes a face
/// needs are read here rather than from the joint system's records.
struct JointEdges {
  std::vector<std::size_t> offset{0};
  std::vector<Plane> planes;
  std::span<const Plane> of(std::size_t j) const {
    return {planes.data() + offset[j], offset[j + 1] - offset[j]};
  }
  // Blocks meet their joints in no order, so of(j) misses the cache: a caller going through the
  // blocks starts loading the offsets two blocks ahead and their planes one block ahead.
  bool has(std::int64_t j) const { return j >= 0 && std::size_t(j) + 1 < offset.size(); }
  void prefetch_offsets(const Block& b) const {
    for (const Face& f : b.faces)
      if (has(f.joint)) prefetch(&offset[std::size_t(f.joint) + 1]);
  }
  void prefetch_planes(const Block& b) const {
    for (const Face& f : b.faces) {
      if (!has(f.joint)) continue;
      const auto* p = reinterpret_cast<const char*>(planes.data() + offset[std::size_t(f.joint)]);
      const auto* e =
          reinterpret_cast<const char*>(planes.data() + offset[std::size_t(f.joint) + 1]);
      if (p == e) continue;
      prefetch(p);  // a square's four planes: 128 bytes, on two or three cache lines
      if (e - p > 64) prefetch(p + 64);
      prefetch(e - 1);
    }
  }
};

/// block_geometry_3d's working arrays, kept from block to block by a caller that computes many
/// (their capacity stays; no allocation per block once they have grown).
struct Scratch3d {
  struct Wedge {
    std::size_t a, b, t;  // facet t = (face, a, b), counter-clockwise
  };
  std::vector<Point> dual;
  std::vector<Triangle> triangles;
  HullScratch hull;
  std::vector<Vec3> local;  // block frame, relative to the hull centre
  std::vector<std::int64_t> vertex_of, sorted;
  std::vector<std::size_t> around_offset;  // face f's wedges: around[around_offset[f] ...]
  std::vector<Wedge> around;
  std::vector<Plane> own;
  std::vector<Vec3> part, clipped;
};

void block_geometry_3d(const Block& b, const JointSystem& js, const Tolerances& tol, std::size_t id,
                       const JointEdges* joint_edges, Scratch3d& s, BlockGeometry& g);

}  // namespace

BlockGeometry block_geometry(const Block& b, const JointSystem& js, const Tolerances& tol,
                             std::size_t id) {
  if (js.dimension == 2) return block_geometry_2d(b, js, tol, id);
  Scratch3d scratch;
  BlockGeometry g;
  block_geometry_3d(b, js, tol, id, nullptr, scratch, g);
  return g;
}

namespace {

/// The part of a face inside its joint's polygon, in the face's plane: its loop (`local`, block
/// frame about the hull centre o) clipped by the polygon's `edges` (global frame), as a fraction
/// of the face's `area`.
double joint_fraction(const std::vector<Vec3>& local, const std::vector<std::int64_t>& loop,
                      const Vec3& normal, double area, std::span<const Plane> edges, const Vec3& o,
                      Scratch3d& s) {
  auto& part = s.part;
  part.clear();
  for (const std::int64_t v : loop) part.push_back(local[std::size_t(v)]);
  bool cut = false;
  for (std::size_t k = 0; k < edges.size() && !part.empty(); ++k) {
    const Plane edge = to_local(edges[k], o);
    // clip_polygon gives a polygon inside the half-plane back as it is: no need to call it.
    if (std::all_of(part.begin(), part.end(), [&](const Vec3& x) { return edge.distance(x) <= 0; }))
      continue;
    clip_polygon(part, edge, s.clipped);
    part.swap(s.clipped);
    cut = true;
  }
  // Uncut, the part's Newell area is the face's area (loop_area's sum): the fraction is 1.
  if (!cut) return 1;
  const double inside = part.size() < 3 ? 0 : normal.dot(newell_normal(part)) / 2;
  return std::clamp(inside / area, 0.0, 1.0);
}

/// block_geometry of a 3-D block into `g` (its arrays reused), with the polygon joints' edges
/// made once for all blocks (`joint_edges`) or, without them, for each face that needs them.
void block_geometry_3d(const Block& b, const JointSystem& js, const Tolerances& tol, std::size_t id,
                       const JointEdges* joint_edges, Scratch3d& s, BlockGeometry& g) {
  const std::size_t nf = b.faces.size();
  if (nf < 4)
    throw Error(block_name(id),
                "has " + std::to_string(nf) + " faces; a bounded block has 4 or more",
                "regenerate the blocks with slice-cut");
  const Vec3 centre = hull_centre(b, tol, id);

  // The dual points n_i / d_i (about the centre) and their convex hull.
  auto& dual = s.dual;
  dual.clear();
  for (const Face& f : b.faces) {
    const Vec3 p = f.normal / (f.d - f.normal.dot(centre));
    dual.emplace_back(p.x(), p.y(), p.z());
  }
  auto& triangles = s.triangles;
  const Orientation3 orientation(dual);
  convex_hull(dual, orientation, triangles, s.hull);
  if (triangles.empty())
    throw Error(block_name(id), "its faces do not bound a solid (the dual hull is flat)",
                "regenerate the blocks with slice-cut");
  // The block is bounded iff the centre (the dual origin) is strictly inside the hull: below
  // every (outward) facet, by the exact predicate.
  const Point origin(CGAL::ORIGIN);
  for (const Triangle& tr : triangles)
    if (orientation(dual[tr[0]], dual[tr[1]], dual[tr[2]], origin) != CGAL::NEGATIVE)
      throw Error(block_name(id), "its faces do not bound it (the block is unbounded)",
                  "regenerate the blocks with slice-cut");

  // One vertex per hull facet; facets whose vertices are closer than the geometry tolerance
  // are one vertex (four or more planes meeting).
  // norm() > tol.geometry, without the square root where the squared norm settles it (norm()
  // is the rounded root of the same squared norm, so the answer is the same).
  const double far = tol.geometry * tol.geometry * (1 + 1e-9);
  const auto apart = [&](const Vec3& u, const Vec3& v) {
    const Vec3 w = u - v;
    return w.squaredNorm() > far || w.norm() > tol.geometry;
  };
  auto& local = s.local;
  auto& vertex_of = s.vertex_of;
  local.clear();
  vertex_of.resize(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tr = triangles[t];
    const Vec3 x = meet(b.faces[tr[0]], b.faces[tr[1]], b.faces[tr[2]], centre);
    if (!x.allFinite())
      throw Error(block_name(id), "its faces do not bound it (a vertex at infinity)",
                  "regenerate the blocks with slice-cut");
    std::size_t m = 0;
    while (m < local.size() && apart(local[m], x)) ++m;
    if (m == local.size()) local.push_back(x);
    vertex_of[t] = std::int64_t(m);
  }

  // Every vertex satisfies every half-space (the hull is exact; rounding is far below tol).
  check_inside(b, local, centre, tol, id);

  // Face loops: the facets around a hull vertex, in the hull's counter-clockwise order, are the
  // face's vertices counter-clockwise seen from outside (the polar map keeps orientation). The
  // wedges of hull vertex (= face) f, in facet order: around[around_offset[f] ...].
  auto& offset = s.around_offset;
  offset.assign(nf + 1, 0);
  for (const Triangle& tr : triangles)
    for (const std::size_t f : tr) ++offset[f + 1];
  for (std::size_t f = 0; f < nf; ++f) offset[f + 1] += offset[f];
  s.around.resize(offset[nf]);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k)
      s.around[offset[triangles[t][k]]++] = {triangles[t][(k + 1) % 3], triangles[t][(k + 2) % 3],
                                             t};
  for (std::size_t f = nf; f > 0; --f) offset[f] = offset[f - 1];  // back to the starts
  offset[0] = 0;

  g.loops.resize(nf);
  g.face_area.resize(nf);
  g.face_joint_fraction.assign(nf, 1.0);
  for (std::size_t f = 0; f < nf; ++f) {
    const std::span<const Scratch3d::Wedge> w(s.around.data() + offset[f],
                                              offset[f + 1] - offset[f]);
    if (w.empty())
      throw Error(block_name(id), face_name(b, f) + " does not touch the block (it is redundant)",
                  kSlicerFix);
    auto& loop = g.loops[f];
    loop.clear();
    std::size_t cur = 0;
    for (std::size_t step = 0; step < w.size(); ++step) {
      const std::int64_t v = vertex_of[w[cur].t];
      if (loop.empty() || loop.back() != v) loop.push_back(v);
      const std::size_t next_a = w[cur].b;
      std::size_t next = 0;
      while (next < w.size() && w[next].a != next_a) ++next;
      SLICE_ASSERT(next < w.size());  // the hull is a closed triangulated surface
      cur = next;
    }
    SLICE_ASSERT(cur == 0);
    while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
    auto& sorted = s.sorted;
    sorted.assign(loop.begin(), loop.end());
    std::sort(sorted.begin(), sorted.end());
    const bool repeats = std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
    double bound = 0;
    const double area = loop.size() < 3 ? 0 : loop_area(local, loop, b.faces[f].normal, &bound);
    // area <= tol.geometry * perimeter / 2, with the perimeter (square roots) worked out only
    // where its bound does not settle it.
    if (loop.size() < 3 || repeats || area <= tol.geometry * (bound * (1 + 1e-9)) / 2) {
      const double perimeter = loop.size() < 3 ? 0 : loop_perimeter(local, loop);
      if (loop.size() < 3 || repeats || area <= tol.geometry * perimeter / 2)
        throw Error(block_name(id),
                    face_name(b, f) + " has no area: " + std::to_string(loop.size()) +
                        " distinct vertices, area " + num(area) + " (below tolerance " +
                        num(tol.geometry * perimeter / 2) + " = tolerance x half perimeter)",
                    kSlicerFix);
    }
    g.face_area[f] = area;

    // Part of the face inside its joint's polygon, in the face's plane (block frame).
    const std::int64_t j = b.faces[f].joint;
    if (j < 0 || std::size_t(j) >= js.joints.size()) continue;
    std::span<const Plane> edges;
    if (joint_edges)
      edges = joint_edges->of(std::size_t(j));
    else if (!js.joints[std::size_t(j)].persistent())
      edges = s.own = polygon_edges(js.joints[std::size_t(j)]);
    if (!edges.empty())
      g.face_joint_fraction[f] =
          joint_fraction(local, loop, b.faces[f].normal, area, edges, b.origin + centre, s);
  }

  const MassProperties mp = mass_properties(local, g.loops, Vec3::Zero());
  SLICE_ASSERT(mp.volume > 0);  // every face has positive area and the centre is inside
  g.volume = mp.volume;
  g.centroid = b.origin + centre + mp.centroid;
  g.inertia = mp.inertia;
  g.vertices.clear();
  for (const Vec3& x : local) g.vertices.push_back(b.origin + centre + x);
}

/// Appends block i's geometry to geo (block-local vertex numbers, as the file stores them).
void append(Geometry& geo, const BlockGeometry& g, GeometryStats& st) {
  geo.vertices.insert(geo.vertices.end(), g.vertices.begin(), g.vertices.end());
  geo.vertex_offset.push_back(std::int64_t(geo.vertices.size()));
  for (std::size_t f = 0; f < g.loops.size(); ++f) {
    geo.face_vertices.insert(geo.face_vertices.end(), g.loops[f].begin(), g.loops[f].end());
    geo.face_vertex_offset.push_back(std::int64_t(geo.face_vertices.size()));
    geo.face_area.push_back(g.face_area[f]);
    geo.face_joint_fraction.push_back(g.face_joint_fraction[f]);
  }
  geo.volume.push_back(g.volume);
  geo.centroid.push_back(g.centroid);
  geo.inertia.push_back(g.inertia);
  st.vertices += g.vertices.size();
  st.faces += g.loops.size();
}

/// Makes room in geo for appending all of `parts` (no regrowing copies of a run's arrays).
void reserve(Geometry& geo, const std::vector<Geometry>& parts) {
  const auto room = [&](auto member) {
    std::size_t n = (geo.*member).size();
    for (const Geometry& p : parts) n += (p.*member).size();
    (geo.*member).reserve(n);
  };
  room(&Geometry::vertex_offset);
  room(&Geometry::vertices);
  room(&Geometry::face_vertex_offset);
  room(&Geometry::face_vertices);
  room(&Geometry::volume);
  room(&Geometry::centroid);
  room(&Geometry::inertia);
  room(&Geometry::face_area);
  room(&Geometry::face_joint_fraction);
}

/// Appends `part` (blocks made by append into an empty Geometry) to geo.
void append(Geometry& geo, const Geometry& part) {
  const std::int64_t v0 = std::int64_t(geo.vertices.size());
  const std::int64_t fv0 = std::int64_t(geo.face_vertices.size());
  geo.vertices.insert(geo.vertices.end(), part.vertices.begin(), part.vertices.end());
  for (std::size_t i = 1; i < part.vertex_offset.size(); ++i)
    geo.vertex_offset.push_back(v0 + part.vertex_offset[i]);
  geo.face_vertices.insert(geo.face_vertices.end(), part.face_vertices.begin(),
                           part.face_vertices.end());
  for (std::size_t i = 1; i < part.face_vertex_offset.size(); ++i)
    geo.face_vertex_offset.push_back(fv0 + part.face_vertex_offset[i]);
  const auto tail = [](auto& to, const auto& from) {
    to.insert(to.end(), from.begin(), from.end());
  };
  tail(geo.face_area, part.face_area);
  tail(geo.face_joint_fraction, part.face_joint_fraction);
  tail(geo.volume, part.volume);
  tail(geo.centroid, part.centroid);
  tail(geo.inertia, part.inertia);
}

}  // namespace

int orientation_sign(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
  const std::vector<Point> pts{
      {p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z()}, {r.x(), r.y(), r.z()}, {s.x(), s.y(), s.z()}};
  return int(Orientation3(pts)(pts[0], pts[1], pts[2], pts[3]));
}

GeometryStats compute_geometry(const BlockSystem& bs, const GeometrySink& sink,
                               const Progress& progress, int threads) {
  const auto t0 = Clock::now();
  if (!bs.pruned)
    throw Error("/blocks attribute pruned",
                "is 0: the blocks may still carry faces that no longer touch them (no polygon)",
                "prune them first: slice-prune, slice-cut --prune or slice-vertices --prune");
  const Tolerances tol = Tolerances::from_scale(bs.joints.length_scale, bs.joints.options.tolerance,
                                                bs.joints.dimension);
  const std::size_t n = bs.blocks.size();
  GeometryStats st;
  JointEdges joint_edges;
  if (bs.joints.dimension != 2)
    for (const Joint& joint : bs.joints.joints) {
      if (!joint.persistent())
        for (const Plane& e : polygon_edges(joint)) joint_edges.planes.push_back(e);
      joint_edges.offset.push_back(joint_edges.planes.size());
    }
  // Blocks are independent: chunks of them are computed concurrently (oneTBB), a run of chunks
  // at a time, while the run before is gathered in block order and handed to the sink. So the
  // result is the same for every thread count and at most two runs are held here. The first error
  // in block order is the one reported.
  constexpr std::size_t kChunk = 512, kWave = kGeometryRun / kChunk;
  static_assert(kWave * kChunk == kGeometryRun);
  tbb::task_arena arena(thread_count(threads));
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  struct Wave {
    std::size_t first = 0;  // its first block
    std::vector<Geometry> parts;
    std::vector<GeometryStats> stats;
    std::vector<std::exception_ptr> failure;
  };
  const auto compute = [&](std::size_t w0, Wave& wave) {
    const std::size_t count = std::min(chunks, w0 + kWave) - w0;
    wave.first = w0 * kChunk;
    wave.parts.assign(count, Geometry{});
    wave.stats.assign(count, GeometryStats{});
    wave.failure.assign(count, nullptr);
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t c) {
      const std::size_t lo = (w0 + c) * kChunk, hi = std::min(n, lo + kChunk);
      try {
        Scratch3d scratch;  // a chunk's blocks reuse one set of working arrays
        BlockGeometry g;
        for (std::size_t i = lo; i < hi; ++i) {
          if (i + 2 < hi) joint_edges.prefetch_offsets(bs.blocks[i + 2]);
          if (i + 1 < hi) joint_edges.prefetch_planes(bs.blocks[i + 1]);
          if (bs.joints.dimension == 2)
            g = block_geometry(bs.blocks[i], bs.joints, tol, i);
          else
            block_geometry_3d(bs.blocks[i], bs.joints, tol, i, &joint_edges, scratch, g);
          append(wave.parts[c], g, wave.stats[c]);
        }
      } catch (...) {
        wave.failure[c] = std::current_exception();
      }
    });
  };
  // Hands a wave over as one run; false (and the error kept) at its first failed chunk.
  std::exception_ptr failure;
  const auto gather = [&](Wave& wave) {
    if (wave.parts.empty()) return true;
    Geometry run;
    reserve(run, wave.parts);
    for (std::size_t c = 0; c < wave.parts.size(); ++c) {
      if (wave.failure[c]) {
        failure = wave.failure[c];
        return false;
      }
      append(run, wave.parts[c]);
      st.vertices += wave.stats[c].vertices;
      st.faces += wave.stats[c].faces;
    }
    const std::size_t first = wave.first;
    wave = Wave{};
    sink(first, std::move(run));
    return true;
  };
  Wave ready, next;
  arena.execute([&] {
    for (std::size_t w0 = 0; w0 < chunks; w0 += kWave) {
      bool ok = true;
      tbb::task_group group;
      group.run([&] { ok = gather(ready); });
      compute(w0, next);
      group.wait();
      if (!ok) return;
      std::swap(ready, next);
      if (progress) progress("vertices", std::min(n, (w0 + kWave) * kChunk), n);
    }
    gather(ready);
  });
  if (failure) std::rethrow_exception(failure);
  st.blocks = n;
  st.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return st;
}

GeometryStats compute_geometry(BlockSystem& bs, const Progress& progress, int threads) {
  Geometry geo;
  geo.volume.reserve(bs.blocks.size());
  geo.centroid.reserve(bs.blocks.size());
  geo.inertia.reserve(bs.blocks.size());
  const GeometryStats st = compute_geometry(
      std::as_const(bs), [&](std::size_t, Geometry&& run) { append(geo, run); }, progress, threads);
  bs.geometry = std::move(geo);
  bs.stability.reset();  // of the geometry it had
  return st;
}

}  // namespace slice

#include "slice/lp.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "lp_backends.hpp"
#include "slice/error.hpp"
#include "vertex_extremes.hpp"

namespace slice {

namespace {

std::string lower_case(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return out;
}

[[noreturn]] void bad_normal(const Vec3& n, double d, const char* where, const char* what,
                             std::size_t i) {
  throw Error(where,
              std::string(what) + " " + std::to_string(i) + " has normal (" +
                  std::to_string(n.x()) + ", " + std::to_string(n.y()) + ", " +
                  std::to_string(n.z()) + ") and d " + std::to_string(d),
              "normals must be finite unit vectors and d finite");
}

/// Throws unless n is a finite unit vector and d finite (a NaN or inf in n fails the first test).
inline void check_unit(const Vec3& n, double d, const char* where, const char* what,
                       std::size_t i) {
  if (!detail::unit_row_ok(n, d)) bad_normal(n, d, where, what, i);
}

/// Checks the faces and returns max |d_i| (0 for no faces).
double check_faces(std::span<const Face> faces, const char* where) {
  double dmax = 0;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    check_unit(faces[i].normal, faces[i].d, where, "face", i);
    dmax = std::max(dmax, std::abs(faces[i].d));
  }
  return dmax;
}

/// The LP's length scale: the block's size in its own frame, or L for a block of cones.
/// Throws if the tolerances are not a positive length scale and non-negative tolerances.
double block_scale(double dmax, const Tolerances& tol) {
  if (!(tol.length_scale > 0) || !std::isfinite(tol.length_scale) || !(tol.cut >= 0) ||
      !(tol.prune >= 0) || !(tol.geometry >= 0))
    throw Error("LP tolerances",
                "length scale " + std::to_string(tol.length_scale) + ", cut " +
                    std::to_string(tol.cut) + ", prune " + std::to_string(tol.prune) +
                    ", geometry " + std::to_string(tol.geometry),
                "use Tolerances::from_scale(L, rel) with L > 0 and rel >= 0");
  return dmax > 0 ? dmax : tol.length_scale;
}

/// An orthonormal basis (U, V) of the plane with unit normal n, the same for the same n.
void plane_basis(const Vec3& n, Vec3& u, Vec3& v) {
  int k = 0;  // the axis least aligned with n
  if (std::abs(n.y()) < std::abs(n[k])) k = 1;
  if (std::abs(n.z()) < std::abs(n[k])) k = 2;
  u = n.cross(Vec3::Unit(k)).normalized();
  v = n.cross(u);
}

// --- 2-D: a section in (x, z) (Tolerances::dimension == 2, docs/2d.md). The LPs take the
// columns x and z; a face must be normal to the section, a polygon edge normal to y (the
// unit-thickness rectangle's ends) is left out.
constexpr double kSectionSlack = 1e-12;  // |n_y| of a section's face: rounding at most

bool section(const Tolerances& tol) { return tol.dimension == 2; }

void check_in_section(const Vec3& n, const char* where, const char* what, std::size_t i) {
  if (!(std::abs(n.y()) <= kSectionSlack))
    throw Error(where,
                std::string(what) + " " + std::to_string(i) +
                    " has a normal with y = " + std::to_string(n.y()) + " in a 2-D section",
                "a 2-D block's faces are normal to the section (y = 0); check the file's "
                "dimension attribute");
}

/// check_faces, and in 2-D that every face is normal to the section.
double check_block(std::span<const Face> faces, const Tolerances& tol, const char* where) {
  const double dmax = check_faces(faces, where);
  if (section(tol))
    for (std::size_t i = 0; i < faces.size(); ++i)
      check_in_section(faces[i].normal, where, "face", i);
  return dmax;
}

/// A row's coefficients in the LP's space: (x, z) in 2-D, (x, y, z) in 3-D; `last` follows.
LpVec row_of(const Vec3& n, const Tolerances& tol, double last = 0) {
  return section(tol) ? LpVec(n.x(), n.z(), last, 0) : LpVec(n.x(), n.y(), n.z(), last);
}

/// Boon et al. 2015, eq. 7 / 16 in 2-D: the joint's line x = p0 + u U (U in the section), the
/// LP in (u, s). Edges normal to y are the ends of the unit-thickness rectangle: left out.
CutTest cut_test_section(LpSolver& solver, std::span<const Face> faces, const Plane& plane,
                         std::span<const Plane> edges, const Tolerances& tol) {
  check_unit(plane.normal, plane.d, "cut test", "joint plane", 0);
  check_in_section(plane.normal, "cut test", "joint plane", 0);
  const double dmax = check_block(faces, tol, "cut test");
  const double scale = block_scale(dmax, tol);
  const Vec3 u(-plane.normal.z(), 0, plane.normal.x());
  const Vec3 p0 = plane.d * Vec3(plane.normal.x(), 0, plane.normal.z());
  DenseLp& lp = solver.scratch();
  lp.reset(2);
  lp.c = LpVec(0, 1, 0, 0);
  lp.lower[1] = -(2 * dmax + tol.length_scale);
  lp.scale = scale;
  const auto put = [&](const Vec3& n, double d) {
    lp.add_row(LpVec(n.x() * u.x() + n.z() * u.z(), -1, 0, 0),
               d - (n.x() * p0.x() + n.z() * p0.z()));
  };
  for (const Face& f : faces) put(f.normal, f.d);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    check_unit(edges[k].normal, edges[k].d, "cut test", "polygon edge", k);
    if (std::abs(edges[k].normal.y()) > 0.5) continue;  // an end of the rectangle in y
    check_in_section(edges[k].normal, "cut test", "polygon edge", k);
    put(edges[k].normal, edges[k].d);
  }
  const LpResult r = solver.solve(lp);
  CutTest out;
  out.status = r.status;
  if (r.status == LpStatus::optimal) {
    out.s = r.x[1];
    out.point = p0 + r.x[0] * u;
    out.cuts = out.s < -tol.cut;
  }
  return out;
}

}  // namespace

int lp_column(int axis, const Tolerances& tol) {
  if (tol.dimension != 2) return axis;
  return axis == 0 ? 0 : axis == 2 ? 1 : -1;
}

Vec3 lp_point(const LpResult& r, const Tolerances& tol) {
  return tol.dimension == 2 ? Vec3(r.x[0], 0, r.x[1]) : Vec3(r.x.head<3>());
}

std::string to_string(LpBackend backend) {
  switch (backend) {
    case LpBackend::native:
      return "native";
    case LpBackend::ipopt:
      return "ipopt";
    case LpBackend::exact:
      return "exact";
  }
  SLICE_ASSERT(false);
}

LpBackend parse_lp_backend(std::string_view name) {
  const std::string s = lower_case(name);
  if (s == "native") return LpBackend::native;
  if (s == "ipopt") return LpBackend::ipopt;
  if (s == "exact") return LpBackend::exact;
  throw Error("LP backend", "unknown backend '" + std::string(name) + "'",
              "use native, ipopt or exact");
}

std::string to_string(LpStatus status) {
  switch (status) {
    case LpStatus::optimal:
      return "optimal";
    case LpStatus::infeasible:
      return "infeasible";
    case LpStatus::unbounded:
      return "unbounded";
    case LpStatus::failed:
      return "failed";
  }
  SLICE_ASSERT(false);
}

void DenseLp::reset(int n) {
  vars = n;
  maximise = false;
  c.setZero();
  rows.clear();
  lower.setConstant(-kInf);
  upper.setConstant(kInf);
  scale = 1;
}

void DenseLp::validate() const {
  const char* where = "LP";
  if (vars < 1 || vars > kLpMaxVars)
    throw Error(where, "has " + std::to_string(vars) + " variables",
                "use 1 to " + std::to_string(kLpMaxVars));
  if (!(scale > 0) || !std::isfinite(scale))
    throw Error(where, "scale is " + std::to_string(scale), "give a positive finite length");
  if (!c.head(vars).allFinite()) throw Error(where, "objective has a non-finite entry");
  for (int j = 0; j < vars; ++j) {
    if (std::isnan(lower[j]) || std::isnan(upper[j]) || lower[j] > upper[j] || lower[j] == kInf ||
        upper[j] == -kInf)
      throw Error(where, "variable " + std::to_string(j) + " has bounds [" +
                             std::to_string(lower[j]) + ", " + std::to_string(upper[j]) + "]");
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].a.head(vars).allFinite() || !std::isfinite(rows[i].b))
      throw Error(where, "row " + std::to_string(i) + " has a non-finite entry");
  }
}

void LpSolver::solve_batch(std::span<const DenseLp> lps, std::span<LpResult> out) {
  SLICE_ASSERT(lps.size() == out.size());
  for (std::size_t k = 0; k < lps.size(); ++k) out[k] = solve(lps[k]);
}

std::unique_ptr<LpSolver> make_solver(LpBackend backend) {
  switch (backend) {
    case LpBackend::native:
      return detail::make_native_solver();
    case LpBackend::ipopt:
      return detail::make_ipopt_solver();
    case LpBackend::exact:
      return detail::make_exact_solver();
  }
  SLICE_ASSERT(false);
}

// Boon et al. 2015, eq. 7 (persistent joint) and eq. 16 (polygon edges). The plane's equality
// is eliminated by x = p0 + u U + v V with p0 the foot of the block origin on the plane:
//   minimise s  s.t.  (a_i.U) u + (a_i.V) v - s <= d_i - a_i.p0   (faces)
//                     (b_k.U) u + (b_k.V) v - s <= e_k - b_k.p0   (edges)
//                     s >= -(2 max|d_i| + L)
// The bound never binds for a bounded block (s* >= -inradius >= -max d_i); it only keeps an
// unbounded region (a block of cones) from making the LP unbounded.
namespace {

/// Checks the plane and the tolerances and returns the LP's parts (the rows are checked by
/// solve_cut).
CutLp cut_setup(std::span<const Face> faces, const Plane& plane, std::span<const Plane> edges,
                const Tolerances& tol) {
  check_unit(plane.normal, plane.d, "cut test", "joint plane", 0);
  block_scale(0, tol);  // throws for bad tolerances
  CutLp cut;
  cut.faces = faces;
  cut.edges = edges;
  plane_basis(plane.normal, cut.frame.u, cut.frame.v);
  cut.frame.p0 = plane.d * plane.normal;
  cut.length_scale = tol.length_scale;
  cut.plane_d = plane.d;
  return cut;
}

/// Fills lp with the cut LP. Every field is set; the rows are overwritten in place (resize keeps
/// the capacity and, at the same size, constructs nothing).
void fill_cut_lp(const CutLp& cut, DenseLp& lp) {
  const detail::CutBounds bounds = detail::cut_bounds(cut, detail::check_cut_rows(cut));
  lp.vars = 3;
  lp.maximise = false;
  lp.c = LpVec(0, 0, 1, 0);
  lp.lower.setConstant(-DenseLp::kInf);
  lp.upper.setConstant(DenseLp::kInf);
  lp.lower[2] = bounds.s_lower;
  lp.scale = bounds.scale;
  lp.rows.resize(cut.faces.size() + cut.edges.size());
  LpRow* row = lp.rows.data();
  const auto put = [&](const Vec3& n, double d) {
    const detail::CutRow r = detail::cut_row(n, d, cut.frame);
    row->a = LpVec(r.au, r.av, -1, 0);
    row->b = r.b;
    ++row;
  };
  for (const Face& f : cut.faces) put(f.normal, f.d);
  for (const Plane& e : cut.edges) put(e.normal, e.d);
}

}  // namespace

double detail::check_cut_rows(const CutLp& cut) {
  double dmax = 0;
  for (std::size_t i = 0; i < cut.faces.size(); ++i) {
    check_unit(cut.faces[i].normal, cut.faces[i].d, "cut test", "face", i);
    dmax = std::max(dmax, std::abs(cut.faces[i].d));
  }
  for (std::size_t k = 0; k < cut.edges.size(); ++k)
    check_unit(cut.edges[k].normal, cut.edges[k].d, "cut test", "polygon edge", k);
  return dmax;
}

PlaneFrame cut_test_lp(std::span<const Face> faces, const Plane& plane,
                       std::span<const Plane> edges, const Tolerances& tol, DenseLp& lp) {
  const CutLp cut = cut_setup(faces, plane, edges, tol);
  fill_cut_lp(cut, lp);
  return cut.frame;
}

LpResult LpSolver::solve_cut(const CutLp& cut) {
  fill_cut_lp(cut, scratch_);
  return solve(scratch_);
}

CutTest cut_test_result(const LpResult& r, const PlaneFrame& frame, const Tolerances& tol) {
  CutTest out;
  out.status = r.status;
  if (r.status == LpStatus::optimal) {
    out.s = r.x[2];
    out.point = frame.p0 + r.x[0] * frame.u + r.x[1] * frame.v;
    out.cuts = out.s < -tol.cut;
  }
  return out;
}

CutTest cut_test(LpSolver& solver, std::span<const Face> faces, const Plane& plane,
                 std::span<const Plane> edges, const Tolerances& tol) {
  if (section(tol)) return cut_test_section(solver, faces, plane, edges, tol);
  const CutLp cut = cut_setup(faces, plane, edges, tol);
  return cut_test_result(solver.solve_cut(cut), cut.frame, tol);
}

// Boon et al. 2015, eq. 8: maximise c . x over the other faces, c the tested face's normal.
FaceRedundancy face_redundancy(LpSolver& solver, std::span<const Face> faces, std::size_t index,
                               const Tolerances& tol) {
  if (index >= faces.size())
    throw Error("face redundancy",
                "face " + std::to_string(index) + " of a block with " +
                    std::to_string(faces.size()) + " faces",
                "pass the index of one of the block's faces");
  const double dmax = check_block(faces, tol, "face redundancy");
  DenseLp& lp = solver.scratch();
  lp.reset(section(tol) ? 2 : 3);
  lp.maximise = true;
  lp.c = row_of(faces[index].normal, tol);
  lp.scale = block_scale(dmax, tol);
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (i != index) lp.add_row(row_of(faces[i].normal, tol), faces[i].d);
  const LpResult r = solver.solve(lp);
  FaceRedundancy out;
  out.status = r.status;
  if (r.status == LpStatus::optimal) {
    out.value = r.objective;
    out.redundant = out.value <= faces[index].d + tol.prune;
  } else if (r.status == LpStatus::unbounded) {
    out.value = DenseLp::kInf;
  }
  return out;
}

// Boon et al. 2015, eq. 17: maximise +-e_k . x over the block, six LPs on the same rows.
DenseLp& extents_lp(LpSolver& solver, std::span<const Face> faces, const Tolerances& tol) {
  const double dmax = check_block(faces, tol, "extents");
  DenseLp& lp = solver.scratch();
  lp.reset(section(tol) ? 2 : 3);
  lp.maximise = true;
  lp.scale = block_scale(dmax, tol);
  for (const Face& f : faces) lp.add_row(row_of(f.normal, tol), f.d);
  return lp;
}

VertexExtremes vertex_extremes(std::span<const Face> faces, unsigned wanted) {
  return detail::vertex_extremes_of<1>(faces, {wanted})[0];
}

std::array<VertexExtremes, 2> vertex_extremes_split(std::span<const Face> faces, unsigned below,
                                                    unsigned above) {
  return detail::vertex_extremes_of<2>(faces, {below, above});
}

VertexExtremes vertex_extremes(const LpSolver& solver, std::span<const Face> faces, unsigned wanted,
                               const Tolerances& tol) {
  if (solver.backend() != LpBackend::native || section(tol)) return {};
  return vertex_extremes(faces, wanted);
}

std::array<VertexExtremes, 2> vertex_extremes_split(const LpSolver& solver,
                                                    std::span<const Face> faces, unsigned below,
                                                    unsigned above, const Tolerances& tol) {
  if (solver.backend() != LpBackend::native || section(tol)) return {};
  return vertex_extremes_split(faces, below, above);
}

Extents extents(LpSolver& solver, std::span<const Face> faces, const Tolerances& tol) {
  check_block(faces, tol, "extents");
  const VertexExtremes v = vertex_extremes(solver, faces, 0x3fu, tol);
  DenseLp* lp = nullptr;
  Extents out;
  out.status = LpStatus::optimal;
  for (int k = 0; k < 3 && out.status == LpStatus::optimal; ++k) {
    for (const double sign : {1.0, -1.0}) {
      const int dir = 2 * k + (sign > 0 ? 0 : 1);
      if (v.found & (1u << dir)) {
        (sign > 0 ? out.max : out.min)[k] = v.x[std::size_t(dir)][k];
        ++out.at_vertices;
        continue;
      }
      const int column = lp_column(k, tol);
      if (column < 0) continue;  // y in a section: 0 at both ends
      if (!lp) lp = &extents_lp(solver, faces, tol);
      lp->c.setZero();
      lp->c[column] = sign;
      const LpResult r = solver.solve(*lp);
      ++out.lps;
      if (r.status != LpStatus::optimal) {
        out.status = r.status;
        break;
      }
      (sign > 0 ? out.max : out.min)[k] = sign * r.objective;
    }
  }
  if (out.status != LpStatus::optimal) return Extents{out.status};
  out.centre = 0.5 * (out.min + out.max);
  out.radius = 0.5 * (out.max - out.min).norm();
  return out;
}

// Boon et al. 2015, eq. 18: minimise t s.t. a_i . x - d_i <= t (unit a_i); radius = -t*.
ChebyshevBall chebyshev_ball(LpSolver& solver, std::span<const Face> faces, const Tolerances& tol) {
  const double dmax = check_block(faces, tol, "Chebyshev centre");
  const int t = section(tol) ? 2 : 3;  // the column of the radius variable
  DenseLp& lp = solver.scratch();
  lp.reset(t + 1);
  lp.c.setZero();
  lp.c[t] = 1;
  lp.scale = block_scale(dmax, tol);
  for (const Face& f : faces) lp.add_row(row_of(f.normal, tol, -1), f.d);
  const LpResult r = solver.solve(lp);
  ChebyshevBall out;
  out.status = r.status;
  if (r.status == LpStatus::optimal) {
    out.centre = lp_point(r, tol);
    out.radius = -r.x[t];
  }
  return out;
}

}  // namespace slice

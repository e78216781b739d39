#pragma once
// The paper's four linear programs (Boon et al. 2015, eqs. 7/16, 8, 17 and 18) behind one solver
// interface with three backends (docs/design.md, "The linear programs" and "LP backends"):
//   native  a dual simplex for tiny dense LPs written here (src/lp/lp_native.cpp)
//   ipopt   Ipopt's interior point method through its TNLP interface (lp_ipopt.cpp)
//   exact   CGAL's LP solver over CGAL::Gmpzf, exact on the given doubles (lp_exact.cpp)
// Every LP runs in the block's frame: faces are normal . x <= d relative to Block::origin.
#include <Eigen/Core>
#include <array>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/tolerance.hpp"

namespace slice {

enum class LpBackend { native, ipopt, exact };
/// The default: the fastest backend whose decisions exact certifies (slice-bench-lp,
/// pipelines/bench/results/lp.csv: native matches exact to ~1e-16 L with no wrong decision,
/// at ~1/200 of exact's time and ~1/10,000 of ipopt's).
inline constexpr LpBackend kDefaultLpBackend = LpBackend::native;
/// "native", "ipopt" or "exact".
std::string to_string(LpBackend backend);
/// The backend named `name` (case-insensitive); throws Error for any other name.
LpBackend parse_lp_backend(std::string_view name);

/// `infeasible` and `unbounded` are answers about the LP, not failures; `failed` means the
/// backend gave up (iteration limit, numerical trouble) and nothing is known.
enum class LpStatus { optimal, infeasible, unbounded, failed };
std::string to_string(LpStatus status);

/// At most this many variables (the paper's LPs have 3 or 4).
inline constexpr int kLpMaxVars = 4;
using LpVec = Eigen::Vector4d;  // components past DenseLp::vars are ignored

/// The row a . x <= b. Components of `a` past DenseLp::vars are ignored.
struct LpRow {
  LpVec a = LpVec::Zero();
  double b = 0;
};

/// Minimise (or maximise) c . x over x in R^vars subject to a_i . x <= b_i and
/// lower <= x <= upper (an infinite bound is no bound).
struct DenseLp {
  static constexpr double kInf = std::numeric_limits<double>::infinity();

  int vars = 0;  // 1 .. kLpMaxVars
  bool maximise = false;
  LpVec c = LpVec::Zero();
  std::vector<LpRow> rows;  // rows.size() by (vars + 1)
  LpVec lower = LpVec::Constant(-kInf);
  LpVec upper = LpVec::Constant(kInf);
  /// The problem's length scale: the size of the feasible region near the optimum and of |b|.
  /// Not an accuracy: solvers scale internal tolerances and artificial bounds by it.
  double scale = 1;

  /// Empties the problem for `n` variables, keeping the rows' capacity (no allocation).
  void reset(int n);
  void add_row(const LpVec& a, double b) { rows.push_back({a, b}); }
  /// Throws Error naming the first bad field: vars outside 1..4, a non-finite entry (of the
  /// first `vars` components), lower > upper, scale <= 0.
  void validate() const;
};

struct LpResult {
  LpStatus status = LpStatus::failed;
  double objective = 0;     // c . x, when optimal
  LpVec x = LpVec::Zero();  // the optimal point, when optimal
  int iterations = 0;       // backend-specific count, for diagnostics
};

/// The plane's parametrisation x = p0 + u U + v V (block frame) used by the cut test's LP.
struct PlaneFrame {
  Vec3 p0 = Vec3::Zero(), u = Vec3::UnitX(), v = Vec3::UnitY();
};

/// The cut test's LP (see cut_test) in its parts: rows (n . U) u + (n . V) v - s <= d - n . p0
/// for every face and polygon edge, and s >= -(2 max |d_face| + L). The plane is checked; the
/// faces and edges are checked by solve_cut, in its pass over them.
struct CutLp {
  std::span<const Face> faces;
  std::span<const Plane> edges;
  PlaneFrame frame;
  double length_scale = 1;  // L: Tolerances::length_scale
  double plane_d = 0;       // the plane's d (block frame)
};

/// One LP backend. A solver object keeps state between solves (Ipopt's application, a scratch
/// problem): it is not thread-safe, use one per thread.
class LpSolver {
 public:
  virtual ~LpSolver() = default;
  virtual LpBackend backend() const = 0;
  virtual LpResult solve(const DenseLp& lp) = 0;
  /// Solves independent LPs; out.size() == lps.size(). The default solves them one by one;
  /// a backend may stack them into one problem.
  virtual void solve_batch(std::span<const DenseLp> lps, std::span<LpResult> out);
  /// Checks the faces and edges (as cut_test documents) and solves the cut test's LP,
  /// x = (u, v, s). The default fills scratch() (as cut_test_lp) and calls solve; a backend may
  /// build its own form straight from the faces (native does: building the LP was a fifth of a
  /// 20-row cut test's time).
  virtual LpResult solve_cut(const CutLp& cut);
  /// A problem owned by the solver that the problem functions below fill and solve, so that
  /// repeated calls allocate nothing once its capacity has grown.
  DenseLp& scratch() { return scratch_; }

 private:
  DenseLp scratch_;
};

std::unique_ptr<LpSolver> make_solver(LpBackend backend);

// ---- The paper's problems. `faces` are the block's half-spaces relative to its origin (unit
// normals, finite d); a face with a non-unit or non-finite normal throws Error.

/// Cut test (eq. 7; eq. 16 with polygon edges).
struct CutTest {
  LpStatus status = LpStatus::failed;
  /// s*: minimum over the plane of the largest signed distance outside any face or polygon
  /// edge [length]. Negative: some point of the plane is -s* inside every face and edge.
  double s = 0;
  Vec3 point = Vec3::Zero();  // the point of the plane attaining s*, block frame
  bool cuts = false;          // s* < -tol.cut (optimal only)
};

/// Does the joint `plane` (block frame) cut the block `faces`? `edges` are the joint polygon's
/// edges as in-plane half-planes normal . x <= d (block frame, unit normals lying in the plane,
/// the polygon inside); empty for a persistent joint. The plane is parametrised
/// x = p0 + u U + v V, so the LP has the three variables (u, v, s); s >= -(2 max|d_i| + L) keeps
/// it bounded (the inradius of a bounded block is at most max d_i).
CutTest cut_test(LpSolver& solver, std::span<const Face> faces, const Plane& plane,
                 std::span<const Plane> edges, const Tolerances& tol);

/// cut_test in two halves, to batch many cut tests through LpSolver::solve_batch: fills `lp`
/// with the cut test's LP and returns the frame that cut_test_result maps its solution back with.
PlaneFrame cut_test_lp(std::span<const Face> faces, const Plane& plane,
                       std::span<const Plane> edges, const Tolerances& tol, DenseLp& lp);
CutTest cut_test_result(const LpResult& r, const PlaneFrame& frame, const Tolerances& tol);

/// Redundant face (eq. 8): value = max c . x over the other faces, c = faces[index].normal.
struct FaceRedundancy {
  LpStatus status = LpStatus::failed;
  double value = 0;        // max c . x [length, block frame]
  bool redundant = false;  // optimal and value <= faces[index].d + tol.prune
};
FaceRedundancy face_redundancy(LpSolver& solver, std::span<const Face> faces, std::size_t index,
                               const Tolerances& tol);

/// Extents (eq. 17): six LPs maximising +-e_x, +-e_y, +-e_z; the bounding sphere has the box
/// centre and half the box diagonal as radius.
struct Extents {
  LpStatus status = LpStatus::failed;           // optimal only if all six LPs are
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();  // block frame
  Vec3 centre = Vec3::Zero();                   // block frame
  double radius = 0;
  int lps = 0;          // LPs solved
  int at_vertices = 0;  // extremes found at vertices instead (vertex_extremes)
};
Extents extents(LpSolver& solver, std::span<const Face> faces, const Tolerances& tol);
/// The extents LPs' rows in the solver's scratch LP, maximising, objective unset: set c to
/// +-e_k and solve, as extents() does (for a caller that solves only some of the six).
DenseLp& extents_lp(LpSolver& solver, std::span<const Face> faces, const Tolerances& tol);

/// The LP column of coordinate `axis` (0 x, 1 y, 2 z): itself in 3-D; in a 2-D section
/// (tol.dimension == 2) x is column 0, z column 1 and y has none (-1).
int lp_column(int axis, const Tolerances& tol);
/// An LP's optimal point as a position: (x, y, z), or (x, 0, z) from columns 0 and 1 in 2-D.
Vec3 lp_point(const LpResult& r, const Tolerances& tol);

/// Extremes of a block found where three of its faces meet: x[2k] maximises coordinate k,
/// x[2k + 1] minimises it, for the directions `wanted` (bit 2k: +e_k, bit 2k + 1: -e_k). A
/// vertex counts only if it lies inside every face and the signs of its three multipliers
/// prove it optimal (the extents LP's dual), so a direction it answers is the LP's answer up
/// to rounding; directions no such vertex answers are left out of `found`, for the LPs.
/// Blocks of more than kVertexFaces faces, or with faces at grazing angles, are left whole.
/// extents() uses it for the native backend (it is how the LP would end, without the pivots).
struct VertexExtremes {
  std::array<Vec3, 6> x{};
  unsigned found = 0;  // bit per direction, as `wanted`
};
inline constexpr std::size_t kVertexFaces = 10;
VertexExtremes vertex_extremes(std::span<const Face> faces, unsigned wanted);
/// The same where it applies, none found elsewhere: the native backend (exact and ipopt give
/// their own answers) on a 3-D block (a section's LPs are 2-D).
VertexExtremes vertex_extremes(const LpSolver& solver, std::span<const Face> faces, unsigned wanted,
                               const Tolerances& tol);
/// Both pieces of a split at once, in one pass over the vertices they share: `faces` ends with
/// the piece below's new face (n, d); the piece above has the same faces with that one reversed
/// (-n, -d). Returns {vertex_extremes(below's faces, below), vertex_extremes(above's faces,
/// above)}, the same bits, for about the cost of one.
std::array<VertexExtremes, 2> vertex_extremes_split(std::span<const Face> faces, unsigned below,
                                                    unsigned above);
std::array<VertexExtremes, 2> vertex_extremes_split(const LpSolver& solver,
                                                    std::span<const Face> faces, unsigned below,
                                                    unsigned above, const Tolerances& tol);

/// Chebyshev centre and inscribed radius (eq. 18): minimise t s.t. a_i . x - d_i <= t,
/// radius = -t*. A radius <= tol.geometry means the block has no interior.
struct ChebyshevBall {
  LpStatus status = LpStatus::failed;
  Vec3 centre = Vec3::Zero();  // block frame
  double radius = 0;
};
ChebyshevBall chebyshev_ball(LpSolver& solver, std::span<const Face> faces, const Tolerances& tol);

}  // namespace slice

// The native backend: a dual simplex for tiny dense LPs (1-4 variables, up to a few hundred
// rows), written for the paper's LPs.
//
// The LP is min c . x s.t. a_i . x <= b_i, x free in R^N (variable bounds are rows too). A basis
// is N linearly independent rows; its vertex x solves B x = b_B and its multipliers y solve
// B^T y = -c. The dual simplex keeps y >= 0 (dual feasible) and, while some row is violated at
// x, brings the most violated row q in and takes out the row whose multiplier reaches 0 first
// when y moves along a_q = B^T alpha. If no multiplier decreases (alpha <= 0), the rows of B
// and q have no common point: the LP is infeasible (Farkas). When no row is violated, x is
// optimal. Each iteration costs one pass over the rows.
//
// Start: a variable with no bound on the side its cost pushes to gets an artificial bound
// |x_j| <= M (M = 1e3 scale), so the starting basis of bound rows is dual feasible. Artificial
// rows are never priced back in. If one is still in the final basis with a positive multiplier,
// the optimum lies beyond the box: a recession LP (b = 0, |r_j| <= 1) decides between
// "unbounded" and "try a larger box". An infeasibility certificate that leans on an artificial
// row likewise asks for a larger box.
//
// Crash start for the cut test (solve_cut): its rows are (a_u, a_v, -1), and three rows whose
// (a_u, a_v) contain the origin in their triangle form a dual feasible basis with no artificial
// row. Picking the row tightest at u = v = 0 in each of three alternate 60-degree sectors
// guarantees such a triangle (cut_columns); the solver starts there when a fresh LU confirms
// y >= 0, else from the box. Such a basis proves the LP bounded, so the box is never needed.
//
// Accuracy: iterations update B^-1 and y in product form and take x = B^-1 b_B (N^2 flops per
// pivot), but every few pivots, after a small pivot, and before any conclusion (optimal,
// infeasible) they are recomputed from the original rows by a partially pivoted LU of the N x N
// basis; the optimal vertex is then refined with extended-precision residuals. For the cut and
// Chebyshev LPs the optimal multipliers sum to 1, so the objective's error is a few rounding errors
// of |b| + |x|, whatever the basis' condition (see the property tests).
//
// Degeneracy: Harris' two-pass ratio test picks the largest pivot among near-ties; if the
// iterations exceed a multiple of the rows (cycling), pricing switches to Bland's rule, which
// terminates. Once primal feasible, multipliers that rounding or Harris' tolerance left
// negative are removed by primal simplex steps (a near-flat objective needs them: see
// kFinalDualTol).
//
// Speed: no heap allocation once the solver's column buffer has grown; the pass that writes the
// rows into it column by column also validates them (coefficients past N are ignored), and for
// the cut test it computes the rows straight from the faces, four at a time with AVX2; pricing
// is a bare arg-max over four rows per AVX2 step (two per SSE2 step without AVX2; the kernels
// are chosen at run time and give the same bits, SLICE_NO_AVX2=1 forces the portable ones);
// the final check of optimality on fresh numbers re-reads the rows only if the refactorization
// moved x enough to matter. A 20-row cut test takes ~1.5 pivots from the crash basis (6.5 from
// the box) and ~3,200 instructions in all, building the LP included (callgrind; ~6,900 before
// the crash basis and the direct build).
// Tried and not used: Seidel's algorithm as a fast path proposing the basis (on 20-row cut tests
// it made 7.5 violations in 3-D, projected 65 rows to 2-D, 21 violations there and 105 rows in
// 1-D, about 360 row operations against the dual simplex's ~160, and cost 2.5 times as much);
// steepest-edge pricing; a branch-free AVX2 arg-max (lanes kept by blends, merged at the end:
// no faster than the branch, which is rarely taken after the first rows).
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <span>
#include <type_traits>
#include <vector>
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "../cpu.hpp"
#include "lp_backends.hpp"
#include "slice/error.hpp"

namespace slice::detail {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();
// A row is violated when a . x - b exceeds kFeasUlps eps (scale + |x|_inf + max |b|): the
// residual is a dot product of 4 terms, so its rounding error is a few eps times these.
constexpr double kFeasUlps = 32;
// alpha_k counts as a pivot above kPivotTol |a_q| / |a_k|: a smaller one would make the next
// basis numerically singular (its determinant is alpha_k times the current one).
constexpr double kPivotTol = 1e-11;
// Harris' ratio test lets multipliers go this far below 0, relative to |c|, to choose a larger
// pivot among near-ties.
constexpr double kDualTol = 1e-13;
// At a primal feasible vertex, a multiplier below -kFinalDualTol |c| is cleaned up by a primal
// simplex step. Dropping a row with multiplier y lowers the objective by |y| times the distance
// moved (a few scale at most), so the optimum is reached to ~1e-15 |c| scale. Rounding alone
// leaves multipliers of 1e-12 on near-flat objectives (a plane within 1e-12 rad of a face).
constexpr double kFinalDualTol = 1e-15;
// The artificial box starts at kBoxFactor scale and grows by kBoxGrowth, kBoxLevels times.
constexpr double kBoxFactor = 1e3;
constexpr double kBoxGrowth = 1e4;
constexpr int kBoxLevels = 3;
// Between fresh LU factorizations, B^-1, x and y are updated (product form); at most
// kRefactorEvery times in a row, and never across a pivot below kSmallPivot max |alpha|.
constexpr int kRefactorEvery = 8;
constexpr double kSmallPivot = 1e-3;
// Steps of iterative refinement of the optimal vertex (each: residuals in long double, one
// solve). One brings a far vertex of near-parallel faces to a few ulps; see the property tests.
constexpr int kRefineSteps = 1;
// A recession direction r (|r_j| <= 1) proves unboundedness if c . r < -kRecessionTol |c|_1.
constexpr double kRecessionTol = 1e-9;

enum class Outcome { optimal, infeasible, infeasible_in_box, unbounded, failed };

/// The whole LP as the solver reads it: the rows, then the finite variable bounds as rows, copied
/// column by column (a_0 .. a_{N-1}, then b), each column `stride` long (rounded up to a multiple
/// of 4 with pad rows a = 0, b = +inf that are never violated), so that pricing reads four rows
/// per AVX2 step or two per SSE2 step; and the bounds and scale. Filled once per solve, straight
/// from a DenseLp or from the cut test's faces, in the pass that also checks or scales the rows.
struct Columns {
  const double* data = nullptr;
  int stride = 0;
  int rows = 0;                                 // m + bounds
  int m = 0;                                    // LP rows (not bounds)
  double bmax = 0;                              // max |b|
  double amax1 = 1;                             // max(1, max |a_i|_1)
  double scale = 1;                             // DenseLp::scale
  LpVec lower, upper;                           // the variable bounds (infinite: none)
  std::array<int, 2 * kLpMaxVars> bound_row{};  // column row m + k is LP row bound_row[k]
  /// A proposed starting basis (LP rows), if `crash`: used if it is dual feasible.
  bool crash = false;
  std::array<int, kLpMaxVars> crash_rows{};
  /// The LP row (m + 2j: lower bound of x_j, m + 2j + 1: upper) of column row k.
  int lp_row(int k) const { return k < m ? k : bound_row[static_cast<std::size_t>(k - m)]; }
};

/// Lays out the columns for m rows and the finite bounds of `lower` and `upper` (only which are
/// finite matters here; finish_columns writes their values from cols.lower and cols.upper) and
/// sizes `buffer`; the caller writes rows 0 .. m-1 (d[j * stride + i], b at j = N), folds their
/// max |b| and max |a|_1 into bmax and amax1, then calls finish_columns.
template <int N>
double* start_columns(Columns& cols, std::vector<double>& buffer, int m, const LpVec& lower,
                      const LpVec& upper, double scale) {
  cols.m = m;
  cols.lower = lower;
  cols.upper = upper;
  cols.scale = scale;
  int nb = 0;
  for (int j = 0; j < N; ++j) {
    if (lower[j] != -kInf) cols.bound_row[static_cast<std::size_t>(nb++)] = m + 2 * j;
    if (upper[j] != kInf) cols.bound_row[static_cast<std::size_t>(nb++)] = m + 2 * j + 1;
  }
  cols.rows = m + nb;
  cols.stride = (cols.rows + 3) & ~3;
  buffer.resize(static_cast<std::size_t>((N + 1) * cols.stride));  // keeps its capacity
  cols.data = buffer.data();
  return buffer.data();
}

/// Writes the bound rows (from cols.lower and cols.upper) and the pad rows after the m rows.
template <int N>
void finish_columns(Columns& cols, double* d) {
  const int m = cols.m, n = cols.stride;
  for (int i = m; i < cols.rows; ++i) {
    const int row = cols.bound_row[static_cast<std::size_t>(i - m)] - m;
    const int j = row / 2;
    const bool up = row % 2 == 1;
    for (int l = 0; l < N; ++l) d[l * n + i] = l == j ? (up ? 1.0 : -1.0) : 0.0;
    d[N * n + i] = up ? cols.upper[j] : -cols.lower[j];
    cols.bmax = std::max(cols.bmax, std::abs(d[N * n + i]));
  }
  for (int i = cols.rows; i < n; ++i) {
    for (int j = 0; j < N; ++j) d[j * n + i] = 0;
    d[N * n + i] = kInf;
  }
}

/// The columns of a DenseLp; finite: no row has a NaN or inf.
template <int N>
Columns copy_columns(const DenseLp& lp, std::vector<double>& buffer, bool& finite) {
  Columns cols;
  const int m = static_cast<int>(lp.rows.size());
  double* d = start_columns<N>(cols, buffer, m, lp.lower, lp.upper, lp.scale);
  const int n = cols.stride;
  double sum = 0;
  for (int i = 0; i < m; ++i) {
    const LpRow& r = lp.rows[static_cast<std::size_t>(i)];
    double a1 = 0;
    for (int j = 0; j < N; ++j) {
      d[j * n + i] = r.a[j];
      a1 += std::abs(r.a[j]);
    }
    d[N * n + i] = r.b;
    sum += a1 + r.b;  // NaN and inf survive the sum
    cols.amax1 = std::max(cols.amax1, a1);
    cols.bmax = std::max(cols.bmax, std::abs(r.b));
  }
  finish_columns<N>(cols, d);
  finite = std::isfinite(sum);
  return cols;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define SLICE_HAVE_AVX2_PATH 1
/// cut_row for rows [0, count) of an array of Face or Plane (`step` doubles apart, normal then d),
/// four at a time, into the columns d (stride n) from row `at`; returns how many it wrote (a
/// multiple of 4; cut_rows does the rest). The same products and sums in the same order as
/// cut_row, and no fused multiply-add, so the same bits. Clears `ok` if a normal is not unit
/// (|n|^2 as in check_cut_rows) or a d is not finite; raises dmax to max |d|.
__attribute__((target("avx2"))) int cut_rows_avx2(const double* src, int step, int count,
                                                  const PlaneFrame& f, double* d, int n, int at,
                                                  bool& ok, double& dmax) {
  const __m256d ux = _mm256_set1_pd(f.u.x()), uy = _mm256_set1_pd(f.u.y()),
                uz = _mm256_set1_pd(f.u.z());
  const __m256d vx = _mm256_set1_pd(f.v.x()), vy = _mm256_set1_pd(f.v.y()),
                vz = _mm256_set1_pd(f.v.z());
  const __m256d px = _mm256_set1_pd(f.p0.x()), py = _mm256_set1_pd(f.p0.y()),
                pz = _mm256_set1_pd(f.p0.z());
  const __m256d minus_one = _mm256_set1_pd(-1), one = _mm256_set1_pd(1);
  const __m256d unit_tol = _mm256_set1_pd(kUnitNormalTol);
  const __m256d largest = _mm256_set1_pd(std::numeric_limits<double>::max());
  const __m256d sign = _mm256_set1_pd(-0.0);
  __m256d good = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  __m256d dmaxv = _mm256_set1_pd(dmax);
  int i = 0;
  for (; i + 4 <= count; i += 4) {
    // Four (x, y, z, d) rows transposed to x, y, z and d of four rows.
    const double* r = src + static_cast<std::ptrdiff_t>(i) * step;
    const __m256d r0 = _mm256_loadu_pd(r), r1 = _mm256_loadu_pd(r + step),
                  r2 = _mm256_loadu_pd(r + 2 * step), r3 = _mm256_loadu_pd(r + 3 * step);
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    const __m256d nx = _mm256_permute2f128_pd(t0, t2, 0x20);
    const __m256d nz = _mm256_permute2f128_pd(t0, t2, 0x31);
    const __m256d ny = _mm256_permute2f128_pd(t1, t3, 0x20);
    const __m256d dd = _mm256_permute2f128_pd(t1, t3, 0x31);
    const __m256d au = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, ux), _mm256_mul_pd(ny, uy)),
                                     _mm256_mul_pd(nz, uz));
    const __m256d av = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, vx), _mm256_mul_pd(ny, vy)),
                                     _mm256_mul_pd(nz, vz));
    const __m256d np = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, px), _mm256_mul_pd(ny, py)),
                                     _mm256_mul_pd(nz, pz));
    _mm256_storeu_pd(d + at + i, au);
    _mm256_storeu_pd(d + n + at + i, av);
    _mm256_storeu_pd(d + 2 * n + at + i, minus_one);
    _mm256_storeu_pd(d + 3 * n + at + i, _mm256_sub_pd(dd, np));
    // |(x x + y y) + z z - 1| <= tol and |d| <= DBL_MAX, both false for a NaN.
    const __m256d n2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, nx), _mm256_mul_pd(ny, ny)),
                                     _mm256_mul_pd(nz, nz));
    const __m256d dev = _mm256_andnot_pd(sign, _mm256_sub_pd(n2, one));
    const __m256d dabs = _mm256_andnot_pd(sign, dd);
    good = _mm256_and_pd(good, _mm256_cmp_pd(dev, unit_tol, _CMP_LE_OQ));
    good = _mm256_and_pd(good, _mm256_cmp_pd(dabs, largest, _CMP_LE_OQ));
    dmaxv = _mm256_max_pd(dmaxv, dabs);
  }
  if (_mm256_movemask_pd(good) != 0xF) ok = false;
  alignas(32) double m[4];
  _mm256_store_pd(m, dmaxv);
  dmax = std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
  return i;
}
#endif

/// The rows of `items` (Face or Plane) by cut_row into the columns d (stride n) from row `at`,
/// checked as check_cut_rows checks them (ok cleared if one is bad) and max |d| into dmax.
template <class Item>
void cut_rows(std::span<const Item> items, const PlaneFrame& frame, double* d, int n, int at,
              bool& ok, double& dmax) {
  static_assert(std::is_standard_layout_v<Item> && offsetof(Item, d) == 3 * sizeof(double) &&
                sizeof(Item) % sizeof(double) == 0);
  const int count = static_cast<int>(items.size());
  int i = 0;
#if defined(SLICE_HAVE_AVX2_PATH)
  if (count >= 4 && use_avx2())
    i = cut_rows_avx2(items.front().normal.data(), static_cast<int>(sizeof(Item) / sizeof(double)),
                      count, frame, d, n, at, ok, dmax);
#endif
  for (; i < count; ++i) {
    const Item& item = items[static_cast<std::size_t>(i)];
    const CutRow r = cut_row(item.normal, item.d, frame);
    d[at + i] = r.au;
    d[n + at + i] = r.av;
    d[2 * n + at + i] = -1;
    d[3 * n + at + i] = r.b;
    if (!unit_row_ok(item.normal, item.d)) ok = false;
    dmax = std::max(dmax, std::abs(item.d));
  }
}

/// The columns of the cut test's LP (x = (u, v, s)): its rows by cut_row, as in every backend,
/// then s >= s_lower as the row -s <= -s_lower (LP row m + 4), then the pad rows. The faces and
/// edges are checked in the same pass; a bad one throws (check_cut_rows names it).
Columns cut_columns(const CutLp& cut, std::vector<double>& buffer) {
  Columns cols;
  const int m = static_cast<int>(cut.faces.size() + cut.edges.size());
  // s has a finite lower bound; its value (from max |d|) is known after the pass below.
  double* d =
      start_columns<3>(cols, buffer, m, LpVec(-kInf, -kInf, 0, -kInf), LpVec::Constant(kInf), 1);
  const int n = cols.stride;
  const PlaneFrame frame = cut.frame;  // a local: the stores below cannot alias it
  bool ok = true;
  double dmax = 0, edge_dmax = 0;
  cut_rows(cut.faces, frame, d, n, 0, ok, dmax);
  cut_rows(cut.edges, frame, d, n, static_cast<int>(cut.faces.size()), ok, edge_dmax);
  if (!ok) check_cut_rows(cut);  // throws, naming the row
  const CutBounds bounds = cut_bounds(cut, dmax);
  cols.scale = bounds.scale;
  cols.lower[2] = bounds.s_lower;
  double bmax = 0, a1max = 0;
  // The crash basis: the row with the largest -b (the tightest at u = v = 0) in each 60 degree
  // sector of the direction of (a_u, a_v), sector k covering [60k, 60k + 60) degrees.
  std::array<double, 6> best;
  best.fill(-kInf);
  std::array<int, 6> arg{-1, -1, -1, -1, -1, -1};
  for (int i = 0; i < m; ++i) {
    const double au = d[i], av = d[n + i], b = d[3 * n + i];
    bmax = std::max(bmax, std::abs(b));
    a1max = std::max(a1max, std::abs(au) + std::abs(av));
    const double t = std::numbers::sqrt3 * std::abs(au);  // |tan| >= sqrt 3: 60 to 120 degrees
    const int k = av >= 0 ? (av >= t ? 1 : (au > 0 ? 0 : 2)) : (-av >= t ? 4 : (au > 0 ? 5 : 3));
    if (-b > best[static_cast<std::size_t>(k)]) {
      best[static_cast<std::size_t>(k)] = -b;
      arg[static_cast<std::size_t>(k)] = i;
    }
  }
  // Three directions, one from each of sectors 0, 2, 4 (or 1, 3, 5), are pairwise less than 180
  // degrees apart all round, so the origin is inside their triangle: the multipliers y (y >= 0,
  // sum 1, sum y_i a_i = 0) of the three rows exist, and the basis is dual feasible. Of the two
  // triples, the one tighter at the origin. From it, a 20-row cut test takes ~1.5 pivots instead
  // of ~6.5 from the artificial box (2 to drive the box out, 1 for the bound on s).
  const auto triple = [&](int first) {
    double sum = 0;
    for (int k = first; k < 6; k += 2) {
      if (arg[static_cast<std::size_t>(k)] < 0) return -kInf;
      sum += best[static_cast<std::size_t>(k)];
    }
    return sum;
  };
  const double even = triple(0), odd = triple(1);
  if (even > -kInf || odd > -kInf) {
    const int first = even >= odd ? 0 : 1;
    cols.crash = true;
    for (int k = 0; k < 3; ++k)
      cols.crash_rows[static_cast<std::size_t>(k)] = arg[static_cast<std::size_t>(first + 2 * k)];
  }
  cols.bmax = bmax;
  cols.amax1 = std::max(1.0, a1max + 1);
  finish_columns<3>(cols, d);  // the bound on s (LP row m + 4) and the pad rows
  return cols;
}

/// The arg-max of a_i . x - w b_i over the rows in `cols` (w = 1, or 0 for the recession LP),
/// if above `best`: updates best and q (ties: the first row). Four rows per step on AVX2 (chosen
/// at run time), else two on SSE2. Each lane computes ((a_0 x_0 + a_1 x_1) + ...) - b_i w in the
/// same order and with no fused multiply-add on every path, so the choice is the same bit for
/// bit on every x86-64. A new maximum is rare after the first rows, so it is a branch and not a
/// dependency between steps.
template <int N>
void argmax_rows_sse2(const Columns& cols, const double* x, double w, double& best, int& q) {
  const int n = cols.stride;
  const double* a = cols.data;
#if defined(__SSE2__)
  __m128d xv[N];
  for (int j = 0; j < N; ++j) xv[j] = _mm_set1_pd(x[j]);
  const __m128d wv = _mm_set1_pd(w);
  __m128d bestv = _mm_set1_pd(best);
  for (int i = 0; i < n; i += 2) {
    __m128d v = _mm_mul_pd(_mm_load_pd(a + i), xv[0]);
    for (int j = 1; j < N; ++j) v = _mm_add_pd(v, _mm_mul_pd(_mm_load_pd(a + j * n + i), xv[j]));
    v = _mm_sub_pd(v, _mm_mul_pd(_mm_load_pd(a + N * n + i), wv));
    if (__builtin_expect(_mm_movemask_pd(_mm_cmpgt_pd(v, bestv)) != 0, 0)) {
      alignas(16) double vv[2];
      _mm_store_pd(vv, v);
      for (int l = 0; l < 2; ++l)
        if (vv[l] > best) {
          best = vv[l];
          q = i + l;
        }
      bestv = _mm_set1_pd(best);
    }
  }
#else
  for (int i = 0; i < n; ++i) {
    double v = a[i] * x[0];
    for (int j = 1; j < N; ++j) v += a[j * n + i] * x[j];
    v -= a[N * n + i] * w;
    if (v > best) {
      best = v;
      q = i;
    }
  }
#endif
}

#if defined(SLICE_HAVE_AVX2_PATH)
/// As argmax_rows_sse2, four rows per step. (A branch-free form, each lane keeping its own
/// maximum and row by blends, merged at the end, was measured no faster.)
template <int N>
__attribute__((target("avx2"))) void argmax_rows_avx2(const Columns& cols, const double* x,
                                                      double w, double& best, int& q) {
  const int n = cols.stride;
  const double* a = cols.data;
  __m256d xv[N];
  for (int j = 0; j < N; ++j) xv[j] = _mm256_set1_pd(x[j]);
  const __m256d wv = _mm256_set1_pd(w);
  __m256d bestv = _mm256_set1_pd(best);
  for (int i = 0; i < n; i += 4) {
    __m256d v = _mm256_mul_pd(_mm256_loadu_pd(a + i), xv[0]);
    for (int j = 1; j < N; ++j)
      v = _mm256_add_pd(v, _mm256_mul_pd(_mm256_loadu_pd(a + j * n + i), xv[j]));
    v = _mm256_sub_pd(v, _mm256_mul_pd(_mm256_loadu_pd(a + N * n + i), wv));
    if (__builtin_expect(_mm256_movemask_pd(_mm256_cmp_pd(v, bestv, _CMP_GT_OQ)) != 0, 0)) {
      alignas(32) double vv[4];
      _mm256_store_pd(vv, v);
      for (int l = 0; l < 4; ++l)
        if (vv[l] > best) {
          best = vv[l];
          q = i + l;
        }
      bestv = _mm256_set1_pd(best);
    }
  }
}

#endif

template <int N>
using ArgmaxRows = void (*)(const Columns&, const double*, double, double&, int&);

/// The pricing kernel for this CPU.
template <int N>
ArgmaxRows<N> argmax_rows() {
#if defined(SLICE_HAVE_AVX2_PATH)
  if (use_avx2()) return &argmax_rows_avx2<N>;
#endif
  return &argmax_rows_sse2<N>;
}

template <int N>
class DualSimplex {
 public:
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;

  /// homogeneous: solve the recession LP (b = 0, finite bounds 0, free variables in [-1, 1]).
  /// cols: the LP, column by column; c: the cost to minimise.
  DualSimplex(const Columns& cols, const Vec& c, double box, bool homogeneous)
      : cols_(cols),
        c_(c),
        cmax_(c.cwiseAbs().maxCoeff()),
        m_(cols.m),
        box_(box),
        homog_(homogeneous),
        bmax_(homogeneous ? 0.0 : cols.bmax),
        argmax_(argmax_rows<N>()) {}

  Outcome run() {
    if (homog_ || !cols_.crash || !start_crash()) start_basis();
    const int candidates = m_ + 2 * N;
    const int bland_after = 50 + 10 * candidates;
    const int limit = bland_after + 200 + 50 * candidates;
    const int cleanup_limit = 10 + 2 * candidates;
    int cleanups = 0, updates = 0;
    for (iterations_ = 0; iterations_ < limit; ++iterations_) {
      const bool bland = iterations_ >= bland_after;
      double max_violation;
      const int q = price(bland, max_violation);
      if (q < 0) {
        if (!fresh_) {
          // Optimal by updated numbers: refactor. Every residual moves by at most
          // max |a_i|_1 times the move of x, so the rows need another look only if that
          // could push one over the threshold.
          const Vec updated = x_;
          if (!refactor()) return Outcome::failed;
          updates = 0;
          const double drift = (x_ - updated).cwiseAbs().maxCoeff();
          if (!(max_violation + cols_.amax1 * drift <= threshold())) continue;
        }
        // Primal feasible. Dual feasible too, unless rounding or Harris' tolerance left a
        // negative multiplier: then a primal simplex step drops that row.
        const int k = most_negative_multiplier();
        if (k < 0 || cleanups >= cleanup_limit) {
          refine();
          return Outcome::optimal;
        }
        const Vec d = -inverse().col(k);  // leaves row k, keeps the other basis rows tight
        const int p = primal_ratio_test(d);
        if (p < 0) {
          // Nothing blocks: c . d = y_k < 0 along a feasible ray.
          if (y_[k] < -kRecessionTol * c_.cwiseAbs().sum()) return Outcome::unbounded;
          refine();
          return Outcome::optimal;
        }
        set_basis(k, p, row(p));
        if (!refactor()) return Outcome::failed;
        ++cleanups;
        continue;
      }
      const Row rq = row(q);
      const Vec alpha = inverse().transpose() * rq.a;  // a_q = B^T alpha
      const int k = ratio_test(alpha, rq.norm, bland);
      if (k < 0) {
        if (!fresh_) {  // conclude only on fresh numbers
          if (!refactor()) return Outcome::failed;
          updates = 0;
          continue;
        }
        for (int j = 0; j < N; ++j)
          if (artificial(basis_[j]) && alpha[j] < 0) return Outcome::infeasible_in_box;
        return Outcome::infeasible;
      }
      // Row q replaces basis row k. With g = B^-1 e_k (a_j . g = 1 if j = k, else 0):
      //   y' = y - theta alpha, y'_k = theta            (theta = y_k / alpha_k)
      //   B'^-1 = B^-1 - g (alpha - e_k)^T / alpha_k     (Sherman-Morrison)
      //   x' = B'^-1 b_B'
      const Vec g = inv_.col(k);
      const double inv_alpha = 1 / alpha[k];
      const double theta = std::max(y_[k], 0.0) * inv_alpha;
      y_ -= theta * alpha;
      y_[k] = theta;
      Vec w = alpha;
      w[k] -= 1;
      inv_.noalias() -= (g * inv_alpha) * w.transpose();
      set_basis(k, q, rq);
      // x from the updated inverse, not x += g (b_q - a_q . x) / alpha_k: from the box corner
      // (|x| ~ 1e3 scale) that update carried errors of ~1e-13 scale into the real vertex, so
      // basis rows looked violated and the final refactorization moved x past the threshold:
      // 0.8 extra slow scans and 1 extra pricing pass per 8-row LP (12 % of the instructions).
      x_.noalias() = inv_ * basis_b_;
      fresh_ = false;
      // Updates drift: refactor every few, and after a small pivot.
      if (++updates >= kRefactorEvery ||
          std::abs(alpha[k]) < kSmallPivot * alpha.cwiseAbs().maxCoeff()) {
        if (!refactor()) return Outcome::failed;
        updates = 0;
      }
    }
    return Outcome::failed;
  }

  const Vec& x() const { return x_; }
  int iterations() const { return iterations_; }
  /// An artificial row is in the basis with a multiplier that matters.
  bool leans_on_box() const {
    for (int j = 0; j < N; ++j)
      if (artificial(basis_[j]) && y_[j] > kDualTol * cmax_) return true;
    return false;
  }

 private:
  struct Row {
    Vec a;
    double b;
    double norm;  // max |a_j|
  };

  // Rows 0..m-1 are lp.rows; row m + 2j is -x_j <= -lower_j, row m + 2j + 1 is x_j <= upper_j.
  double bound(int i) const {  // the bound of row i >= m as the row's b (+inf if none)
    const int j = (i - m_) / 2;
    return ((i - m_) % 2 == 0) ? -cols_.lower[j] : cols_.upper[j];
  }
  bool artificial(int i) const { return i >= m_ && !homog_ && bound(i) == kInf; }
  Row row(int i) const {
    if (i < m_) {
      const Vec a = col_a(i);
      return {a, col_b(i), a.cwiseAbs().maxCoeff()};
    }
    Vec a = Vec::Zero();
    a[(i - m_) / 2] = ((i - m_) % 2 == 0) ? -1 : 1;
    const double b = bound(i);
    if (homog_) return {a, b == kInf ? 1.0 : 0.0, 1};
    return {a, b == kInf ? box_ : b, 1};
  }

  double threshold() const {
    return kFeasUlps * kEps * (cols_.scale + x_.cwiseAbs().maxCoeff() + bmax_);
  }

  void start_basis() {
    for (int j = 0; j < N; ++j) {
      const int lo = m_ + 2 * j, up = lo + 1;
      // Minimising c_j x_j: c_j > 0 pushes x_j down onto its lower bound, c_j < 0 up.
      int i;
      if (c_[j] > 0)
        i = lo;
      else if (c_[j] < 0)
        i = up;
      else
        i = (bound(lo) != kInf || bound(up) == kInf) ? lo : up;
      set_basis(j, i, row(i));
    }
    // B = diag(sigma), sigma_j = -1 for a lower bound and +1 for an upper: its own inverse and
    // its own LU, x_j = sigma_j b_j, y_j = -sigma_j c_j. Exact: no factorization needed.
    lu_ = basis_a_;
    inv_ = basis_a_;
    for (int j = 0; j < N; ++j) {
      const double sigma = basis_a_(j, j);
      perm_[j] = j;
      inv_pivot_[j] = sigma;
      x_[j] = sigma * basis_b_[j];
      y_[j] = -sigma * c_[j];
    }
    inv_ok_ = true;
    fresh_ = true;
  }

  /// Starts from the rows cols_.crash_rows if they form a dual feasible basis (y >= 0 from a
  /// fresh LU); else false, and start_basis must follow.
  bool start_crash() {
    for (int k = 0; k < N; ++k) {
      const int i = cols_.crash_rows[static_cast<std::size_t>(k)];
      set_basis(k, i, row(i));
    }
    if (!refactor()) return false;
    for (int k = 0; k < N; ++k)
      if (!(y_[k] >= 0)) return false;
    return true;
  }

  /// Basis position k becomes row i; B, b_B and the row's size are kept with it.
  void set_basis(int k, int i, const Row& r) {
    basis_[k] = i;
    basis_a_.row(k) = r.a.transpose();
    basis_b_[k] = r.b;
    basis_norm_[k] = r.norm;
  }

  /// Fresh LU of the basis from the original rows, and x and y from it; B^-1 follows on
  /// demand (a final check of optimality does not need it).
  bool refactor() {
    lu_ = basis_a_;
    for (int k = 0; k < N; ++k) perm_[k] = k;
    // Doolittle LU with partial pivoting: lu_ = P B, unit lower L below the diagonal.
    for (int k = 0; k < N; ++k) {
      int p = k;
      for (int i = k + 1; i < N; ++i)
        if (std::abs(lu_(i, k)) > std::abs(lu_(p, k))) p = i;
      if (!(std::abs(lu_(p, k)) > 0)) return false;
      if (p != k) {
        lu_.row(p).swap(lu_.row(k));
        std::swap(perm_[p], perm_[k]);
      }
      // One division per pivot: the solves below multiply by its reciprocal.
      inv_pivot_[k] = 1 / lu_(k, k);
      for (int i = k + 1; i < N; ++i) {
        lu_(i, k) *= inv_pivot_[k];
        for (int j = k + 1; j < N; ++j) lu_(i, j) -= lu_(i, k) * lu_(k, j);
      }
    }
    x_ = solve(basis_b_);
    y_ = solve_transposed(-c_);
    fresh_ = true;
    inv_ok_ = false;
    return std::isfinite(x_.sum() + y_.sum());
  }

  const Mat& inverse() {
    if (!inv_ok_) {
      for (int k = 0; k < N; ++k) inv_.col(k) = solve(Vec::Unit(k));
      inv_ok_ = true;
    }
    return inv_;
  }

  Vec solve(const Vec& rhs) const {  // B x = rhs
    Vec z;
    for (int i = 0; i < N; ++i) {
      double s = rhs[perm_[i]];
      for (int j = 0; j < i; ++j) s -= lu_(i, j) * z[j];
      z[i] = s;
    }
    for (int i = N - 1; i >= 0; --i) {
      double s = z[i];
      for (int j = i + 1; j < N; ++j) s -= lu_(i, j) * z[j];
      z[i] = s * inv_pivot_[i];
    }
    return z;
  }

  Vec solve_transposed(const Vec& rhs) const {  // B^T y = rhs, B^T = U^T L^T P
    Vec w;
    for (int i = 0; i < N; ++i) {
      double s = rhs[i];
      for (int j = 0; j < i; ++j) s -= lu_(j, i) * w[j];
      w[i] = s * inv_pivot_[i];
    }
    for (int i = N - 1; i >= 0; --i) {
      double s = w[i];
      for (int j = i + 1; j < N; ++j) s -= lu_(j, i) * w[j];
      w[i] = s;
    }
    Vec y;
    for (int i = 0; i < N; ++i) y[perm_[i]] = w[i];
    return y;
  }

  /// Iterative refinement of x against the original basis rows with residuals in long double
  /// (x87 extended on x86-64): x then has the accuracy of its rounding even for an
  /// ill-conditioned basis (a far vertex of near-parallel faces), not eps times the condition.
  void refine() {
    for (int step = 0; step < kRefineSteps; ++step) {
      Vec r;
      for (int k = 0; k < N; ++k) {
        long double s = basis_b_[k];
        for (int j = 0; j < N; ++j)
          s -= static_cast<long double>(basis_a_(k, j)) * static_cast<long double>(x_[j]);
        r[k] = static_cast<double>(s);
      }
      const Vec dx = solve(r);
      if (!dx.allFinite()) return;
      x_ += dx;
    }
  }

  bool in_basis(int i) const {
    for (int k = 0; k < N; ++k)
      if (basis_[k] == i) return true;
    return false;
  }

  /// Column row k of the buffer (rows, then finite bounds): a and the b in use.
  Vec col_a(int k) const {
    Vec a;
    for (int j = 0; j < N; ++j) a[j] = cols_.data[j * cols_.stride + k];
    return a;
  }
  double col_b(int k) const { return homog_ ? 0.0 : cols_.data[N * cols_.stride + k]; }

  /// The entering row: the most violated one (Dantzig) or the first violated one (Bland), or
  /// -1 if no row is violated by more than threshold(). max_violation: the largest a . x - b.
  int price(bool bland, double& max_violation) const {
    const double thr = threshold();
    if (!bland) {
      // The hot loop: a bare arg-max. A row of the basis is tight at x, so it cannot be the
      // most violated one unless x is off by more than thr (then the slow scan below).
      double best = -kInf;
      int k = -1;
      argmax_(cols_, x_.data(), homog_ ? 0.0 : 1.0, best, k);
      max_violation = best;
      if (!(best > thr)) return -1;
      const int q = cols_.lp_row(k);
      if (!in_basis(q)) return q;
    }
    // Bland's rule, or a basis row came out violated: scan again, skipping the basis.
    int q = -1;
    double best = thr;
    max_violation = -kInf;
    for (int k = 0; k < cols_.rows; ++k) {
      const double v = col_a(k).dot(x_) - col_b(k);
      const int i = cols_.lp_row(k);
      max_violation = std::max(max_violation, v);
      if (v > best && !in_basis(i) && !(bland && q >= 0)) {
        best = v;
        q = i;
      }
    }
    return q;
  }

  int most_negative_multiplier() const {
    int k = -1;
    double worst = -kFinalDualTol * cmax_;
    for (int j = 0; j < N; ++j)
      if (y_[j] < worst) {
        worst = y_[j];
        k = j;
      }
    return k;
  }

  /// The row that blocks the move from x along d first (largest a . d among ties), or -1.
  int primal_ratio_test(const Vec& d) const {
    const double dn = d.cwiseAbs().maxCoeff();
    int best = -1;
    double best_t = 0, best_ad = 0;
    for (int k = 0; k < cols_.rows; ++k) {
      const Vec a = col_a(k);
      const int i = cols_.lp_row(k);
      const double ad = a.dot(d);
      if (!(ad > kPivotTol * dn * a.cwiseAbs().maxCoeff()) || in_basis(i)) continue;
      const double t = std::max(col_b(k) - a.dot(x_), 0.0) / ad;
      if (best < 0 || t < best_t || (t == best_t && ad > best_ad)) {
        best = i;
        best_t = t;
        best_ad = ad;
      }
    }
    return best;
  }

  /// The leaving basis position, or -1 if no multiplier decreases (infeasible).
  int ratio_test(const Vec& alpha, double aq_norm, bool bland) const {
    std::array<bool, N> ok{};
    std::array<double, N> inv{};
    bool any = false;
    for (int k = 0; k < N; ++k) {
      ok[k] = alpha[k] * basis_norm_[k] > kPivotTol * aq_norm;
      if (ok[k]) inv[k] = 1 / alpha[k];
      any = any || ok[k];
    }
    if (!any) return -1;
    if (bland) {  // exact minimum ratio, ties to the smallest row index
      int best = -1;
      double best_ratio = 0;
      for (int k = 0; k < N; ++k) {
        if (!ok[k]) continue;
        const double ratio = std::max(y_[k], 0.0) * inv[k];
        if (best < 0 || ratio < best_ratio || (ratio == best_ratio && basis_[k] < basis_[best])) {
          best = k;
          best_ratio = ratio;
        }
      }
      return best;
    }
    // Harris: the largest step that keeps every y >= -delta, then the largest pivot within it.
    const double delta = kDualTol * cmax_;
    std::array<double, N> ratio{};
    double theta = kInf;
    for (int k = 0; k < N; ++k)
      if (ok[k]) {
        const double yk = std::max(y_[k], 0.0);
        ratio[k] = yk * inv[k];
        theta = std::min(theta, (yk + delta) * inv[k]);
      }
    int best = -1;
    for (int k = 0; k < N; ++k)
      if (ok[k] && ratio[k] <= theta && (best < 0 || alpha[k] > alpha[best])) best = k;
    return best;
  }

  const Columns& cols_;
  Vec c_;
  double cmax_;
  int m_;
  double box_;
  bool homog_;
  double bmax_;  // max |b| over rows and finite bounds
  ArgmaxRows<N> argmax_;
  std::array<int, N> basis_{};
  Mat basis_a_;  // the basis rows' a, one per row
  Vec basis_b_;
  std::array<double, N> basis_norm_{};  // max |a_k|
  std::array<int, N> perm_{};
  Mat lu_;
  std::array<double, N> inv_pivot_{};
  Mat inv_;              // B^-1: exact at the start, then updated or recomputed
  bool inv_ok_ = false;  // inv_ is B^-1 (else compute it from the LU)
  bool fresh_ = false;   // x, y (and B^-1) come from a fresh LU
  Vec x_, y_;
  int iterations_ = 0;
};

/// Solves min c . x over the LP in `cols`; objective = c_orig . x (c_orig: the LP's own c,
/// before a maximisation's sign change).
template <int N>
LpResult solve_columns(const Columns& cols, const Eigen::Matrix<double, N, 1>& c,
                       const Eigen::Matrix<double, N, 1>& c_orig) {
  LpResult out;
  double box = kBoxFactor * cols.scale;
  for (int level = 0; level < kBoxLevels; ++level, box *= kBoxGrowth) {
    DualSimplex<N> dual(cols, c, box, false);
    const Outcome o = dual.run();
    out.iterations += dual.iterations();
    if (o == Outcome::failed) return out;
    if (o == Outcome::unbounded) {
      out.status = LpStatus::unbounded;
      return out;
    }
    if (o == Outcome::infeasible) {
      out.status = LpStatus::infeasible;
      return out;
    }
    if (o == Outcome::infeasible_in_box) {
      if (level + 1 == kBoxLevels) out.status = LpStatus::infeasible;  // nothing within 1e11 scale
      continue;
    }
    if (dual.leans_on_box()) {
      DualSimplex<N> rec(cols, c, 1, true);
      const Outcome ro = rec.run();
      out.iterations += rec.iterations();
      if (ro == Outcome::optimal && c.dot(rec.x()) < -kRecessionTol * c.cwiseAbs().sum()) {
        out.status = LpStatus::unbounded;
        return out;
      }
      continue;  // a finite optimum outside the box: grow it
    }
    out.status = LpStatus::optimal;
    out.x.setZero();
    out.x.template head<N>() = dual.x();
    out.objective = c_orig.dot(dual.x());
    return out;
  }
  return out;
}

template <int N>
LpResult solve_fixed(const DenseLp& lp, std::vector<double>& buffer) {
  bool finite = true;
  const Columns cols = copy_columns<N>(lp, buffer, finite);
  if (!finite) lp.validate();  // throws, naming the row (else a finite sum overflowed)
  const Eigen::Matrix<double, N, 1> c = lp.c.template head<N>();
  return solve_columns<N>(cols, lp.maximise ? Eigen::Matrix<double, N, 1>(-c) : c, c);
}

class NativeSolver final : public LpSolver {
 public:
  LpBackend backend() const override { return LpBackend::native; }
  LpResult solve(const DenseLp& lp) override {
    // The rows are checked in the solver's first pass over them; the rest here.
    const auto lo = lp.lower.array(), up = lp.upper.array();
    if (lp.vars < 1 || lp.vars > kLpMaxVars || !(lp.scale > 0) || !std::isfinite(lp.scale) ||
        !(lo <= up).all() || (lo == kInf).any() || (up == -kInf).any() ||
        !std::isfinite(lp.c.head(lp.vars).sum()))
      lp.validate();
    switch (lp.vars) {
      case 1:
        return solve_fixed<1>(lp, buffer_);
      case 2:
        return solve_fixed<2>(lp, buffer_);
      case 3:
        return solve_fixed<3>(lp, buffer_);
      case 4:
        return solve_fixed<4>(lp, buffer_);
    }
    SLICE_ASSERT(false);
  }
  LpResult solve_cut(const CutLp& cut) override {
    const Columns cols = cut_columns(cut, buffer_);
    const Eigen::Vector3d c(0, 0, 1);
    return solve_columns<3>(cols, c, c);
  }

 private:
  std::vector<double> buffer_;  // the rows column by column; grows, never shrinks
};

}  // namespace

std::unique_ptr<LpSolver> make_native_solver() { return std::make_unique<NativeSolver>(); }

}  // namespace slice::detail

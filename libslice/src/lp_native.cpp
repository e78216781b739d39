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
// Accuracy: x and y are recomputed every iteration from the original rows by a partially
// pivoted LU of the N x N basis (no drifting update), and refined at the end. For the cut and
// Chebyshev LPs the optimal multipliers sum to 1, so the objective's error is a few rounding
// errors of |b| + |x|, whatever the basis' condition (see the property tests).
//
// Degeneracy: Harris' two-pass ratio test picks the largest pivot among near-ties; if the
// iterations exceed a multiple of the rows (cycling), pricing switches to Bland's rule, which
// terminates. Once primal feasible, multipliers that rounding or Harris' tolerance left
// negative are removed by primal simplex steps (a near-flat objective needs them: see
// kFinalDualTol). No heap allocation: the rows are read in place.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "lp_backends.hpp"
#include "slice/error.hpp"

namespace slice::detail {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// A row is violated when a . x - b exceeds kFeasUlps eps (scale + |x|_inf + |b|): the residual
// is a dot product of 4 terms, so its rounding error is a few eps times these magnitudes.
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
// A recession direction r (|r_j| <= 1) proves unboundedness if c . r < -kRecessionTol |c|_1.
constexpr double kRecessionTol = 1e-9;

enum class Outcome { optimal, infeasible, infeasible_in_box, unbounded, failed };

template <int N>
class DualSimplex {
 public:
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;

  /// homogeneous: solve the recession LP (b = 0, finite bounds 0, free variables in [-1, 1]).
  DualSimplex(const DenseLp& lp, const Vec& c, double box, bool homogeneous)
      : lp_(lp), c_(c), m_(static_cast<int>(lp.rows.size())), box_(box), homog_(homogeneous) {}

  Outcome run() {
    start_basis();
    const int candidates = m_ + 2 * N;
    const int bland_after = 50 + 10 * candidates;
    const int limit = bland_after + 200 + 50 * candidates;
    const int cleanup_limit = 10 + 2 * candidates;
    int cleanups = 0;
    for (iterations_ = 0; iterations_ < limit; ++iterations_) {
      if (!factor_basis()) return Outcome::failed;
      const bool bland = iterations_ >= bland_after;
      const int q = price(bland);
      if (q < 0) {
        // Primal feasible. Dual feasible too, unless rounding or Harris' tolerance left a
        // negative multiplier: then a primal simplex step drops that row.
        const int k = most_negative_multiplier();
        if (k < 0 || cleanups >= cleanup_limit) {
          refine();
          return Outcome::optimal;
        }
        const Vec d = solve(-Vec::Unit(k));  // leaves row k, keeps the other basis rows tight
        const int p = primal_ratio_test(d);
        if (p < 0) {
          // Nothing blocks: c . d = y_k < 0 along a feasible ray.
          if (y_[k] < -kRecessionTol * c_.cwiseAbs().sum()) return Outcome::unbounded;
          refine();
          return Outcome::optimal;
        }
        basis_[k] = p;
        ++cleanups;
        continue;
      }
      const Vec aq = row_a(q);
      const Vec alpha = solve_transposed(aq);
      const int k = ratio_test(alpha, aq.cwiseAbs().maxCoeff(), bland);
      if (k < 0) {
        for (int j = 0; j < N; ++j)
          if (artificial(basis_[j]) && alpha[j] < 0) return Outcome::infeasible_in_box;
        return Outcome::infeasible;
      }
      basis_[k] = q;
    }
    return Outcome::failed;
  }

  const Vec& x() const { return x_; }
  const Vec& y() const { return y_; }
  int iterations() const { return iterations_; }
  /// An artificial row is in the basis with a multiplier that matters.
  bool leans_on_box() const {
    const double tol = kDualTol * c_.cwiseAbs().maxCoeff();
    for (int j = 0; j < N; ++j)
      if (artificial(basis_[j]) && y_[j] > tol) return true;
    return false;
  }

 private:
  // Rows 0..m-1 are lp.rows; row m + 2j is -x_j <= -lower_j, row m + 2j + 1 is x_j <= upper_j.
  Vec row_a(int i) const {
    if (i < m_) return lp_.rows[i].a.template head<N>();
    const int j = (i - m_) / 2;
    Vec a = Vec::Zero();
    a[j] = ((i - m_) % 2 == 0) ? -1 : 1;
    return a;
  }
  double bound(int i) const {  // the bound of row i >= m as the row's b (+inf if none)
    const int j = (i - m_) / 2;
    return ((i - m_) % 2 == 0) ? -lp_.lower[j] : lp_.upper[j];
  }
  bool artificial(int i) const { return i >= m_ && !homog_ && bound(i) == DenseLp::kInf; }
  double row_b(int i) const {
    if (i < m_) return homog_ ? 0.0 : lp_.rows[i].b;
    const double b = bound(i);
    if (homog_) return b == DenseLp::kInf ? 1.0 : 0.0;
    return b == DenseLp::kInf ? box_ : b;
  }

  void start_basis() {
    for (int j = 0; j < N; ++j) {
      const int lo = m_ + 2 * j, up = lo + 1;
      // Minimising c_j x_j: c_j > 0 pushes x_j down onto its lower bound, c_j < 0 up.
      if (c_[j] > 0)
        basis_[j] = lo;
      else if (c_[j] < 0)
        basis_[j] = up;
      else
        basis_[j] = (bound(lo) != DenseLp::kInf || bound(up) == DenseLp::kInf) ? lo : up;
    }
  }

  bool factor_basis() {
    Vec b;
    for (int k = 0; k < N; ++k) {
      lu_.row(k) = row_a(basis_[k]).transpose();
      b[k] = row_b(basis_[k]);
      perm_[k] = k;
    }
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
      for (int i = k + 1; i < N; ++i) {
        lu_(i, k) /= lu_(k, k);
        for (int j = k + 1; j < N; ++j) lu_(i, j) -= lu_(i, k) * lu_(k, j);
      }
    }
    b_ = b;
    x_ = solve(b);
    y_ = solve_transposed(-c_);
    return x_.allFinite() && y_.allFinite();
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
      z[i] = s / lu_(i, i);
    }
    return z;
  }

  Vec solve_transposed(const Vec& rhs) const {  // B^T y = rhs, B^T = U^T L^T P
    Vec w;
    for (int i = 0; i < N; ++i) {
      double s = rhs[i];
      for (int j = 0; j < i; ++j) s -= lu_(j, i) * w[j];
      w[i] = s / lu_(i, i);
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
    for (int step = 0; step < 2; ++step) {
      Vec r;
      for (int k = 0; k < N; ++k) {
        const Vec a = row_a(basis_[k]);
        long double s = b_[k];
        for (int j = 0; j < N; ++j)
          s -= static_cast<long double>(a[j]) * static_cast<long double>(x_[j]);
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

  /// The entering row: the most violated one (Dantzig) or the first violated one (Bland).
  int price(bool bland) const {
    const double xn = x_.cwiseAbs().maxCoeff();
    const double base = kFeasUlps * kEps * (lp_.scale + xn);
    int q = -1;
    double worst = 0;
    for (int i = 0; i < m_; ++i) {
      const LpRow& r = lp_.rows[i];
      const double b = homog_ ? 0.0 : r.b;
      const double v = r.a.template head<N>().dot(x_) - b;
      if (v > base + kFeasUlps * kEps * std::abs(b) && v > worst && !in_basis(i)) {
        q = i;
        worst = v;
        if (bland) return q;
      }
    }
    for (int i = m_; i < m_ + 2 * N; ++i) {
      const double b = bound(i);
      if (b == DenseLp::kInf) continue;  // no bound: artificial or absent, never priced
      const double bb = homog_ ? 0.0 : b;
      const double v = row_a(i).dot(x_) - bb;
      if (v > base + kFeasUlps * kEps * std::abs(bb) && v > worst && !in_basis(i)) {
        q = i;
        worst = v;
        if (bland) return q;
      }
    }
    return q;
  }

  int most_negative_multiplier() const {
    int k = -1;
    double worst = -kFinalDualTol * c_.cwiseAbs().maxCoeff();
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
    auto consider = [&](int i, const Vec& a, double b) {
      const double ad = a.dot(d);
      if (!(ad > kPivotTol * dn * a.cwiseAbs().maxCoeff()) || in_basis(i)) return;
      const double t = std::max(b - a.dot(x_), 0.0) / ad;
      if (best < 0 || t < best_t || (t == best_t && ad > best_ad)) {
        best = i;
        best_t = t;
        best_ad = ad;
      }
    };
    for (int i = 0; i < m_; ++i)
      consider(i, lp_.rows[i].a.template head<N>(), homog_ ? 0.0 : lp_.rows[i].b);
    for (int i = m_; i < m_ + 2 * N; ++i)
      if (bound(i) != DenseLp::kInf) consider(i, row_a(i), row_b(i));
    return best;
  }

  /// The leaving basis position, or -1 if no multiplier decreases (infeasible).
  int ratio_test(const Vec& alpha, double aq_norm, bool bland) const {
    std::array<bool, N> ok{};
    bool any = false;
    for (int k = 0; k < N; ++k) {
      const double ak_norm = row_a(basis_[k]).cwiseAbs().maxCoeff();
      ok[k] = alpha[k] * ak_norm > kPivotTol * aq_norm;
      any = any || ok[k];
    }
    if (!any) return -1;
    if (bland) {  // exact minimum ratio, ties to the smallest row index
      int best = -1;
      double best_ratio = 0;
      for (int k = 0; k < N; ++k) {
        if (!ok[k]) continue;
        const double ratio = std::max(y_[k], 0.0) / alpha[k];
        if (best < 0 || ratio < best_ratio || (ratio == best_ratio && basis_[k] < basis_[best])) {
          best = k;
          best_ratio = ratio;
        }
      }
      return best;
    }
    // Harris: the largest step that keeps every y >= -delta, then the largest pivot within it.
    const double delta = kDualTol * c_.cwiseAbs().maxCoeff();
    double theta = std::numeric_limits<double>::infinity();
    for (int k = 0; k < N; ++k)
      if (ok[k]) theta = std::min(theta, (std::max(y_[k], 0.0) + delta) / alpha[k]);
    int best = -1;
    for (int k = 0; k < N; ++k)
      if (ok[k] && std::max(y_[k], 0.0) / alpha[k] <= theta && (best < 0 || alpha[k] > alpha[best]))
        best = k;
    return best;
  }

  const DenseLp& lp_;
  Vec c_;
  int m_;
  double box_;
  bool homog_;
  std::array<int, N> basis_{};
  std::array<int, N> perm_{};
  Mat lu_;
  Vec b_, x_, y_;
  int iterations_ = 0;
};

template <int N>
LpResult solve_fixed(const DenseLp& lp) {
  using Vec = typename DualSimplex<N>::Vec;
  const Vec c = (lp.maximise ? -lp.c : lp.c).template head<N>();
  LpResult out;
  double box = kBoxFactor * lp.scale;
  for (int level = 0; level < kBoxLevels; ++level, box *= kBoxGrowth) {
    DualSimplex<N> dual(lp, c, box, false);
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
      DualSimplex<N> rec(lp, c, 1, true);
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
    out.objective = lp.c.template head<N>().dot(dual.x());
    return out;
  }
  return out;
}

class NativeSolver final : public LpSolver {
 public:
  LpBackend backend() const override { return LpBackend::native; }
  LpResult solve(const DenseLp& lp) override {
    lp.validate();
    switch (lp.vars) {
      case 1:
        return solve_fixed<1>(lp);
      case 2:
        return solve_fixed<2>(lp);
      case 3:
        return solve_fixed<3>(lp);
      case 4:
        return solve_fixed<4>(lp);
    }
    SLICE_ASSERT(false);
  }
};

}  // namespace

std::unique_ptr<LpSolver> make_native_solver() { return std::make_unique<NativeSolver>(); }

}  // namespace slice::detail

// The ipopt backend: Ipopt's primal-dual interior point method through its C++ TNLP interface.
// The only file that includes Ipopt.
//
// Given its best chance on LPs: one IpoptApplication per solver object, initialised once;
// constant Jacobian and Hessian (Ipopt evaluates them once per solve); Mehrotra's
// predictor-corrector (Ipopt's LP/QP mode); no bound relaxation; no output. A second
// application with Ipopt's default algorithm re-solves an LP on which Mehrotra's method fails
// (it cannot detect infeasibility). Each LP is scaled so its variables are
// O(1) (x = scale x'), so Ipopt's absolute tolerances become relative to the block's size.
//
// solve_batch stacks independent LPs into one block-diagonal problem (objective = sum of the
// objectives): Ipopt's fixed cost per solve is shared, at the price of iterating until the
// hardest LP converges and factorizing a larger KKT matrix. If the stacked solve does not end
// optimal (one LP infeasible, say), the LPs are solved one by one instead. Measured with
// slice-bench-lp (pipelines/bench/results/lp.csv: 200 cut tests per set, batches of 50, one
// core of a shared 2-core machine), median time per LP single / stacked:
//   8 rows 5.5 / 0.95 ms   20 rows 8.2 / 2.4 ms   50 rows 7.3 / 7.0 ms   200 rows 18.8 / 30.9 ms
// with the same error against exact. So solve_batch stacks LPs of up to kStackMaxRows rows
// (the slicer's cut tests of one joint against many blocks are independent) and solves
// larger ones one by one; solve() is a batch of one.
#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>
#include <cmath>
#include <vector>

#include "lp_backends.hpp"
#include "slice/error.hpp"

namespace slice::detail {
namespace {

using Ipopt::Index;
using Ipopt::Number;

// Ipopt's convergence tolerance on the scaled problem (|x'| ~ 1): the accuracy the benchmark
// reports for ipopt follows from it.
constexpr double kIpoptTol = 1e-10;
// |x'| beyond this (x' = x / scale) is taken as divergence: the LP is unbounded.
constexpr double kDivergingTol = 1e10;
// Ipopt's value for "no bound" (its default nlp_lower_bound_inf / nlp_upper_bound_inf).
constexpr double kIpoptInf = 1e19;
// Mehrotra's method solves these LPs in 10-30 iterations; more means it is stuck (infeasible).
constexpr int kMehrotraMaxIter = 200;
constexpr int kMaxIter = 3000;
// solve_batch stacks LPs with at most this many rows on average, else solves them one by one
// (stacking lost at 200 rows; see above).
constexpr std::size_t kStackMaxRows = 100;

/// Several DenseLps as one NLP: variables and rows concatenated, a block-diagonal Jacobian.
class StackedLp final : public Ipopt::TNLP {
 public:
  explicit StackedLp(std::span<const DenseLp* const> lps) : lps_(lps) {
    Index n = 0, m = 0, nnz = 0;
    for (const DenseLp* lp : lps_) {
      var0_.push_back(n);
      row0_.push_back(m);
      n += lp->vars;
      m += static_cast<Index>(lp->rows.size());
      nnz += lp->vars * static_cast<Index>(lp->rows.size());
    }
    n_ = n;
    m_ = m;
    nnz_ = nnz;
  }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = n_;
    m = m_;
    nnz_jac_g = nnz_;
    nnz_h_lag = 0;  // an LP: the Hessian of the Lagrangian is zero
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index, Number* x_l, Number* x_u, Index, Number* g_l, Number* g_u) override {
    for (std::size_t k = 0; k < lps_.size(); ++k) {
      const DenseLp& lp = *lps_[k];
      for (int j = 0; j < lp.vars; ++j) {
        x_l[var0_[k] + j] = std::isfinite(lp.lower[j]) ? lp.lower[j] / lp.scale : -kIpoptInf;
        x_u[var0_[k] + j] = std::isfinite(lp.upper[j]) ? lp.upper[j] / lp.scale : kIpoptInf;
      }
      for (std::size_t i = 0; i < lp.rows.size(); ++i) {
        g_l[row0_[k] + static_cast<Index>(i)] = -kIpoptInf;
        g_u[row0_[k] + static_cast<Index>(i)] = lp.rows[i].b / lp.scale;
      }
    }
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number*, Number*, Index,
                          bool init_lambda, Number*) override {
    if (!init_x || init_z || init_lambda) return false;
    for (Index j = 0; j < n; ++j) x[j] = 0;
    return true;
  }

  bool eval_f(Index, const Number* x, bool, Number& obj) override {
    obj = 0;
    for (std::size_t k = 0; k < lps_.size(); ++k) {
      const DenseLp& lp = *lps_[k];
      const double sign = lp.maximise ? -1 : 1;
      for (int j = 0; j < lp.vars; ++j) obj += sign * lp.c[j] * x[var0_[k] + j];
    }
    return true;
  }

  bool eval_grad_f(Index, const Number*, bool, Number* grad) override {
    for (std::size_t k = 0; k < lps_.size(); ++k) {
      const DenseLp& lp = *lps_[k];
      const double sign = lp.maximise ? -1 : 1;
      for (int j = 0; j < lp.vars; ++j) grad[var0_[k] + j] = sign * lp.c[j];
    }
    return true;
  }

  bool eval_g(Index, const Number* x, bool, Index, Number* g) override {
    for (std::size_t k = 0; k < lps_.size(); ++k) {
      const DenseLp& lp = *lps_[k];
      for (std::size_t i = 0; i < lp.rows.size(); ++i) {
        double s = 0;
        for (int j = 0; j < lp.vars; ++j) s += lp.rows[i].a[j] * x[var0_[k] + j];
        g[row0_[k] + static_cast<Index>(i)] = s;
      }
    }
    return true;
  }

  bool eval_jac_g(Index, const Number*, bool, Index, Index, Index* row, Index* col,
                  Number* values) override {
    Index e = 0;
    for (std::size_t k = 0; k < lps_.size(); ++k) {
      const DenseLp& lp = *lps_[k];
      for (std::size_t i = 0; i < lp.rows.size(); ++i)
        for (int j = 0; j < lp.vars; ++j, ++e) {
          if (values == nullptr) {
            row[e] = row0_[k] + static_cast<Index>(i);
            col[e] = var0_[k] + j;
          } else {
            values[e] = lp.rows[i].a[j];
          }
        }
    }
    return true;
  }

  bool eval_h(Index, const Number*, bool, Number, Index, const Number*, bool, Index, Index*, Index*,
              Number*) override {
    return true;  // no entries
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number*,
                         const Number*, Index, const Number*, const Number*, Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x_.assign(x, x + n);
  }

  /// LP k's solution in its own units, from the last finalize_solution.
  void result(std::size_t k, LpResult& out) const {
    const DenseLp& lp = *lps_[k];
    out.x.setZero();
    for (int j = 0; j < lp.vars; ++j) out.x[j] = lp.scale * x_[var0_[k] + j];
    out.objective = lp.c.dot(out.x);
  }

 private:
  std::span<const DenseLp* const> lps_;
  std::vector<Index> var0_, row0_;
  Index n_ = 0, m_ = 0, nnz_ = 0;
  std::vector<double> x_;
};

LpStatus map_status(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded:
    case Ipopt::Solved_To_Acceptable_Level:
      return LpStatus::optimal;
    case Ipopt::Infeasible_Problem_Detected:
      return LpStatus::infeasible;
    case Ipopt::Diverging_Iterates:
      return LpStatus::unbounded;
    default:
      return LpStatus::failed;
  }
}

class IpoptSolver final : public LpSolver {
 public:
  IpoptSolver() : app_(make_app(true)), fallback_(make_app(false)) {}

  LpBackend backend() const override { return LpBackend::ipopt; }

  LpResult solve(const DenseLp& lp) override {
    lp.validate();
    const DenseLp* one[] = {&lp};
    LpResult out;
    solve_stacked(one, std::span<LpResult>(&out, 1));
    return out;
  }

  void solve_batch(std::span<const DenseLp> lps, std::span<LpResult> out) override {
    SLICE_ASSERT(lps.size() == out.size());
    if (lps.empty()) return;
    std::vector<const DenseLp*> ptrs;
    ptrs.reserve(lps.size());
    std::size_t rows = 0;
    for (const DenseLp& lp : lps) {
      lp.validate();
      ptrs.push_back(&lp);
      rows += lp.rows.size();
    }
    const bool stack = lps.size() > 1 && rows <= kStackMaxRows * lps.size();
    if (!stack || solve_stacked(ptrs, out) != LpStatus::optimal)
      for (std::size_t k = 0; k < lps.size(); ++k) solve_stacked({&ptrs[k], 1}, out.subspan(k, 1));
  }

 private:
  static Ipopt::SmartPtr<Ipopt::IpoptApplication> make_app(bool mehrotra) {
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
    Ipopt::OptionsList& o = *app->Options();
    o.SetStringValue("sb", "yes");  // no banner
    o.SetIntegerValue("print_level", 0);
    o.SetStringValue("jac_c_constant", "yes");
    o.SetStringValue("jac_d_constant", "yes");
    o.SetStringValue("hessian_constant", "yes");
    o.SetStringValue("nlp_scaling_method", "none");  // the LP is scaled already
    o.SetNumericValue("tol", kIpoptTol);
    // Ipopt relaxes every bound by 1e-8 (relative) by default: a touching plane would then
    // seem to cut by ~1e-8 L. An LP has no reason for it.
    o.SetNumericValue("bound_relax_factor", 0);
    o.SetNumericValue("diverging_iterates_tol", kDivergingTol);
    if (mehrotra) {
      o.SetStringValue("mehrotra_algorithm", "yes");
      o.SetIntegerValue("max_iter", kMehrotraMaxIter);
    } else {
      o.SetIntegerValue("max_iter", kMaxIter);
    }
    if (app->Initialize() != Ipopt::Solve_Succeeded)
      throw Error("ipopt", "IpoptApplication::Initialize failed",
                  "check the Ipopt installation (coinor-libipopt-dev)");
    return app;
  }

  LpStatus solve_stacked(std::span<const DenseLp* const> lps, std::span<LpResult> out) {
    Ipopt::SmartPtr<StackedLp> nlp = new StackedLp(lps);
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = app_;
    LpStatus status = map_status(app->OptimizeTNLP(nlp));
    if (status == LpStatus::failed) {
      // Mehrotra's method takes every step and so has no restoration phase: on an infeasible
      // LP it runs out of iterations. Ipopt's default filter line search detects infeasibility.
      app = fallback_;
      status = map_status(app->OptimizeTNLP(nlp));
    }
    const Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics();
    const int iterations = Ipopt::IsValid(stats) ? stats->IterationCount() : 0;
    for (std::size_t k = 0; k < lps.size(); ++k) {
      out[k] = LpResult{};
      out[k].status = status;
      out[k].iterations = iterations;
      if (status == LpStatus::optimal) nlp->result(k, out[k]);
    }
    return status;
  }

  Ipopt::SmartPtr<Ipopt::IpoptApplication> app_;       // Mehrotra predictor-corrector
  Ipopt::SmartPtr<Ipopt::IpoptApplication> fallback_;  // Ipopt's default algorithm
};

}  // namespace

std::unique_ptr<LpSolver> make_ipopt_solver() { return std::make_unique<IpoptSolver>(); }

}  // namespace slice::detail

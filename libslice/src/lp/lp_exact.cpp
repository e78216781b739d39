// The exact backend: CGAL's linear programming solver over CGAL::Gmpzf (arbitrary-precision
// binary floats: every double is one, and sums and products are exact), so the answer is exact
// for the LP as given in doubles. The reference for every error figure. The only file that
// includes CGAL.
#include <CGAL/Gmpzf.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>
#include <gmp.h>

#include <cmath>

#include "lp_backends.hpp"

namespace slice::detail {
namespace {

using ET = CGAL::Gmpzf;
using Exact = CGAL::Quotient<ET>;

/// num / den to within an ulp, without overflow: the mantissas divide as a rational, the
/// exponents subtract.
double to_double(const Exact& q) {
  const ET& num = q.numerator();
  const ET& den = q.denominator();
  if (mpz_sgn(num.man()) == 0) return 0;
  mpq_t r;
  mpq_init(r);
  mpz_set(mpq_numref(r), num.man());
  mpz_set(mpq_denref(r), den.man());
  mpq_canonicalize(r);
  // Bring the quotient near 1 before converting, so mpq_get_d neither under- nor overflows.
  const long shift = static_cast<long>(mpz_sizeinbase(mpq_numref(r), 2)) -
                     static_cast<long>(mpz_sizeinbase(mpq_denref(r), 2));
  if (shift > 0)
    mpz_mul_2exp(mpq_denref(r), mpq_denref(r), static_cast<mp_bitcnt_t>(shift));
  else if (shift < 0)
    mpz_mul_2exp(mpq_numref(r), mpq_numref(r), static_cast<mp_bitcnt_t>(-shift));
  const double m = mpq_get_d(r);
  mpq_clear(r);
  return std::ldexp(m, static_cast<int>(shift + num.exp() - den.exp()));
}

class ExactSolver final : public LpSolver {
 public:
  LpBackend backend() const override { return LpBackend::exact; }

  LpResult solve(const DenseLp& lp) override {
    lp.validate();
    // Rows a . x <= b, variables free unless bounded; CGAL minimises.
    CGAL::Quadratic_program<double> qp(CGAL::SMALLER, false, 0, false, 0);
    const double sign = lp.maximise ? -1 : 1;
    for (int j = 0; j < lp.vars; ++j) {
      qp.set_c(j, sign * lp.c[j]);
      if (std::isfinite(lp.lower[j])) qp.set_l(j, true, lp.lower[j]);
      if (std::isfinite(lp.upper[j])) qp.set_u(j, true, lp.upper[j]);
    }
    for (std::size_t i = 0; i < lp.rows.size(); ++i) {
      const int row = static_cast<int>(i);
      for (int j = 0; j < lp.vars; ++j)
        if (lp.rows[i].a[j] != 0) qp.set_a(j, row, lp.rows[i].a[j]);
      qp.set_b(row, lp.rows[i].b);
    }
    // CGAL needs to know every variable even if no row mentions it.
    for (int j = 0; j < lp.vars; ++j)
      if (lp.c[j] == 0) qp.set_c(j, 0.0);

    const CGAL::Quadratic_program_solution<ET> s = CGAL::solve_linear_program(qp, ET());
    LpResult out;
    out.iterations = s.number_of_iterations();
    switch (s.status()) {
      case CGAL::QP_OPTIMAL: {
        out.status = LpStatus::optimal;
        int j = 0;
        for (auto it = s.variable_values_begin(); it != s.variable_values_end() && j < lp.vars;
             ++it, ++j)
          out.x[j] = to_double(*it);
        out.objective = sign * to_double(s.objective_value());
        break;
      }
      case CGAL::QP_INFEASIBLE:
        out.status = LpStatus::infeasible;
        break;
      case CGAL::QP_UNBOUNDED:
        out.status = LpStatus::unbounded;
        break;
      default:  // QP_UPDATE: the solver stopped mid-way
        out.status = LpStatus::failed;
        break;
    }
    return out;
  }
};

}  // namespace

std::unique_ptr<LpSolver> make_exact_solver() { return std::make_unique<ExactSolver>(); }

}  // namespace slice::detail

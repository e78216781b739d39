#include "slice/decide.hpp"

#include <cmath>
#include <limits>
#include <type_traits>

namespace slice {
namespace {

// The default band: this many rounding errors of the domain's length scale. The native solver's
// answers are within a few of the exact ones (slice-bench-lp: 3.3e-16 L at worst).
constexpr double kDoubtUlps = 256;

/// The backend, and the exact backend for every LP it fails on.
class FallbackSolver final : public LpSolver {
 public:
  FallbackSolver(LpBackend backend, DecisionCounts& counts)
      : primary_(make_solver(backend)), counts_(counts) {}
  LpBackend backend() const override { return primary_->backend(); }
  LpResult solve(const DenseLp& lp) override { return settle(primary_->solve(lp), lp); }
  LpResult solve_cut(const CutLp& cut) override {
    const LpResult r = primary_->solve_cut(cut);
    if (r.status != LpStatus::failed) return r;
    return settle(r, cut);
  }
  LpSolver& exact() {
    if (!exact_) exact_ = make_solver(LpBackend::exact);
    return *exact_;
  }

 private:
  template <class Problem>
  LpResult settle(const LpResult& r, const Problem& p) {
    if (r.status != LpStatus::failed || primary_->backend() == LpBackend::exact) {
      if (r.status == LpStatus::failed) ++counts_.failed;
      return r;
    }
    ++counts_.resolved;
    LpResult e;
    if constexpr (std::is_same_v<Problem, CutLp>)
      e = exact().solve_cut(p);
    else
      e = exact().solve(p);
    if (e.status == LpStatus::failed) ++counts_.failed;
    return e;
  }

  std::unique_ptr<LpSolver> primary_;
  std::unique_ptr<LpSolver> exact_;
  DecisionCounts& counts_;
};

}  // namespace

DecisionCounts& DecisionCounts::operator+=(const DecisionCounts& o) {
  resolved += o.resolved;
  failed += o.failed;
  checked += o.checked;
  changed += o.changed;
  return *this;
}

struct Referee::Impl {
  Impl(LpBackend backend, const Tolerances& t, bool certify)
      : tol(t),
        solver(backend, counts),
        recheck(backend != LpBackend::exact),
        cut_band(certify ? t.cut
                         : kDoubtUlps * std::numeric_limits<double>::epsilon() * t.length_scale),
        prune_band(certify ? t.prune : cut_band),
        relative_band(certify ? t.cut / t.length_scale  // the scene's relative tolerance
                              : kDoubtUlps * std::numeric_limits<double>::epsilon()) {}
  Tolerances tol;
  DecisionCounts counts;
  FallbackSolver solver;
  bool recheck;
  double cut_band, prune_band;
  double relative_band;  // for the limits, relative to the limit
};

Referee::Referee(LpBackend backend, const Tolerances& tol, bool certify)
    : impl_(std::make_unique<Impl>(backend, tol, certify)) {}
Referee::~Referee() = default;

LpSolver& Referee::solver() { return impl_->solver; }
const DecisionCounts& Referee::counts() const { return impl_->counts; }

CutTest Referee::cut(std::span<const Face> faces, const Plane& plane,
                     std::span<const Plane> edges) {
  Impl& m = *impl_;
  const CutTest t = cut_test(m.solver, faces, plane, edges, m.tol);
  if (!m.recheck || t.status != LpStatus::optimal || std::abs(t.s + m.tol.cut) > m.cut_band)
    return t;
  ++m.counts.checked;
  const CutTest e = cut_test(m.solver.exact(), faces, plane, edges, m.tol);
  if (e.status != LpStatus::optimal) ++m.counts.failed;
  if (e.cuts != t.cuts) ++m.counts.changed;
  return e;
}

FaceRedundancy Referee::redundancy(std::span<const Face> faces, std::size_t index) {
  Impl& m = *impl_;
  const FaceRedundancy r = face_redundancy(m.solver, faces, index, m.tol);
  if (!m.recheck || r.status != LpStatus::optimal ||
      std::abs(r.value - (faces[index].d + m.tol.prune)) > m.prune_band)
    return r;
  ++m.counts.checked;
  const FaceRedundancy e = face_redundancy(m.solver.exact(), faces, index, m.tol);
  if (e.status == LpStatus::failed) ++m.counts.failed;
  if (e.redundant != r.redundant) ++m.counts.changed;
  return e;
}

double Referee::limit_band(double limit) const {
  const Impl& m = *impl_;
  return m.recheck ? m.relative_band * limit + m.cut_band : 0.0;
}

ChebyshevBall Referee::limit_ball(std::span<const Face> faces, double min_diameter,
                                  double max_aspect, double bounding_radius) {
  Impl& m = *impl_;
  const ChebyshevBall c = chebyshev_ball(m.solver, faces, m.tol);
  if (!m.recheck || c.status != LpStatus::optimal) return c;
  const auto near = [&](double value, double limit) {
    return limit > 0 && std::abs(value - limit) <= m.relative_band * limit + m.cut_band;
  };
  const auto passes = [&](const ChebyshevBall& b) {
    return within_limits(b.radius, bounding_radius, min_diameter, max_aspect);
  };
  if (!near(2 * c.radius, min_diameter) && !near(bounding_radius, max_aspect * c.radius)) return c;
  ++m.counts.checked;
  const ChebyshevBall e = chebyshev_ball(m.solver.exact(), faces, m.tol);
  if (e.status != LpStatus::optimal) {
    ++m.counts.failed;
    return c;
  }
  if (passes(e) != passes(c)) ++m.counts.changed;
  return e;
}

}  // namespace slice

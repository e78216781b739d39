#pragma once
// Private: the backend factories behind make_solver (one .cpp each, so that only lp_ipopt.cpp
// sees Ipopt and only lp_exact.cpp sees CGAL).
#include <memory>

#include "slice/lp.hpp"

namespace slice::detail {

/// A face's or polygon edge's row of the cut LP: (n . U) u + (n . V) v - s <= d - n . p0. One
/// formula for every backend, so that they all solve the same doubles.
struct CutRow {
  double au, av, b;
};
inline CutRow cut_row(const Vec3& n, double d, const PlaneFrame& f) {
  // Written out: the same sums in the same order wherever it is inlined.
  const double au = n.x() * f.u.x() + n.y() * f.u.y() + n.z() * f.u.z();
  const double av = n.x() * f.v.x() + n.y() * f.v.y() + n.z() * f.v.z();
  const double np = n.x() * f.p0.x() + n.y() * f.p0.y() + n.z() * f.p0.z();
  return {au, av, d - np};
}

std::unique_ptr<LpSolver> make_native_solver();
std::unique_ptr<LpSolver> make_ipopt_solver();
std::unique_ptr<LpSolver> make_exact_solver();

}  // namespace slice::detail

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
  return {n.dot(f.u), n.dot(f.v), d - n.dot(f.p0)};
}

std::unique_ptr<LpSolver> make_native_solver();
std::unique_ptr<LpSolver> make_ipopt_solver();
std::unique_ptr<LpSolver> make_exact_solver();

}  // namespace slice::detail

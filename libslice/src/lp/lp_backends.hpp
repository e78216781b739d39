#pragma once
// Private: the backend factories behind make_solver (one .cpp each, so that only lp_ipopt.cpp
// sees Ipopt and only lp_exact.cpp sees CGAL), and the cut LP's rows, checks and bounds that
// lp.cpp and the native backend's own builder share.
#include <algorithm>
#include <cmath>
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

// A face normal is unit if | |n|^2 - 1 | is below this. Dimensionless: normals come from sin/cos
// of angles or from normalisation, both good to a few ulps; this only catches unnormalised input.
inline constexpr double kUnitNormalTol = 1e-10;

/// n is a finite unit vector (| |n|^2 - 1 | <= kUnitNormalTol; a NaN or inf fails) and d finite.
/// The AVX2 row builder in lp_native.cpp computes the same |n|^2 in the same order.
inline bool unit_row_ok(const Vec3& n, double d) {
  const double n2 = n.x() * n.x() + n.y() * n.y() + n.z() * n.z();
  return std::abs(n2 - 1) <= kUnitNormalTol && std::isfinite(d);
}

/// Throws Error naming the first face or polygon edge of `cut` without a finite unit normal or a
/// finite d; returns max |d| over the faces.
double check_cut_rows(const CutLp& cut);

/// The cut LP's bound on s and its DenseLp::scale, given max |d| over the faces.
struct CutBounds {
  double s_lower, scale;
};
inline CutBounds cut_bounds(const CutLp& cut, double dmax) {
  const double block = dmax > 0 ? dmax : cut.length_scale;
  return {-(2 * dmax + cut.length_scale), std::max(block, std::abs(cut.plane_d))};
}

std::unique_ptr<LpSolver> make_native_solver();
std::unique_ptr<LpSolver> make_ipopt_solver();
std::unique_ptr<LpSolver> make_exact_solver();

}  // namespace slice::detail

#pragma once
// Private: the backend factories behind make_solver (one .cpp each, so that only lp_ipopt.cpp
// sees Ipopt and only lp_exact.cpp sees CGAL).
#include <memory>

#include "slice/lp.hpp"

namespace slice::detail {

std::unique_ptr<LpSolver> make_native_solver();
std::unique_ptr<LpSolver> make_ipopt_solver();
std::unique_ptr<LpSolver> make_exact_solver();

}  // namespace slice::detail

#pragma once
// Field-by-field equality of the library's data (exact: for HDF5 round trips), with Catch2
// assertions that name the row that differs.
#include "slice/h5io.hpp"

namespace test {

void check_same(const slice::Plane& a, const slice::Plane& b);
void check_same(const slice::Region& a, const slice::Region& b);
void check_same(const slice::JointSystem& a, const slice::JointSystem& b);
void check_same(const slice::BlockSystem& a, const slice::BlockSystem& b);

}  // namespace test

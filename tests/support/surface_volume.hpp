#pragma once
// Closed forms for tests of ground surfaces (surface_zone_test.cpp, geotiff_test.cpp).
#include <array>
#include <string>

#include "slice/geometry.hpp"

namespace test {

/// The integral over the triangle's plan of clamp(h, z0, z1) - z0, h linear on it: the part
/// with h in [z0, z1] by fans (a linear function's integral over a triangle is its area times
/// the mean of its corners), plus the part above z1 as a flat column. Summed over a surface's
/// triangles: the rock between z0 and z1 under it.
double column_volume(const std::array<slice::Vec3, 3>& t, double z0, double z1);

/// The surface tests' scene: two sets of joints (bedding 15/040 at 2.9, joints 75/130 at 3.4) in
/// the domain `box` (a TOML array), and one zone whose keys are `zone`.
std::string surface_scene(const std::string& name, const std::string& box, const std::string& zone);

}  // namespace test

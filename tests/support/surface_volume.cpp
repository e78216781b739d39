#include "support/surface_volume.hpp"

#include <cmath>
#include <vector>

#include "slice/polytope.hpp"

namespace test {

std::string surface_scene(const std::string& name, const std::string& box,
                          const std::string& zone) {
  return "[scene]\nname = \"" + name + "\"\n[domain]\nbox = " + box + R"(
[[sets]]
name = "bedding"
dip = 15
dip_direction = 40
spacing = 2.9
[[sets]]
name = "joints"
dip = 75
dip_direction = 130
spacing = 3.4
[[zones]]
)" + zone +
         "\n";
}

double column_volume(const std::array<slice::Vec3, 3>& t, double z0, double z1) {
  using slice::Vec3;
  const std::vector<Vec3> poly(t.begin(), t.end());
  const auto integral = [&](const std::vector<Vec3>& p, bool at_top) {
    double v = 0;
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
      const double area = std::abs((p[k] - p[0]).cross(p[k + 1] - p[0]).z()) / 2;
      const double h = at_top ? z1 : (p[0].z() + p[k].z() + p[k + 1].z()) / 3;
      v += area * (h - z0);
    }
    return v;
  };
  const auto mid =
      slice::clip_polygon(slice::clip_polygon(poly, {Vec3::UnitZ(), z1}), {-Vec3::UnitZ(), -z0});
  return integral(mid, false) + integral(slice::clip_polygon(poly, {-Vec3::UnitZ(), -z1}), true);
}

}  // namespace test

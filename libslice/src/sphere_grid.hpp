#pragma once
// A uniform grid over bounding spheres: which blocks may a plane or a box reach? Each block is
// listed in every cell its sphere's bounding box overlaps; queries visit the cells a plane or
// box passes through, so a joint meets the blocks near it, not all of them (paper Fig. 20:
// cost linear in the number of blocks). Visits may repeat a block and include blocks the
// plane misses: callers deduplicate and test spheres exactly.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "slice/geometry.hpp"

namespace slice {

class SphereGrid {
 public:
  /// An empty grid over the box [lo, hi] with about `cells` cubic cells.
  void reset(const Vec3& lo, const Vec3& hi, std::size_t cells) {
    lo_ = lo;
    const Vec3 size = (hi - lo).cwiseMax(1e-300);
    h_ = std::cbrt(size.prod() / double(std::max<std::size_t>(cells, 1)));
    h_ = std::max(h_, size.maxCoeff() / 1024);  // at most 1024 cells along an axis
    for (int k = 0; k < 3; ++k) n_[k] = std::max(1, int(std::ceil(size[k] / h_)));
    cells_.assign(std::size_t(n_[0]) * std::size_t(n_[1]) * std::size_t(n_[2]), {});
  }

  void insert(std::size_t id, const Eigen::Vector4d& sphere) {
    std::array<int, 3> a{}, b{};
    const Vec3 c = sphere.head<3>();
    for (int k = 0; k < 3; ++k) {
      a[k] = index(k, c[k] - sphere[3]);
      b[k] = index(k, c[k] + sphere[3]);
    }
    for (int i = a[0]; i <= b[0]; ++i)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int k = a[2]; k <= b[2]; ++k) cells_[cell(i, j, k)].push_back(std::uint32_t(id));
  }

  /// Visits the blocks of every cell the plane normal . x = d passes through.
  template <typename Visit>
  void visit_plane(const Plane& p, Visit&& visit) const {
    int k = 0;  // the axis the normal is most aligned with: solve the plane for it
    for (int a = 1; a < 3; ++a)
      if (std::abs(p.normal[a]) > std::abs(p.normal[k])) k = a;
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    std::array<int, 3> idx{};
    for (int i = 0; i < n_[a]; ++i) {
      for (int j = 0; j < n_[b]; ++j) {
        // The plane's range along k over the column's four corners.
        double tmin = INFINITY, tmax = -INFINITY;
        for (int ci = 0; ci < 2; ++ci)
          for (int cj = 0; cj < 2; ++cj) {
            const double x = lo_[a] + (i + ci) * h_, y = lo_[b] + (j + cj) * h_;
            const double t = (p.d - p.normal[a] * x - p.normal[b] * y) / p.normal[k];
            tmin = std::min(tmin, t);
            tmax = std::max(tmax, t);
          }
        if (tmax < lo_[k] || tmin > lo_[k] + n_[k] * h_) continue;
        const int k0 = index(k, tmin), k1 = index(k, tmax);
        idx[a] = i;
        idx[b] = j;
        for (int m = k0; m <= k1; ++m) {
          idx[k] = m;
          for (const std::uint32_t id : cells_[cell(idx[0], idx[1], idx[2])]) visit(id);
        }
      }
    }
  }

  /// Visits the blocks of every cell the box [lo, hi] overlaps.
  template <typename Visit>
  void visit_box(const Vec3& lo, const Vec3& hi, Visit&& visit) const {
    std::array<int, 3> a{}, b{};
    for (int k = 0; k < 3; ++k) {
      if (hi[k] < lo_[k] || lo[k] > lo_[k] + n_[k] * h_) return;
      a[k] = index(k, lo[k]);
      b[k] = index(k, hi[k]);
    }
    for (int i = a[0]; i <= b[0]; ++i)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int k = a[2]; k <= b[2]; ++k)
          for (const std::uint32_t id : cells_[cell(i, j, k)]) visit(id);
  }

 private:
  Vec3 lo_ = Vec3::Zero();
  double h_ = 1;
  std::array<int, 3> n_{1, 1, 1};
  std::vector<std::vector<std::uint32_t>> cells_;

  int index(int axis, double x) const {
    const double t = std::floor((x - lo_[axis]) / h_);
    return int(std::clamp(t, 0.0, double(n_[axis] - 1)));
  }
  std::size_t cell(int i, int j, int k) const {
    return (std::size_t(i) * std::size_t(n_[1]) + std::size_t(j)) * std::size_t(n_[2]) +
           std::size_t(k);
  }
};

}  // namespace slice

#pragma once
// A loose multi-level grid over bounding spheres: which blocks may a plane or a box reach?
// Level l has cubic cells of size h_l = h_0 2^l; a sphere of radius R is stored once, in the
// cell of its centre on the finest level with R <= h_l / 2, so it lies inside that cell grown
// by h_l / 2 on every side (its "loose" cell). A query visits, on every level, the cells whose
// loose box meets the plane or box. One entry per block whatever its size, so memory stays
// linear even while early, large blocks span the domain; a joint meets the blocks near it,
// not all of them (paper Fig. 20: cost linear in the number of blocks). Visits include
// blocks the plane misses: callers test spheres exactly.
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
  /// An empty grid over the box [lo, hi] whose finest level has about `cells` cells.
  void reset(const Vec3& lo, const Vec3& hi, std::size_t cells) {
    lo_ = lo;
    const Vec3 size = (hi - lo).cwiseMax(1e-300);
    double h = std::cbrt(size.prod() / double(std::max<std::size_t>(cells, 1)));
    h = std::max(h, size.maxCoeff() / 1024);  // at most 1024 cells along an axis
    levels_.clear();
    // Coarser levels until one cell holds any sphere of the domain (R <= half its diagonal).
    const double needed = size.norm();
    for (;; h *= 2) {
      Level l;
      l.h = h;
      for (int k = 0; k < 3; ++k) l.n[k] = std::max(1, int(std::ceil(size[k] / h)));
      l.cells.assign(std::size_t(l.n[0]) * std::size_t(l.n[1]) * std::size_t(l.n[2]), {});
      levels_.push_back(std::move(l));
      if (h >= needed) break;
    }
    where_.clear();
  }

  void insert(std::size_t id, const Eigen::Vector4d& sphere) {
    std::size_t lev = 0;
    while (lev + 1 < levels_.size() && sphere[3] > levels_[lev].h / 2) ++lev;
    Level& l = levels_[lev];
    std::array<int, 3> c{};
    for (int k = 0; k < 3; ++k) c[k] = l.index(k, sphere[k] - lo_[k]);
    const std::size_t cell = l.cell(c[0], c[1], c[2]);
    l.cells[cell].push_back(std::uint32_t(id));
    if (where_.size() <= id) where_.resize(id + 1, {kNone, 0});
    where_[id] = {std::uint32_t(lev), std::uint32_t(cell)};
  }

  /// Moves a block whose sphere changed.
  void update(std::size_t id, const Eigen::Vector4d& sphere) {
    erase(id);
    insert(id, sphere);
  }

  /// Visits the blocks stored in every loose cell the plane normal . x = d passes through.
  template <typename Visit>
  void visit_plane(const Plane& p, Visit&& visit) const {
    int k = 0;  // the axis the normal is most aligned with: solve the plane for it
    for (int a = 1; a < 3; ++a)
      if (std::abs(p.normal[a]) > std::abs(p.normal[k])) k = a;
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    for (const Level& l : levels_) {
      const double m = l.h / 2;  // loose margin
      std::array<int, 3> idx{};
      for (int i = 0; i < l.n[a]; ++i) {
        for (int j = 0; j < l.n[b]; ++j) {
          // The plane's range along k over the loose column's four corners.
          double tmin = INFINITY, tmax = -INFINITY;
          for (int ci = 0; ci < 2; ++ci)
            for (int cj = 0; cj < 2; ++cj) {
              const double x = lo_[a] + (i + ci) * l.h + (ci ? m : -m);
              const double y = lo_[b] + (j + cj) * l.h + (cj ? m : -m);
              const double t = (p.d - p.normal[a] * x - p.normal[b] * y) / p.normal[k];
              tmin = std::min(tmin, t);
              tmax = std::max(tmax, t);
            }
          tmin -= lo_[k] + m;
          tmax -= lo_[k] - m;
          if (tmax < 0 || tmin > l.n[k] * l.h) continue;
          idx[a] = i;
          idx[b] = j;
          const int k1 = l.index(k, tmax);
          for (int c = l.index(k, tmin); c <= k1; ++c) {
            idx[k] = c;
            for (const std::uint32_t id : l.cells[l.cell(idx[0], idx[1], idx[2])]) visit(id);
          }
        }
      }
    }
  }

  /// Visits the blocks stored in every loose cell the box [lo, hi] overlaps.
  template <typename Visit>
  void visit_box(const Vec3& lo, const Vec3& hi, Visit&& visit) const {
    for (const Level& l : levels_) {
      const double m = l.h / 2;
      std::array<int, 3> a{}, b{};
      bool outside = false;
      for (int k = 0; k < 3; ++k) {
        const double x0 = lo[k] - lo_[k] - m, x1 = hi[k] - lo_[k] + m;
        if (x1 < 0 || x0 > l.n[k] * l.h) outside = true;
        a[k] = l.index(k, x0);
        b[k] = l.index(k, x1);
      }
      if (outside) continue;
      for (int i = a[0]; i <= b[0]; ++i)
        for (int j = a[1]; j <= b[1]; ++j)
          for (int k = a[2]; k <= b[2]; ++k)
            for (const std::uint32_t id : l.cells[l.cell(i, j, k)]) visit(id);
    }
  }

 private:
  static constexpr std::uint32_t kNone = ~std::uint32_t(0);

  struct Level {
    double h = 1;
    std::array<int, 3> n{1, 1, 1};
    std::vector<std::vector<std::uint32_t>> cells;
    /// The cell index along `axis` of the offset x from the grid's corner, clamped.
    int index(int axis, double x) const {
      return int(std::clamp(std::floor(x / h), 0.0, double(n[axis] - 1)));
    }
    std::size_t cell(int i, int j, int k) const {
      return (std::size_t(i) * std::size_t(n[1]) + std::size_t(j)) * std::size_t(n[2]) +
             std::size_t(k);
    }
  };
  struct Where {
    std::uint32_t level, cell;
  };

  Vec3 lo_ = Vec3::Zero();
  std::vector<Level> levels_;
  std::vector<Where> where_;  // by block id

  void erase(std::size_t id) {
    if (id >= where_.size() || where_[id].level == kNone) return;
    auto& v = levels_[where_[id].level].cells[where_[id].cell];
    const auto it = std::find(v.begin(), v.end(), std::uint32_t(id));
    if (it != v.end()) {
      *it = v.back();
      v.pop_back();
    }
    where_[id].level = kNone;
  }
};

}  // namespace slice

#include "slice/orientation_stats.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "slice/error.hpp"
#include "slice/orientation.hpp"

namespace slice {

double fisher_alpha95_deg(std::size_t n, double r) {
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  const double N = static_cast<double>(n);
  const double spread = N - r;
  if (!(spread > kParallelPoles * N)) return 0;
  const double c = 1 - spread / r * (std::pow(20.0, 1 / (N - 1)) - 1);
  if (!(c >= -1 && c <= 1)) return 180;
  return std::acos(c) * 180 / std::numbers::pi;
}

OrientationStats orientation_stats(std::span<const Vec3> normals) {
  OrientationStats s;
  s.count = normals.size();
  if (normals.empty()) {
    s.mean_dip_deg = s.mean_dip_direction_deg = s.fisher_kappa = s.alpha95_deg =
        std::numeric_limits<double>::quiet_NaN();
    return s;
  }
  std::vector<Vec3> unit;
  unit.reserve(normals.size());
  Eigen::Matrix3d t = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double len = normals[i].norm();
    if (!normals[i].allFinite() || !(len > 0))
      throw Error("orientation statistics",
                  "pole " + std::to_string(i) + " is not a direction (not finite, or no length)",
                  "give each plane's normal as a finite vector of length > 0");
    unit.push_back(normals[i] / len);
    t += unit.back() * unit.back().transpose();
  }
  const double N = static_cast<double>(normals.size());
  // The orientation tensor's principal axis: the eigenvector of its largest eigenvalue
  // (Eigen's are ascending). Its sign is arbitrary; only the side it picks matters.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(t / N);
  const Vec3 axis = eig.eigenvectors().col(2);
  for (int k = 0; k < 3; ++k) s.eigenvalues[std::size_t(k)] = eig.eigenvalues()(2 - k);
  // Fold each pole to the axis' side, then the Fisher mean of the folded poles. A pole at right
  // angles to the axis (n . axis = 0 exactly) is not part of any cluster; it keeps its sign.
  Vec3 r = Vec3::Zero();
  for (const Vec3& u : unit) r += u.dot(axis) < 0 ? Vec3(-u) : u;
  s.resultant = std::min(r.norm(), N);
  const Vec3 mean = s.resultant > 0 ? Vec3(r / r.norm()) : axis;
  s.mean_normal = mean.z() < 0 ? Vec3(-mean) : mean;
  const DipAndDirection dd = dip_from_normal(s.mean_normal);
  s.mean_dip_deg = dd.dip_deg;
  s.mean_dip_direction_deg = dd.dip_direction_deg;
  if (normals.size() < 2) {
    s.fisher_kappa = s.alpha95_deg = std::numeric_limits<double>::quiet_NaN();
    return s;
  }
  const double spread = N - s.resultant;
  s.fisher_kappa =
      spread > kParallelPoles * N ? (N - 1) / spread : std::numeric_limits<double>::infinity();
  s.alpha95_deg = fisher_alpha95_deg(normals.size(), s.resultant);
  return s;
}

}  // namespace slice

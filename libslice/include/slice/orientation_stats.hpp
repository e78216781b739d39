#pragma once
// libslice/src/scene/orientation_stats.cpp: the statistics of a set of plane orientations
// (docs/dfn-statistics.md): the mean orientation, Fisher's concentration kappa and the 95 %
// confidence cone about the mean (Fisher 1953, "Dispersion on a sphere", Proc. R. Soc. A
// 217:295-305; Priest 1993, "Discontinuity analysis for rock engineering", section 3).
//
// A plane's pole is an axis: n and -n are the same plane. Summing upward normals (z >= 0) is
// wrong for steep sets, whose poles straddle the horizontal: a joint of dip 88 towards 020 and
// one of dip 88 towards 200 are 4 degrees apart, but their upward normals are 176 degrees apart.
// So the poles are folded into one hemisphere first, that of the principal axis of the
// orientation tensor T = sum n n^T (its eigenvector of the largest eigenvalue, which does not
// depend on the sign of any n): each pole is taken with the sign that puts it on the axis'
// side, and the Fisher mean is the direction of their resultant R.
#include <array>
#include <cstddef>
#include <span>

#include "slice/geometry.hpp"

namespace slice {

struct OrientationStats {
  std::size_t count = 0;              // poles
  Vec3 mean_normal = Vec3::UnitZ();   // upward unit normal of the mean plane
  double mean_dip_deg = 0;            // [0, 90]
  double mean_dip_direction_deg = 0;  // [0, 360); 0 for a horizontal mean
  double resultant = 0;               // |R|, R the sum of the folded unit poles (<= count)
  // Fisher's estimate (N - 1) / (N - |R|): +infinity when every pole is the same (within
  // kParallelPoles), NaN for fewer than 2 poles.
  double fisher_kappa = 0;
  // The semi-angle of the 95 % confidence cone about the mean (Fisher 1953):
  // cos a95 = 1 - (N - |R|) / |R| (20^(1/(N-1)) - 1); 0 when kappa is infinite, NaN for fewer
  // than 2 poles, 180 where the formula leaves [-1, 1] (too few, too scattered poles).
  double alpha95_deg = 0;
  // Eigenvalues of T / N, largest first (they add up to 1): (1, 0, 0) for parallel poles,
  // (1/3, 1/3, 1/3) for uniform ones; a girdle has two large ones.
  std::array<double, 3> eigenvalues{};
};

/// N - |R| at most this times N counts as every pole parallel (kappa infinite): the rounding of
/// the sum of N unit vectors.
inline constexpr double kParallelPoles = 1e-12;

/// The statistics of the poles `normals` (any length > 0, either sense). Throws Error naming the
/// normal's index for one that is not finite or has no length. count 0 (and NaN angles) for none.
OrientationStats orientation_stats(std::span<const Vec3> normals);

/// The Fisher 95 % confidence cone's semi-angle (degrees) of n unit poles with resultant
/// length r (see OrientationStats::alpha95_deg).
double fisher_alpha95_deg(std::size_t n, double r);

}  // namespace slice

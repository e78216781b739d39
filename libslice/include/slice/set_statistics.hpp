#pragma once
// libslice/src/scene/set_statistics.cpp: what a joint set of a joint system is, measured from
// its joints (docs/dfn-statistics.md): the mean orientation and Fisher kappa
// (orientation_stats.hpp), the size distribution fitted, the intensity, and the [[sets]] entry
// of a stochastic set that draws joints like them (docs/scenes.md, "[[sets]]").
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "slice/orientation_stats.hpp"
#include "slice/scene.hpp"

namespace slice {

/// One distribution fitted to sizes, by maximum likelihood: lognormal (the mean and sd of the
/// logs), exponential (the mean), power law (the exponent, on [min, max] = the smallest and
/// largest size), or fixed (every size the same, within kSameSize).
struct SizeFit {
  SizeSpec size;  // as a [[sets]] `size` takes it (mean and sd of the size itself)
  // Kolmogorov-Smirnov statistic: the largest gap between the sizes' empirical distribution
  // function and the fitted one (0 for fixed).
  double ks = 0;
};
struct SizeFits {
  std::size_t count = 0;
  std::vector<SizeFit> fits;  // fixed alone, or lognormal, exponential, power-law in this order
  std::size_t best = 0;       // the fit with the smallest ks (the first on a tie)
  // 1.358 / sqrt(count): a fully specified distribution is refused at the 5 % level above it.
  // The parameters here are fitted to the same sizes, so a fit well below this is good, and the
  // test is only indicative (Lilliefors).
  double ks_critical_95 = 0;
};
/// Sizes that differ by at most this times the largest are one size (a fixed distribution).
inline constexpr double kSameSize = 1e-9;

/// Fits the three distributions to `sizes` (> 0, finite; Error naming the index otherwise).
/// One size, or all the same: `fixed`. None: no fits.
SizeFits fit_sizes(std::span<const double> sizes);

/// What a set's joints measure.
struct SetStatistics {
  std::size_t set = 0;  // index into JointSystem::sets
  std::size_t joints = 0;
  OrientationStats orientation;  // of every joint of the set
  // Finite joints: their shape as a [[sets]] entry draws it (the most common corner count:
  // 4 corners a square, or a rectangle of the median aspect if that is above 1.01; any other
  // count a regular polygon of that many sides, or an ellipse of that many corners and the
  // median aspect of their second moments of area if that is above 1.01), and the size of
  // each (docs/scenes.md `size`) of that shape with the joint's area.
  std::size_t finite = 0;
  JointShape shape = JointShape::square;
  std::int64_t sides = 4;
  double aspect = 1;
  // The sizes fitted: those of the finite joints whose centre lies in the domain (an unbiased
  // sample: joints centred outside are kept only if they reach in, which favours large ones);
  // all finite joints when none is centred inside.
  SizeFits sizes;
  bool sizes_centred_inside = true;
  // Intensity, as joints.h5 records it (JointSetSpec): area inside the domain per volume, and
  // joints crossing the set's scanline per length (that of the scene, or the domain's chord
  // along the set's mean normal through the mean of its vertices).
  double p32 = 0, p10 = 0;
  Vec3 scanline_from = Vec3::Zero(), scanline_to = Vec3::Zero();
};

/// The statistics of set `set` of `js` (3-D or 2-D; a 2-D set has no sizes).
SetStatistics set_statistics(const JointSystem& js, std::size_t set);

/// The size of a finite joint of area `area` as a set of this shape defines it: the side of a
/// square, the long side of a rectangle of `aspect`, the diameter of the circle through the
/// corners of a regular polygon of `sides`, the long diameter of an ellipse of `aspect` (whose
/// area the joint's is: an ellipse set with fit = "equal-area" draws it back).
double equivalent_size(double area, JointShape shape, std::int64_t sides, double aspect);

/// A [[sets]] entry (TOML, several lines, ending in a newline) of a stochastic set that draws
/// joints like the set's: its name, the mean dip and dip direction, fisher_kappa (left out when
/// every joint has one orientation), its p32 and the best size fit, its shape; a set without
/// finite joints: persistent planes with its p10 on its scanline. Its kind, friction angle,
/// cohesion and tension are the set's. Empty for a set with no joints, a boundary set or a 2-D
/// system (which have no such entry).
std::string sets_entry(const JointSystem& js, const SetStatistics& s);

}  // namespace slice

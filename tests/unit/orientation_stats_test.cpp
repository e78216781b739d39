// Orientation statistics (orientation_stats.hpp) and size fits (set_statistics.hpp) on sets drawn
// here, with fixed seeds and a sampler of the test's own (not the library's): Fisher poles about a
// known mean at every dip from 0 to 90 and every dip direction, and sizes from known
// distributions.
#include "slice/orientation_stats.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "slice/orientation.hpp"
#include "slice/set_statistics.hpp"
#include "support/support.hpp"

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;

namespace {

// Uniform in (0, 1) from a std::mt19937_64 (its sequence is fixed by the standard; the
// standard's distributions are not, so none is used).
struct Uniform {
  std::mt19937_64 g;
  explicit Uniform(std::uint64_t seed) : g(seed) {}
  double operator()() { return (static_cast<double>(g() >> 11) + 0.5) * 0x1p-53; }
};

// n poles from the Fisher distribution of concentration kappa about the upward normal of
// (dip, dip direction), each returned with a random sign (a pole is an axis).
std::vector<Vec3> fisher_poles(double dip, double ddir, double kappa, std::size_t n,
                               std::uint64_t seed) {
  Uniform u(seed);
  const slice::JointFrame f = slice::plane_frame(dip, ddir);
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < n; ++i) {
    // cos theta by the inverse of its distribution function, exact for large kappa.
    const double c = 1 + std::log1p(u() * std::expm1(-2 * kappa)) / kappa;
    const double s = std::sqrt(std::max(0.0, 1 - c * c));
    const double phi = 2 * std::numbers::pi * u();
    Vec3 p = c * f.n + s * (std::cos(phi) * f.u + std::sin(phi) * f.v);
    if (u() < 0.5) p = -p;
    out.push_back(p);
  }
  return out;
}

double axis_angle_deg(const Vec3& a, const Vec3& b) {
  const double c = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return std::acos(c) * 180 / std::numbers::pi;
}

// The angle from the true mean that the mean of n poles of concentration kappa exceeds with
// probability 1e-6: the mean is (for kappa N >> 1) Fisher-distributed with concentration about
// kappa N, so P(angle > t) = exp(-kappa N (1 - cos t)).
double mean_tolerance_deg(double kappa, std::size_t n) {
  const double one_minus_cos = std::log(1e6) / (kappa * static_cast<double>(n));
  return std::acos(std::max(-1.0, 1 - one_minus_cos)) * 180 / std::numbers::pi;
}

// The factors kappa's estimate (N - 1) / (N - R) stays within with probability 1 - 2e-6: it is
// kappa 2(N - 1) / chi2(2N - 2) (Fisher 1953, for kappa >> 1); the chi-square quantiles at 1e-6
// by Wilson and Hilferty's approximation. N = 30: 0.47 to 2.9; N = 300: 0.77 to 1.34.
std::pair<double, double> kappa_factors(std::size_t n) {
  const double df = 2 * (static_cast<double>(n) - 1), z = 4.753;  // z: the 1e-6 normal quantile
  const auto q = [&](double zz) {
    const double c = 1 - 2 / (9 * df) + zz * std::sqrt(2 / (9 * df));
    return c * c * c;  // chi2 / df
  };
  return {1 / q(z), 1 / q(-z)};
}

}  // namespace

TEST_CASE("orientation statistics recover Fisher sets at every dip and dip direction",
          "[orientation_stats]") {
  std::vector<double> dips = {0, 0.5, 2};
  for (double d = 5; d <= 85; d += 5) dips.push_back(d);
  for (const double d : {87.0, 88.0, 89.0, 89.5, 89.9, 90.0}) dips.push_back(d);
  struct Draw {
    double kappa;
    std::size_t n;
  };
  const std::vector<Draw> draws = {{10, 40}, {30, 100}, {100, 300}, {400, 30}};
  std::size_t cases = 0, covered = 0, failures = 0;
  double worst_ratio = 1;
  std::uint64_t seed = 1;
  for (const double dip : dips)
    for (double ddir = 0; ddir < 360; ddir += 15)
      for (const Draw& dr : draws) {
        ++seed;
        const auto poles = fisher_poles(dip, ddir, dr.kappa, dr.n, seed);
        const slice::OrientationStats s = slice::orientation_stats(poles);
        const Vec3 truth = slice::normal_from_dip(dip, ddir);
        const double off = axis_angle_deg(s.mean_normal, truth);
        const double tol = mean_tolerance_deg(dr.kappa, dr.n);
        const double ratio = s.fisher_kappa / dr.kappa;
        const auto [lo, hi] = kappa_factors(dr.n);
        worst_ratio = std::max({worst_ratio, ratio, 1 / ratio});
        ++cases;
        covered += off <= s.alpha95_deg ? 1 : 0;
        // The reported angles are those of the reported normal, upward.
        const bool consistent =
            s.mean_normal.z() >= 0 &&
            (slice::normal_from_dip(s.mean_dip_deg, s.mean_dip_direction_deg) - s.mean_normal)
                    .norm() < 1e-9 &&
            s.mean_dip_deg >= 0 && s.mean_dip_deg <= 90 && s.mean_dip_direction_deg >= 0 &&
            s.mean_dip_direction_deg < 360;
        if (off > tol || ratio > hi || ratio < lo || !consistent || s.count != dr.n) {
          ++failures;
          FAIL_CHECK("dip " << dip << " ddir " << ddir << " kappa " << dr.kappa << " n " << dr.n
                            << " seed " << seed << ": mean " << s.mean_dip_deg << "/"
                            << s.mean_dip_direction_deg << " off " << off << " deg (tolerance "
                            << tol << "), kappa " << s.fisher_kappa);
        }
      }
  CAPTURE(cases, covered, worst_ratio);
  CHECK(failures == 0);
  CHECK(cases == dips.size() * 24 * draws.size());
  // The 95 % cone holds the true mean in about 95 % of the cases (binomial sd 0.6 % here).
  const double coverage = static_cast<double>(covered) / static_cast<double>(cases);
  CHECK(coverage > 0.93);
  CHECK(coverage < 0.97);
}

TEST_CASE("a vertical set's poles straddle the horizontal: folding, not upward normals",
          "[orientation_stats]") {
  // Poles of a vertical set striking N-S (dip direction 090): half of the upward normals point
  // east, half west. Their plain sum is a wrong mean (far from horizontal); folded, the mean
  // is vertical.
  const auto poles = fisher_poles(90, 90, 50, 400, 7);
  Vec3 upward = Vec3::Zero();
  for (const Vec3& p : poles) upward += p.z() < 0 ? Vec3(-p) : p;
  CHECK(slice::dip_from_normal(upward).dip_deg < 85);  // the old, wrong mean
  const slice::OrientationStats s = slice::orientation_stats(poles);
  CHECK_THAT(s.mean_dip_deg, WithinAbs(90, 0.5));
  CHECK(axis_angle_deg(s.mean_normal, Vec3::UnitX()) < 0.5);
  CHECK_THAT(s.fisher_kappa, WithinRel(50, 0.2));
}

TEST_CASE("a hillside's two steep sets keep their own means", "[orientation_stats]") {
  // The road cut of issue 43: J1 77.1/020 and J2 69.3/140 of a FracMan DFN; summed upward
  // normals had made them 67.5/018 and 67.3/140.
  struct Set {
    double dip, ddir, kappa;
    std::uint64_t seed;
  };
  for (const Set& set : {Set{77.1, 20, 25, 11}, Set{69.3, 140, 15, 12}, Set{86, 200, 40, 13}}) {
    CAPTURE(set.dip, set.ddir);
    const auto poles = fisher_poles(set.dip, set.ddir, set.kappa, 500, set.seed);
    const slice::OrientationStats s = slice::orientation_stats(poles);
    CAPTURE(s.mean_dip_deg, s.mean_dip_direction_deg, s.fisher_kappa, s.alpha95_deg);
    CHECK(axis_angle_deg(s.mean_normal, slice::normal_from_dip(set.dip, set.ddir)) <
          mean_tolerance_deg(set.kappa, 500));
    CHECK_THAT(s.mean_dip_deg, WithinAbs(set.dip, 1.5));
    const auto [lo, hi] = kappa_factors(500);  // 0.81 to 1.25
    CHECK(s.fisher_kappa > set.kappa * lo);
    CHECK(s.fisher_kappa < set.kappa * hi);
    CHECK(s.alpha95_deg > 0);
    CHECK(s.alpha95_deg < 2);  // about 140 / sqrt(kappa N) degrees
  }
}

TEST_CASE("orientation statistics of degenerate sets", "[orientation_stats]") {
  SECTION("none") {
    const slice::OrientationStats s = slice::orientation_stats(std::vector<Vec3>{});
    CHECK(s.count == 0);
    CHECK(std::isnan(s.mean_dip_deg));
    CHECK(std::isnan(s.fisher_kappa));
  }
  SECTION("one pole: its orientation, no kappa") {
    const slice::OrientationStats s =
        slice::orientation_stats(std::vector<Vec3>{-slice::normal_from_dip(60, 300)});
    CHECK_THAT(s.mean_dip_deg, WithinAbs(60, 1e-9));
    CHECK_THAT(s.mean_dip_direction_deg, WithinAbs(300, 1e-9));
    CHECK(std::isnan(s.fisher_kappa));
    CHECK(std::isnan(s.alpha95_deg));
  }
  SECTION("one orientation, given in both senses: kappa infinite, no cone") {
    const Vec3 n = slice::normal_from_dip(90, 45);
    const slice::OrientationStats s = slice::orientation_stats(std::vector<Vec3>{n, -n, 3 * n});
    CHECK(std::isinf(s.fisher_kappa));
    CHECK(s.alpha95_deg == 0);
    CHECK_THAT(s.mean_dip_deg, WithinAbs(90, 1e-9));
    CHECK_THAT(s.eigenvalues[0], WithinAbs(1, 1e-12));
  }
  SECTION("a pole that is not a direction is refused") {
    const std::string e = test::error_of([] {
      slice::orientation_stats(std::vector<Vec3>{Vec3::UnitZ(), Vec3::Zero()});
    });
    CHECK(e.find("pole 1") != std::string::npos);
    CHECK(test::error_of([] {
            slice::orientation_stats(std::vector<Vec3>{Vec3(NAN, 0, 1)});
          }).find("pole 0") != std::string::npos);
  }
  SECTION("Fisher's cone: the formula against a hand-computed value") {
    // N = 10, R = 9.5: cos a95 = 1 - 0.5 / 9.5 (20^(1/9) - 1) = 0.979213..., a95 = 11.7027 deg.
    CHECK_THAT(slice::fisher_alpha95_deg(10, 9.5), WithinAbs(11.7027, 1e-3));
    CHECK(slice::fisher_alpha95_deg(2, 0.1) == 180);  // too few, too scattered
  }
}

namespace {
std::vector<double> lognormal_sizes(double zeta, double sigma, std::size_t n, std::uint64_t seed) {
  Uniform u(seed);
  std::vector<double> x;
  for (std::size_t i = 0; i < n; ++i) {  // Box-Muller
    const double z = std::sqrt(-2 * std::log(u())) * std::cos(2 * std::numbers::pi * u());
    x.push_back(std::exp(zeta + sigma * z));
  }
  return x;
}
}  // namespace

TEST_CASE("size fits pick the distribution the sizes were drawn from", "[set_statistics]") {
  const std::size_t n = 2000;
  SECTION("lognormal") {
    // mean 5, sd 2: sigma^2 = ln(1 + 4/25), zeta = ln 5 - sigma^2 / 2.
    const double s2 = std::log(1 + 4.0 / 25), zeta = std::log(5.0) - s2 / 2;
    const slice::SizeFits f = slice::fit_sizes(lognormal_sizes(zeta, std::sqrt(s2), n, 21));
    REQUIRE(f.fits.size() == 3);
    CHECK(f.fits[f.best].size.distribution == slice::SizeDistribution::lognormal);
    CHECK_THAT(f.fits[0].size.mean, WithinRel(5, 0.03));
    CHECK_THAT(f.fits[0].size.sd, WithinRel(2, 0.06));
    CHECK(f.fits[0].ks < f.ks_critical_95);
  }
  SECTION("exponential") {
    Uniform u(22);
    std::vector<double> x;
    for (std::size_t i = 0; i < n; ++i) x.push_back(-3 * std::log(u()));
    const slice::SizeFits f = slice::fit_sizes(x);
    CHECK(f.fits[f.best].size.distribution == slice::SizeDistribution::exponential);
    CHECK_THAT(f.fits[1].size.mean, WithinRel(3, 0.05));
    CHECK(f.fits[1].ks < f.ks_critical_95);
  }
  SECTION("power law") {
    // density ~ x^-2.5 on [0.5, 50] by the inverse of its distribution function.
    Uniform u(23);
    const double a = 2.5, b = 1 - a, lo = 0.5, hi = 50;
    std::vector<double> x;
    for (std::size_t i = 0; i < n; ++i)
      x.push_back(std::pow(std::pow(lo, b) + u() * (std::pow(hi, b) - std::pow(lo, b)), 1 / b));
    const slice::SizeFits f = slice::fit_sizes(x);
    CHECK(f.fits[f.best].size.distribution == slice::SizeDistribution::power_law);
    CHECK_THAT(f.fits[2].size.exponent, WithinAbs(2.5, 0.1));
    CHECK(f.fits[2].size.min >= lo);
    CHECK(f.fits[2].size.max <= hi);
    CHECK(f.fits[2].ks < f.ks_critical_95);
  }
  SECTION("one size") {
    const std::vector<double> x(10, 2.5);
    const slice::SizeFits f = slice::fit_sizes(x);
    REQUIRE(f.fits.size() == 1);
    CHECK(f.fits[0].size.distribution == slice::SizeDistribution::fixed);
    CHECK(f.fits[0].size.value == 2.5);
  }
  SECTION("a size that is not > 0 is refused") {
    CHECK(test::error_of([] {
            slice::fit_sizes(std::vector<double>{1, 2, -1});
          }).find("size 2") != std::string::npos);
  }
}

TEST_CASE("equivalent sizes of the scene's shapes", "[set_statistics]") {
  CHECK_THAT(slice::equivalent_size(4, slice::JointShape::square, 4, 1), WithinRel(2, 1e-12));
  CHECK_THAT(slice::equivalent_size(8, slice::JointShape::rectangle, 4, 2), WithinRel(4, 1e-12));
  // A regular hexagon of diameter 2 (circumradius 1) has area 3 sqrt(3) / 2.
  CHECK_THAT(slice::equivalent_size(1.5 * std::sqrt(3.0), slice::JointShape::polygon, 6, 1),
             WithinRel(2, 1e-12));
}

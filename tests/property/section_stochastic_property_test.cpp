// Stochastic 3-D sets in a section (docs/2d.md, "Stochastic sets in a section"), on random
// scenes with fixed seeds: the traces' P21 in the section matches P32 x E[sin theta] within
// sampling error (theta the angle between a joint's normal and the section's; E over the
// Fisher distribution of the poles, integrated here), and the joints are reproducible exactly.
// A p10 set (joints per unit length along its mean pole) is the p32 set of p32 = p10 / E|cos|,
// and a line along the mean pole of a 3-D set crosses P32 E|cos| joints per unit length; a count
// set is the first `count` traces of the same stream.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "slice/stochastic.hpp"

using slice::Vec3;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kW = 40, kH = 30;  // the section's domain, [0, kW] x [0, kH]

std::string num(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

// E[sin theta] for poles drawn from the Fisher distribution (kappa; 0: all at the mean) about
// the pole of (dip, dip direction), theta the angle to the horizontal unit normal `normal`:
// the cosine w to the mean by its inverse CDF on a midpoint grid of probabilities, the
// azimuth on a uniform grid.
double mean_sin(double dip, double dip_direction, double kappa, const Vec3& normal) {
  const slice::JointFrame f = slice::plane_frame(dip, dip_direction);
  const auto sin_of = [&](const Vec3& n) {
    const double c = n.dot(normal);
    return std::sqrt(std::max(0.0, 1 - c * c));
  };
  if (kappa == 0) return sin_of(f.n);
  const int nu = 2000, nphi = 360;
  double sum = 0;
  for (int i = 0; i < nu; ++i) {
    const double u = (i + 0.5) / nu;
    const double w = 1 + std::log1p(-u * (1 - std::exp(-2 * kappa))) / kappa;
    const double s = std::sqrt(std::max(0.0, 1 - w * w));
    for (int k = 0; k < nphi; ++k) {
      const double phi = 2 * kPi * (k + 0.5) / nphi;
      sum += sin_of(w * f.n + s * (std::cos(phi) * f.u + std::sin(phi) * f.v));
    }
  }
  return sum / (double(nu) * nphi);
}

// The length of a 2-D joint's segment inside the domain rectangle: its ends are the corners of
// its rectangle at y = +0.5 (joint_polygon), clipped by Liang and Barsky's method.
double length_in_domain(const slice::Joint& j) {
  std::vector<Vec3> ends;
  for (const Vec3& x : slice::joint_polygon(j))
    if (x.y() > 0) ends.push_back(x);
  REQUIRE(ends.size() == 2);
  const Vec3 a = ends[0], d = ends[1] - ends[0];
  double t0 = 0, t1 = 1;
  for (const auto& [p, q] : {std::pair{-d.x(), a.x()}, std::pair{d.x(), kW - a.x()},
                             std::pair{-d.z(), a.z()}, std::pair{d.z(), kH - a.z()}}) {
    if (p == 0) {
      if (q < 0) return 0;
    } else if (p < 0) {
      t0 = std::max(t0, q / p);
    } else {
      t1 = std::min(t1, q / p);
    }
  }
  return t1 > t0 ? (t1 - t0) * d.norm() : 0;
}

// E|cos theta| between a Fisher pole (kappa) and the mean pole, on the same grid as mean_sin:
// the mean |w| of the inverse CDF at the midpoints of nu probabilities. 1 for kappa = 0.
double mean_abs_cos(double kappa) {
  if (kappa == 0) return 1;
  const int nu = 200000;
  double sum = 0;
  for (int i = 0; i < nu; ++i) {
    const double u = (i + 0.5) / nu;
    sum += std::abs(1 + std::log1p(-u * (1 - std::exp(-2 * kappa))) / kappa);
  }
  return sum / nu;
}

// A random section case: a mean plane at least 20 degrees off the section (sin theta of the
// mean plane >= 0.34), a strike, and every 2nd case rectangles, every 3rd lognormal sizes;
// kappa 0, 0, 15, 40 in turn.
struct Case {
  double dip = 0, dd = 0, strike = 0, kappa = 0;
  Vec3 normal;
  std::string size;  // the size, shape and fisher_kappa lines of the set

  Case(int c, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> uni(0, 1);
    do {
      dip = 10 + 80 * uni(rng);
      dd = 360 * uni(rng);
      strike = std::floor(360 * uni(rng));
      normal = Vec3(-std::cos(strike * kPi / 180), std::sin(strike * kPi / 180), 0);
    } while (mean_sin(dip, dd, 0, normal) < 0.34);
    kappa = std::array<double, 4>{0, 0, 15, 40}[std::size_t(c % 4)];
    size = c % 3 == 1
               ? "size = { distribution = \"lognormal\", mean = 4, sd = 1.5 }\n"
               : "size = { distribution = \"fixed\", value = " + num(3 + 3 * uni(rng)) + " }\n";
    if (c % 2 == 1) size += "shape = \"rectangle\"\naspect = 2\n";
    if (kappa > 0) size += "fisher_kappa = " + num(kappa) + "\n";
  }

  // The scene of seed `seed` whose one set has this intensity line (e.g. "p32 = 0.5").
  std::string scene(int seed, const std::string& intensity) const {
    return "[scene]\nname = \"case\"\ndimension = 2\nseed = " + std::to_string(seed) +
           "\n[domain]\nbox = { min = [0, 0], max = [40, 30] }\n[section]\npoint = "
           "[3, -7, 0]\nstrike = " +
           num(strike) + "\n[[sets]]\nname = \"s\"\ndip = " + num(dip) +
           "\ndip_direction = " + num(dd) + "\n" + intensity + "\n" + size;
  }
};

// The traces' P21 in the 40 x 30 section and its standard error (sum of squared lengths).
struct P21 {
  double p21 = 0, se = 0;
  std::size_t n = 0;
};
P21 p21_of(const slice::JointSystem& js) {
  double sum = 0, sum2 = 0;
  std::size_t n = 0;
  for (const slice::Joint& j : js.joints) {
    REQUIRE(j.set == 0);
    REQUIRE(std::abs(j.plane.normal.y()) < 1e-15);
    const double l = length_in_domain(j);
    CHECK(l > 0);  // each trace reaches into the domain
    sum += l;
    sum2 += l * l;
    ++n;
  }
  return {sum / (kW * kH), std::sqrt(sum2) / (kW * kH), n};
}

// The first `n` joints of a and b are the same, bit for bit.
void same_joints(const slice::JointSystem& a, const slice::JointSystem& b, std::size_t n) {
  REQUIRE(a.joints.size() >= n);
  REQUIRE(b.joints.size() >= n);
  for (std::size_t i = 0; i < n; ++i) {
    CHECK(a.joints[i].centre == b.joints[i].centre);
    CHECK(a.joints[i].plane.normal == b.joints[i].plane.normal);
    CHECK(a.joints[i].plane.d == b.joints[i].plane.d);
    CHECK(a.joints[i].polygon_uv == b.joints[i].polygon_uv);
  }
}

slice::JointSystem joints_of(const std::string& text) {
  return slice::generate_joints(slice::parse_scene(text, "case.toml"));
}

}  // namespace

TEST_CASE("a stochastic 3-D set's traces in a section have P21 = P32 x mean sin theta",
          "[property][section]") {
  std::mt19937_64 rng(2026);
  const int cases = 24;
  double zsum = 0;
  for (int c = 0; c < cases; ++c) {
    const Case k(c, rng);
    const double p32 = 0.5;
    const std::string text = k.scene(1000 + c, "p32 = " + num(p32));
    CAPTURE(c, text);
    const slice::JointSystem js = joints_of(text);
    REQUIRE(js.dimension == 2);
    const P21 t = p21_of(js);
    const double expected = p32 * mean_sin(k.dip, k.dd, k.kappa, k.normal);
    const double z = (t.p21 - expected) / t.se;
    CAPTURE(t.n, t.p21, expected, t.se, z, js.sets[0].candidates);
    CHECK(t.n > 40);
    CHECK(std::abs(z) < 4);
    // slice-joints' P21 (the set's achieved_p32: joint area per unit thickness) is this one.
    CHECK(std::abs(js.sets[0].achieved_p32 - t.p21) < 1e-9 * t.p21);
    zsum += z;
    // The same scene gives the same joints, bit for bit.
    const slice::JointSystem again = joints_of(text);
    REQUIRE(again.joints.size() == js.joints.size());
    same_joints(again, js, js.joints.size());
  }
  // Over all cases the deviations average out: no bias beyond sampling error.
  CHECK(std::abs(zsum / cases) < 3 / std::sqrt(double(cases)));
}

TEST_CASE("E|cos| of the Fisher poles: the closed form is the mean of the draws' inverse CDF",
          "[property][section]") {
  // fisher_mean_abs_cos (1 - tanh(kappa / 2) / kappa), which converts a section's p10 to P32,
  // against the mean |cos| over the inverse CDF the generator draws the poles with.
  for (const double kappa : {0.0, 0.01, 0.5, 1.0, 2.0, 5.0, 15.0, 40.0, 200.0, 1000.0}) {
    CAPTURE(kappa);
    CHECK(std::abs(slice::fisher_mean_abs_cos(kappa) - mean_abs_cos(kappa)) < 1e-6);
  }
  CHECK(slice::fisher_mean_abs_cos(0) == 1);  // no scatter: every pole at the mean
}

TEST_CASE("in 3-D a line along a set's mean pole crosses P32 E|cos| joints per unit length",
          "[property][section]") {
  // The relation a section's p10 rests on, with the 3-D generator: a p32 set's achieved_p10,
  // measured on the domain's chord along the mean pole (the default scanline), is
  // P32 E|cos theta| within sampling error (Poisson: the standard error of n crossings is
  // sqrt(n)); kappa 0, 5, 15, 40 in turn.
  std::mt19937_64 rng(2027);
  std::uniform_real_distribution<double> uni(0, 1);
  const int cases = 24;
  double zsum = 0;
  for (int c = 0; c < cases; ++c) {
    const double dip = 80 * uni(rng), dd = 360 * uni(rng);
    const double kappa = std::array<double, 4>{0, 5, 15, 40}[std::size_t(c % 4)];
    const double p32 = 1.5;
    std::string text = "[scene]\nname = \"p10\"\nseed = " + std::to_string(3000 + c) +
                       "\n[domain]\nbox = { min = [0, 0, 0], max = [30, 30, 30] }\n[[sets]]\n"
                       "name = \"s\"\ndip = " +
                       num(dip) + "\ndip_direction = " + num(dd) + "\np32 = " + num(p32) +
                       "\nsize = { distribution = \"fixed\", value = 4 }\n";
    if (kappa > 0) text += "fisher_kappa = " + num(kappa) + "\n";
    CAPTURE(c, text);
    const slice::JointSystem js = joints_of(text);
    const slice::JointSetSpec& s = js.sets.at(0);
    const double length = (s.scanline_to - s.scanline_from).norm();
    const double hits = s.achieved_p10 * length;
    const double expected = p32 * mean_abs_cos(kappa) * length;
    const double z = (hits - expected) / std::sqrt(expected);
    CAPTURE(length, hits, expected, z);
    CHECK(hits > 20);
    CHECK(std::abs(z) < 4);
    zsum += z;
  }
  CHECK(std::abs(zsum / cases) < 3 / std::sqrt(double(cases)));
}

TEST_CASE("a p10 set in a section is the p32 set of p32 = p10 / E|cos|: its P21 follows",
          "[property][section]") {
  std::mt19937_64 rng(2028);
  std::uniform_real_distribution<double> uni(0, 1);
  const int cases = 24;
  double zsum = 0;
  for (int c = 0; c < cases; ++c) {
    const Case k(c, rng);
    const double p10 = 0.3 + 0.4 * uni(rng);
    const std::string text = k.scene(2000 + c, "p10 = " + num(p10));
    CAPTURE(c, text);
    const slice::JointSystem js = joints_of(text);
    const double p32 = p10 / mean_abs_cos(k.kappa);
    // The P32 drawn is stored as the set's p32 (slice-joints prints it).
    CHECK(std::abs(js.sets[0].p32 - p32) < 1e-6 * p32);
    CHECK(js.sets[0].intensity == slice::SetIntensity::p10);
    const P21 t = p21_of(js);
    const double expected = p32 * mean_sin(k.dip, k.dd, k.kappa, k.normal);
    const double z = (t.p21 - expected) / t.se;
    CAPTURE(t.n, t.p21, expected, t.se, z);
    CHECK(t.n > 20);
    CHECK(std::abs(z) < 4);
    zsum += z;
    // The same joints as the p32 set of that P32, bit for bit.
    const slice::JointSystem same = joints_of(k.scene(2000 + c, "p32 = " + num(js.sets[0].p32)));
    REQUIRE(same.joints.size() == js.joints.size());
    same_joints(same, js, js.joints.size());
  }
  CHECK(std::abs(zsum / cases) < 3 / std::sqrt(double(cases)));
}

TEST_CASE("a count set in a section has exactly count traces: the first of the same stream",
          "[property][section]") {
  // A count set draws the stream a p32 set of the same seed draws, and keeps the joints with a
  // trace in the domain until it has `count`: the p32 set's first `count` traces.
  std::mt19937_64 rng(2029);
  std::uniform_real_distribution<double> uni(0, 1);
  const int cases = 24;
  for (int c = 0; c < cases; ++c) {
    const Case k(c, rng);
    const auto count = static_cast<std::size_t>(5 + std::floor(60 * uni(rng)));
    const std::string text = k.scene(4000 + c, "count = " + std::to_string(count));
    CAPTURE(c, count, text);
    const slice::JointSystem js = joints_of(text);
    const P21 t = p21_of(js);  // every trace reaches into the domain
    CHECK(t.n == count);
    CHECK(js.sets[0].joint_count == std::int64_t(count));
    const slice::JointSystem p32 = joints_of(k.scene(4000 + c, "p32 = 1"));
    CAPTURE(p32.joints.size());
    same_joints(js, p32, count);
    CHECK(js.sets[0].candidates <= p32.sets[0].candidates);
  }
}

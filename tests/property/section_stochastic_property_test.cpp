// Stochastic 3-D sets in a section (docs/2d.md, "Stochastic sets in a section"), on random
// scenes with fixed seeds: the traces' P21 in the section matches P32 x E[sin theta] within
// sampling error (theta the angle between a joint's normal and the section's; E over the
// Fisher distribution of the poles, integrated here), and the joints are reproducible exactly.
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

}  // namespace

TEST_CASE("a stochastic 3-D set's traces in a section have P21 = P32 x mean sin theta",
          "[property][section]") {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> uni(0, 1);
  const int cases = 24;
  double zsum = 0;
  for (int c = 0; c < cases; ++c) {
    double dip = 0, dd = 0, strike = 0, sin_mean = 0;
    Vec3 normal;
    do {  // a mean plane at least 20 degrees off the section
      dip = 10 + 80 * uni(rng);
      dd = 360 * uni(rng);
      strike = std::floor(360 * uni(rng));
      normal = Vec3(-std::cos(strike * kPi / 180), std::sin(strike * kPi / 180), 0);
      sin_mean = mean_sin(dip, dd, 0, normal);
    } while (sin_mean < 0.34);
    const double kappa = std::array<double, 4>{0, 0, 15, 40}[std::size_t(c % 4)];
    const bool lognormal = c % 3 == 1;
    const bool rectangle = c % 2 == 1;
    const double p32 = 0.5;
    std::string text =
        "[scene]\nname = \"case\"\ndimension = 2\nseed = " + std::to_string(1000 + c) +
        "\n[domain]\nbox = { min = [0, 0], max = [40, 30] }\n[section]\npoint = "
        "[3, -7, 0]\nstrike = " +
        num(strike) + "\n[[sets]]\nname = \"s\"\ndip = " + num(dip) +
        "\ndip_direction = " + num(dd) + "\np32 = " + num(p32) + "\n";
    text += lognormal
                ? "size = { distribution = \"lognormal\", mean = 4, sd = 1.5 }\n"
                : "size = { distribution = \"fixed\", value = " + num(3 + 3 * uni(rng)) + " }\n";
    if (rectangle) text += "shape = \"rectangle\"\naspect = 2\n";
    if (kappa > 0) text += "fisher_kappa = " + num(kappa) + "\n";
    CAPTURE(c, text);
    const slice::Scene scene = slice::parse_scene(text, "case.toml");
    const slice::JointSystem js = slice::generate_joints(scene);
    REQUIRE(js.dimension == 2);
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
    const double area = kW * kH;
    const double p21 = sum / area, se = std::sqrt(sum2) / area;
    const double expected = p32 * mean_sin(dip, dd, kappa, normal);
    const double z = (p21 - expected) / se;
    CAPTURE(n, p21, expected, se, z, js.sets[0].candidates);
    CHECK(n > 40);
    CHECK(std::abs(z) < 4);
    // slice-joints' P21 (the set's achieved_p32: joint area per unit thickness) is this one.
    CHECK(std::abs(js.sets[0].achieved_p32 - p21) < 1e-9 * p21);
    zsum += z;
    // The same scene gives the same joints, bit for bit.
    const slice::JointSystem again = slice::generate_joints(slice::parse_scene(text, "case.toml"));
    REQUIRE(again.joints.size() == js.joints.size());
    for (std::size_t i = 0; i < js.joints.size(); ++i) {
      CHECK(again.joints[i].centre == js.joints[i].centre);
      CHECK(again.joints[i].plane.normal == js.joints[i].plane.normal);
      CHECK(again.joints[i].plane.d == js.joints[i].plane.d);
      CHECK(again.joints[i].polygon_uv == js.joints[i].polygon_uv);
    }
  }
  // Over all cases the deviations average out: no bias beyond sampling error.
  CHECK(std::abs(zsum / cases) < 3 / std::sqrt(double(cases)));
}

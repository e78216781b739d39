// slice/stochastic.hpp and the stochastic [[sets]] of scene files (docs/design.md, "Stochastic
// joints"): shapes by hand, the measures by hand, then the statistics of generated sets against the
// requested distributions (fixed seeds; each statistic is also shown to reject a wrong
// distribution), reproducibility, and bad input.
#include "slice/stochastic.hpp"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "io/h5/h5.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec2;
using slice::Vec3;

namespace {

constexpr double kPi = std::numbers::pi;

slice::JointSetSpec shape_spec(slice::JointShape shape, double aspect = 1, std::int64_t sides = 4,
                               slice::EllipseFit fit = slice::EllipseFit::circumscribed) {
  slice::JointSetSpec s;
  s.size.distribution = slice::SizeDistribution::fixed;
  s.size.value = 1;
  s.shape = shape;
  s.aspect = aspect;
  s.sides = sides;
  s.fit = fit;
  return s;
}

double signed_area(const std::vector<Vec2>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    a += p[i].x() * p[(i + 1) % p.size()].y() - p[i].y() * p[(i + 1) % p.size()].x();
  return 0.5 * a;
}

// Signed distance of q from the line through the edge a-b, positive on the left (inside of a
// counter-clockwise polygon).
double left_of(const Vec2& a, const Vec2& b, const Vec2& q) {
  const Vec2 e = (b - a).normalized(), r = q - a;
  return e.x() * r.y() - e.y() * r.x();
}

slice::DomainBox cube(double side) {
  slice::DomainBox d;
  d.planes = {{Vec3::UnitX(), side}, {-Vec3::UnitX(), 0},   {Vec3::UnitY(), side},
              {-Vec3::UnitY(), 0},   {Vec3::UnitZ(), side}, {-Vec3::UnitZ(), 0}};
  d.min = Vec3::Zero();
  d.max = Vec3::Constant(side);
  d.interior_point = Vec3::Constant(side / 2);
  d.volume = side * side * side;
  d.tol = 1e-9 * side;
  return d;
}

slice::Joint joint(double dip, double dip_direction, const Vec3& centre,
                   std::vector<Vec2> polygon = {}) {
  slice::Joint j;
  j.dip_deg = dip;
  j.dip_direction_deg = dip_direction;
  const Vec3 n = slice::normal_from_dip(dip, dip_direction);
  j.plane = {n, n.dot(centre)};
  j.centre = centre;
  j.polygon_uv = std::move(polygon);
  return j;
}

std::vector<Vec2> square(double side) {
  const double h = side / 2;
  return {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
}

std::string num(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

// A scene: a cube of the given side and the given [[sets]] text; order as-given.
std::string scene_text(std::uint64_t seed, double side, const std::string& sets,
                       const std::string& scene_extra = "") {
  return "[scene]\nseed = " + std::to_string(seed) + "\n" + scene_extra +
         "[domain]\nbox = { min = [0, 0, 0], max = [" + num(side) + ", " + num(side) + ", " +
         num(side) + "] }\n" + sets;
}

slice::JointSystem generate(const std::string& text) {
  return slice::generate_joints(slice::parse_scene(text, "test.toml"));
}

bool inside_cube(const Vec3& x, double side) {
  return (x.array() > 0).all() && (x.array() < side).all();
}

// The joints of set `set` whose centres lie in the cube: an unbiased sample of the set's
// distributions (a joint's centre is uniform and independent of its size and orientation;
// those centred outside are kept only if they reach in, which favours the large ones).
std::vector<const slice::Joint*> centred_inside(const slice::JointSystem& js, int set,
                                                double side) {
  std::vector<const slice::Joint*> out;
  for (const auto& j : js.joints)
    if (j.set == set && inside_cube(j.centre, side)) out.push_back(&j);
  return out;
}

// Kolmogorov-Smirnov: the statistic D of `x` against the CDF F and its p-value, from the
// asymptotic Kolmogorov distribution with Stephens' small-sample correction.
struct Ks {
  double d = 0, p = 0;
};
Ks ks_test(std::vector<double> x, const std::function<double(double)>& cdf) {
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  Ks r;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = cdf(x[i]);
    r.d = std::max({r.d, static_cast<double>(i + 1) / n - f, f - static_cast<double>(i) / n});
  }
  const double lambda = (std::sqrt(n) + 0.12 + 0.11 / std::sqrt(n)) * r.d;
  double q = 0;  // Q_KS(lambda) = 2 sum (-1)^(k-1) exp(-2 k^2 lambda^2)
  for (int k = 1; k <= 100; ++k)
    q += 2 * ((k % 2) ? 1 : -1) * std::exp(-2.0 * k * k * lambda * lambda);
  r.p = std::clamp(q, 0.0, 1.0);
  if (lambda < 0.2) r.p = 1;  // the series converges slowly there; D is tiny
  return r;
}

// The message of the slice::Error that f throws.
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const slice::Error& e) {
    return e.what();
  }
  FAIL("no slice::Error");
  return {};
}

std::string parse_error(const std::string& text) {
  return error_of([&] { (void)slice::parse_scene(text, "bad.toml"); });
}

void check_message(const std::string& msg, const std::vector<std::string>& parts) {
  INFO("message: " << msg);
  for (const auto& p : parts) CHECK_THAT(msg, Contains(p));
}

}  // namespace

// ---- Shapes ---------------------------------------------------------------------------------

TEST_CASE("a square joint: corners, area, radius, rotation", "[stochastic][shape]") {
  const auto s = shape_spec(slice::JointShape::square);
  const auto p = slice::joint_polygon(s, 2.0, 0);
  REQUIRE(p.size() == 4);
  CHECK(p[0] == Vec2(-1, -1));
  CHECK(p[2] == Vec2(1, 1));
  CHECK(signed_area(p) == 4.0);  // counter-clockwise
  CHECK_THAT(slice::shape_area_factor(s), WithinRel(1.0, 1e-15));
  CHECK_THAT(slice::shape_radius_factor(s), WithinRel(std::sqrt(0.5), 1e-15));
  // A quarter turn maps corners onto corners exactly (sind/cosd are exact at 90 degrees).
  const auto q = slice::joint_polygon(s, 2.0, 90);
  CHECK(q[0] == Vec2(1, -1));
  CHECK(q[1] == Vec2(1, 1));
}

TEST_CASE("rectangle, polygon and ellipse joints have the areas of their definitions",
          "[stochastic][shape]") {
  using slice::JointShape;
  SECTION("rectangle: long side along u") {
    const auto s = shape_spec(JointShape::rectangle, 2.0);
    const auto p = slice::joint_polygon(s, 4.0, 0);
    CHECK(p == std::vector<Vec2>{{-2, -1}, {2, -1}, {2, 1}, {-2, 1}});
    CHECK_THAT(slice::shape_area_factor(s), WithinRel(0.5, 1e-15));
    CHECK_THAT(slice::shape_radius_factor(s), WithinRel(std::sqrt(1.25) / 2, 1e-15));
  }
  SECTION("regular hexagon in the circle of diameter size") {
    const auto s = shape_spec(JointShape::polygon, 1, 6);
    const auto p = slice::joint_polygon(s, 2.0, 0);
    REQUIRE(p.size() == 6);
    CHECK(p[0] == Vec2(1, 0));
    for (const auto& v : p) CHECK_THAT(v.norm(), WithinRel(1.0, 1e-15));
    CHECK_THAT(signed_area(p), WithinRel(1.5 * std::sqrt(3.0), 1e-14));
  }
  SECTION("ellipse as a circumscribed 16-gon: every edge touches, nothing pokes out") {
    const auto s = shape_spec(JointShape::ellipse, 2.0, 16);
    const double a = 1, b = 0.5;  // size 2, aspect 2
    const auto p = slice::joint_polygon(s, 2.0, 0);
    REQUIRE(p.size() == 16);
    // Area of the affine image of the n-gon circumscribing the unit circle: n tan(pi/n) a b.
    CHECK_THAT(signed_area(p), WithinRel(16 * std::tan(kPi / 16) * a * b, 1e-13));
    for (std::size_t i = 0; i < p.size(); ++i) {
      double closest = 1e9;
      for (int k = 0; k < 20000; ++k) {
        const double t = 2 * kPi * k / 20000;
        const double d = left_of(p[i], p[(i + 1) % p.size()], {a * std::cos(t), b * std::sin(t)});
        CHECK(d >= -1e-12);  // the ellipse is inside
        closest = std::min(closest, d);
      }
      CHECK(closest < 1e-6);  // and touches every edge
    }
  }
  SECTION("ellipse as an equal-area 12-gon") {
    const auto s = shape_spec(JointShape::ellipse, 3.0, 12, slice::EllipseFit::equal_area);
    CHECK_THAT(signed_area(slice::joint_polygon(s, 2.0, 0)), WithinRel(kPi * 1 * (1.0 / 3), 1e-13));
  }
}

TEST_CASE("joint_size inverts joint_polygon for every shape", "[stochastic][shape]") {
  using slice::JointShape;
  const std::vector<slice::JointSetSpec> specs = {
      shape_spec(JointShape::square), shape_spec(JointShape::rectangle, 3.5),
      shape_spec(JointShape::polygon, 1, 5),
      shape_spec(JointShape::ellipse, 2, 16, slice::EllipseFit::circumscribed),
      shape_spec(JointShape::ellipse, 4, 7, slice::EllipseFit::equal_area)};
  for (const auto& s : specs) {
    const auto j = joint(30, 40, {1, 2, 3}, slice::joint_polygon(s, 3.7, 33));
    CHECK_THAT(slice::joint_size(s, j), WithinRel(3.7, 1e-13));
  }
  CHECK(std::isinf(slice::joint_size(specs[0], joint(30, 40, {1, 2, 3}))));
}

// ---- Measures -------------------------------------------------------------------------------

TEST_CASE("area_inside: the part of a joint inside the domain", "[stochastic][measure]") {
  const auto d = cube(10);
  CHECK_THAT(slice::area_inside(joint(0, 0, {5, 5, 5}, square(4)), d), WithinRel(16.0, 1e-12));
  // Half out through the face x = 10.
  CHECK_THAT(slice::area_inside(joint(0, 0, {10, 5, 5}, square(4)), d), WithinRel(8.0, 1e-12));
  // A quarter in, at the edge x = 10, y = 10.
  CHECK_THAT(slice::area_inside(joint(0, 0, {10, 10, 5}, square(4)), d), WithinRel(4.0, 1e-12));
  CHECK(slice::area_inside(joint(0, 0, {20, 5, 5}, square(4)), d) == 0);
  // Vertical (the plane x = 5), its v axis up: half above z = 10.
  CHECK_THAT(slice::area_inside(joint(90, 90, {5, 5, 10}, square(4)), d), WithinRel(8.0, 1e-12));
  // On the face z = 10 itself: it reaches nowhere into the domain.
  CHECK(slice::area_inside(joint(0, 0, {5, 5, 10}, square(4)), d) == 0);
  // Persistent planes: the whole section.
  CHECK_THAT(slice::area_inside(joint(0, 0, {5, 5, 3}), d), WithinRel(100.0, 1e-12));
  CHECK_THAT(slice::area_inside(joint(45, 90, {5, 5, 5}), d),
             WithinRel(100 * std::sqrt(2.0), 1e-12));
  CHECK_THAT(slice::area_inside(joint(45, 90, {50, 5, -40}), d),
             WithinRel(100 * std::sqrt(2.0), 1e-12));  // the same plane x + z = 10
  CHECK(slice::area_inside(joint(0, 0, {5, 5, 12}), d) == 0);
}

TEST_CASE("crosses_segment and chord", "[stochastic][measure]") {
  const auto j = joint(0, 0, {5, 5, 5}, square(2));
  CHECK(slice::crosses_segment(j, {5, 5, 0}, {5, 5, 10}));
  CHECK(slice::crosses_segment(j, {5.9, 4.1, 10}, {5.9, 4.1, 0}));
  CHECK_FALSE(slice::crosses_segment(j, {7, 5, 0}, {7, 5, 10}));  // misses the polygon
  CHECK_FALSE(slice::crosses_segment(j, {5, 5, 6}, {5, 5, 10}));  // ends above the plane
  CHECK(slice::crosses_segment(joint(0, 0, {50, 50, 5}), {5, 5, 0}, {5, 5, 10}));  // persistent
  const auto [a, b] = slice::chord(cube(10), {5, 5, 5}, Vec3(0, 0.6, 0.8));
  CHECK(a.isApprox(Vec3(5, 5 - 3.75, 0)));
  CHECK(b.isApprox(Vec3(5, 5 + 3.75, 10)));
}

TEST_CASE("a regular set records its count, P32 and P10", "[stochastic][measure]") {
  // Planes z = 1..9 in a 10 m cube: 9 x 100 m2 / 1000 m3; 9 crossings of the 10 m chord.
  const auto js =
      generate(scene_text(0, 10, "[[sets]]\ndip = 0\ndip_direction = 0\nspacing = 1\n"));
  const auto& s = js.sets.at(0);
  CHECK(s.joint_count == 9);
  CHECK_THAT(s.achieved_p32, WithinRel(0.9, 1e-12));
  CHECK_THAT(s.achieved_p10, WithinRel(0.9, 1e-12));
  CHECK_FALSE(s.scanline_given);
  CHECK(s.scanline_from.isApprox(Vec3(5, 5, 0)));
  CHECK(s.scanline_to.isApprox(Vec3(5, 5, 10)));
}

// ---- Statistics of generated sets -----------------------------------------------------------

TEST_CASE("sampled sizes follow the requested distribution (Kolmogorov-Smirnov, 1%)",
          "[stochastic][statistics]") {
  struct Case {
    const char* name;
    std::string size, shape;
    double density;  // about 10,000 centres in the 100 m cube
    std::function<double(double)> cdf;
    std::function<double(double)> wrong;  // the same, 5% larger: must be rejected
  };
  // Lognormal with the mean and sd of the size itself: sigma^2 = ln(1 + sd^2/mean^2).
  const double sigma = std::sqrt(std::log1p(0.04)), zeta = std::log(5.0) - sigma * sigma / 2;
  // Power law on [0.5, 50] with density ~ x^-2.5: a Pareto (shape 1.5) truncated at 50.
  auto power = [](double x) {
    return gsl_cdf_pareto_P(x, 1.5, 0.5) / gsl_cdf_pareto_P(50, 1.5, 0.5);
  };
  const std::vector<Case> cases = {
      {"lognormal(5, 1) squares", "{ distribution = \"lognormal\", mean = 5.0, sd = 1.0 }",
       "shape = \"square\"", 0.01, [=](double x) { return gsl_cdf_lognormal_P(x, zeta, sigma); },
       [=](double x) { return gsl_cdf_lognormal_P(x / 1.05, zeta, sigma); }},
      {"exponential(3) rectangles", "{ distribution = \"exponential\", mean = 3.0 }",
       "shape = \"rectangle\"\naspect = 2.5", 0.01,
       [](double x) { return gsl_cdf_exponential_P(x, 3.0); },
       [](double x) { return gsl_cdf_exponential_P(x / 1.05, 3.0); }},
      {"power-law(2.5, 0.5, 50) equal-area ellipses",
       "{ distribution = \"power-law\", exponent = 2.5, min = 0.5, max = 50 }",
       "shape = \"ellipse\"\naspect = 1.5\nsides = 12\nfit = \"equal-area\"", 0.01, power,
       [=](double x) { return power(std::min(x / 1.05, 50.0)); }},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name);
    const auto js =
        generate(scene_text(2015, 100,
                            "[[sets]]\ndip = 30\ndip_direction = 60\nfisher_kappa = "
                            "10\ndensity = " +
                                num(c.density) + "\nsize = " + c.size + "\n" + c.shape + "\n"));
    std::vector<double> sizes;
    for (const auto* j : centred_inside(js, 0, 100))
      sizes.push_back(slice::joint_size(js.sets[0], *j));
    CAPTURE(sizes.size());
    CHECK(sizes.size() > 9000);
    const Ks right = ks_test(sizes, c.cdf), wrong = ks_test(sizes, c.wrong);
    CAPTURE(right.d, right.p, wrong.d, wrong.p);
    INFO(c.name << ": KS D = " << right.d << ", p = " << right.p << " (n = " << sizes.size()
                << "); against a 5% larger size: p = " << wrong.p);
    CHECK(right.p > 0.01);
    CHECK(wrong.p < 0.01);
  }
  SECTION("fixed: every size is the value") {
    const auto js = generate(
        scene_text(3, 20,
                   "[[sets]]\ndip = 30\ndip_direction = 60\ncount = 500\nsize = { distribution = "
                   "\"fixed\", value = 2.5 }\nshape = \"polygon\"\nsides = 7\n"));
    REQUIRE(js.joints.size() == 500);
    for (const auto& j : js.joints)
      CHECK_THAT(slice::joint_size(js.sets[0], j), WithinRel(2.5, 1e-13));
  }
}

TEST_CASE("Fisher orientations: mean in its 95% cone, kappa estimate within 10%",
          "[stochastic][statistics]") {
  // Persistent planes through points of a box domain all meet it: exactly N joints, with no
  // selection by orientation.
  const double kappas[] = {5, 20, 100};
  const double orientations[][2] = {{85, 9}, {8, 122}};
  for (const double kappa : kappas)
    for (const auto& o : orientations) {
      CAPTURE(kappa, o[0], o[1]);
      const auto js =
          generate(scene_text(11, 10,
                              "[[sets]]\ndip = " + num(o[0]) + "\ndip_direction = " + num(o[1]) +
                                  "\nfisher_kappa = " + num(kappa) + "\ncount = 10000\n"));
      REQUIRE(js.joints.size() == 10000);
      const Vec3 mean = slice::normal_from_dip(o[0], o[1]);
      Vec3 sum = Vec3::Zero();
      for (const auto& j : js.joints) {
        CHECK(j.plane.normal.z() >= 0);  // stored as upward normals ...
        CHECK(j.plane.normal.isApprox(slice::normal_from_dip(j.dip_deg, j.dip_direction_deg)));
        // ... so fold each onto the mean's side before summing (poles are axes).
        sum += j.plane.normal.dot(mean) < 0 ? Vec3(-j.plane.normal) : j.plane.normal;
      }
      const double n = 10000, r = sum.norm();
      const double kappa_hat = (n - 1) / (n - r);
      // Fisher (1953): cos a95 = 1 - (N - R) / R ((1 / 0.05)^(1 / (N - 1)) - 1).
      const double a95 = std::acos(1 - (n - r) / r * (std::pow(20.0, 1 / (n - 1)) - 1));
      const double off = std::acos(std::min(1.0, sum.normalized().dot(mean)));
      INFO("kappa " << kappa << " at " << o[0] << "/" << o[1] << ": estimate " << kappa_hat
                    << ", mean " << off * 180 / kPi << " deg off (a95 = " << a95 * 180 / kPi
                    << " deg)");
      CHECK_THAT(kappa_hat, WithinRel(kappa, 0.10));
      CHECK(off < a95);
    }
}

TEST_CASE("Poisson centres: counts have the mean and variance of a Poisson variable",
          "[stochastic][statistics]") {
  // 300 scenes differing in the seed; density 0.05 in a 10 m cube: mean 50 centres inside.
  const int runs = 300;
  const double mu = 50;
  std::vector<double> counts;
  for (int seed = 1; seed <= runs; ++seed) {
    const auto js = generate(scene_text(
        static_cast<std::uint64_t>(seed), 10,
        "[[sets]]\ndip = 40\ndip_direction = 200\ndensity = 0.05\nsize = { distribution = "
        "\"fixed\", value = 0.5 }\n"));
    counts.push_back(static_cast<double>(centred_inside(js, 0, 10).size()));
  }
  double mean = 0, ss = 0;
  for (const double c : counts) mean += c / runs;
  for (const double c : counts) ss += (c - mean) * (c - mean);
  const double var = ss / (runs - 1);
  // The dispersion index sum (x - mean)^2 / mean is chi-squared with runs - 1 degrees of
  // freedom for Poisson counts (variance = mean); fixed counts (variance 0) or a doubled
  // variance fail it.
  const double p = gsl_cdf_chisq_P(ss / mean, runs - 1);
  INFO("Poisson: mean " << mean << ", variance " << var << " (expected " << mu
                        << " both); dispersion test p = " << p);
  CHECK_THAT(mean, WithinAbs(mu, 4 * std::sqrt(mu / runs)));
  CHECK(p > 0.005);
  CHECK(p < 0.995);
}

TEST_CASE("P32 and P10 targets are met within 2%", "[stochastic][statistics]") {
  SECTION("p32 of lognormal squares, exponential rectangles and power-law ellipses") {
    const std::vector<std::string> sets = {
        "size = { distribution = \"lognormal\", mean = 3.0, sd = 1.0 }\n",
        "size = { distribution = \"exponential\", mean = 2.0 }\nshape = \"rectangle\"\naspect = "
        "3\n",
        "size = { distribution = \"power-law\", exponent = 2.5, min = 0.5, max = 20 }\n"
        "shape = \"ellipse\"\naspect = 2\n"};
    for (const auto& size : sets) {
      CAPTURE(size);
      const auto js = generate(scene_text(
          5, 30, "[[sets]]\ndip = 60\ndip_direction = 300\nfisher_kappa = 20\np32 = 0.5\n" + size));
      const auto& s = js.sets.at(0);
      // Recomputed from the joints, independently of the generator's running sum.
      double area = 0;
      for (const auto& j : js.joints) area += slice::area_inside(j, cube(30));
      INFO("P32 target 0.5: achieved " << s.achieved_p32 << " with " << js.joints.size()
                                       << " joints");
      CHECK_THAT(area / 27000, WithinRel(s.achieved_p32, 1e-9));
      CHECK_THAT(s.achieved_p32, WithinRel(0.5, 0.02));
      CHECK(s.joint_count == static_cast<std::int64_t>(js.joints.size()));
      CHECK(s.candidates > s.joint_count);  // some drawn joints missed the domain
    }
  }
  SECTION("p10 of finite and of persistent joints along a scanline") {
    for (const std::string& size :
         {std::string("size = { distribution = \"lognormal\", mean = 4.0, sd = 1.0 }\n"),
          std::string()}) {
      CAPTURE(size);
      const auto js = generate(
          scene_text(6, 30,
                     "[[sets]]\ndip = 80\ndip_direction = 100\nfisher_kappa = 10\np10 = 1.5\n"
                     "scanline = { from = [0, 15, 15], to = [30, 15, 15] }\n" +
                         size));
      // Crossings counted here: the segment's crossing with the plane, inside the polygon
      // (checked with global corners, not the library's (u, v) test).
      const Vec3 a(0, 15, 15), b(30, 15, 15);
      int hits = 0;
      for (const auto& j : js.joints) {
        const double sa = j.plane.distance(a), sb = j.plane.distance(b);
        if (sa * sb >= 0) continue;
        const Vec3 x = a + sa / (sa - sb) * (b - a);
        bool in = true;
        const auto f = slice::plane_frame(j.dip_deg, j.dip_direction_deg);
        for (std::size_t i = 0; i < j.polygon_uv.size(); ++i) {
          const Vec3 p = f.to_global(j.centre, j.polygon_uv[i]);
          const Vec3 q = f.to_global(j.centre, j.polygon_uv[(i + 1) % j.polygon_uv.size()]);
          in = in && (q - p).cross(x - p).dot(j.plane.normal) >= 0;
        }
        hits += in ? 1 : 0;
      }
      const auto& s = js.sets.at(0);
      INFO("P10 target 1.5: achieved " << hits / 30.0 << " (" << hits << " crossings, "
                                       << js.joints.size() << " joints)");
      CHECK_THAT(hits / 30.0, WithinRel(1.5, 0.02));
      CHECK(s.achieved_p10 == hits / 30.0);
    }
  }
}

// ---- Reproducibility ------------------------------------------------------------------------

TEST_CASE("the same scene gives the same joints -- appending a set changes no other set",
          "[stochastic][reproducibility]") {
  const std::string j1 =
      "[[sets]]\nname = \"J1\"\ndip = 20\ndip_direction = 10\nfisher_kappa = 15\ndensity = 0.02\n"
      "size = { distribution = \"lognormal\", mean = 3.0, sd = 1.0 }\n";
  const std::string j2 =
      "[[sets]]\nname = \"J2\"\ndip = 70\ndip_direction = 250\np32 = 0.3\n"
      "size = { distribution = \"exponential\", mean = 2.0 }\n";
  const auto a = generate(scene_text(9, 20, j1));
  const auto again = generate(scene_text(9, 20, j1));
  const auto both = generate(scene_text(9, 20, j1 + j2));
  const auto other_seed = generate(scene_text(10, 20, j1));
  auto set_joints = [](const slice::JointSystem& js, int set) {
    std::vector<const slice::Joint*> out;
    for (const auto& j : js.joints)
      if (j.set == set) out.push_back(&j);
    return out;
  };
  auto same = [](const slice::Joint& x, const slice::Joint& y) {
    return x.plane.normal == y.plane.normal && x.plane.d == y.plane.d && x.centre == y.centre &&
           x.dip_deg == y.dip_deg && x.dip_direction_deg == y.dip_direction_deg &&
           x.polygon_uv == y.polygon_uv;
  };
  const auto first = set_joints(a, 0);
  REQUIRE(first.size() > 100);
  for (const auto* other : {&again, &both}) {
    const auto js = set_joints(*other, 0);
    REQUIRE(js.size() == first.size());
    for (std::size_t i = 0; i < js.size(); ++i) CHECK(same(*js[i], *first[i]));
  }
  CHECK(set_joints(both, 1).size() > 100);
  CHECK_FALSE(same(*set_joints(other_seed, 0).at(0), *first.at(0)));
  CHECK(a.sets[0].stream_seed == slice::set_stream_seed(9, 0));
  CHECK(both.sets[1].stream_seed == slice::set_stream_seed(9, 1));
  CHECK(slice::set_stream_seed(9, 0) != slice::set_stream_seed(9, 1));
  CHECK(slice::set_stream_seed(9, 0) != slice::set_stream_seed(10, 0));
  CHECK(slice::set_stream_seed(9, 0) < (1ull << 32));
}

TEST_CASE("a stochastic scene shifted by (5e5, 5e6, 300) gives the same joints, shifted",
          "[stochastic][reproducibility]") {
  const Vec3 shift(5e5, 5e6, 300);
  auto scene = [&](const Vec3& o) {
    return "[scene]\nseed = 12\n[domain]\nbox = { min = [" + num(o.x()) + ", " + num(o.y()) + ", " +
           num(o.z()) + "], max = [" + num(o.x() + 30) + ", " + num(o.y() + 30) + ", " +
           num(o.z() + 30) +
           "] }\n[[sets]]\ndip = 50\ndip_direction = 30\nfisher_kappa = 20\np32 = 0.3\n"
           "size = { distribution = \"lognormal\", mean = 3.0, sd = 1.0 }\n";
  };
  const auto a = generate(scene(Vec3::Zero())), b = generate(scene(shift));
  REQUIRE(a.joints.size() == b.joints.size());
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    CAPTURE(i);
    CHECK(a.joints[i].polygon_uv == b.joints[i].polygon_uv);
    CHECK(a.joints[i].plane.normal == b.joints[i].plane.normal);
    CHECK_THAT((b.joints[i].centre - shift - a.joints[i].centre).norm(), WithinAbs(0, 1e-8));
  }
  CHECK_THAT(b.sets[0].achieved_p32, WithinRel(a.sets[0].achieved_p32, 1e-9));
}

TEST_CASE("joint order applies to stochastic sets: alternating, each set largest first",
          "[stochastic][order]") {
  const auto js =
      generate(scene_text(4, 20,
                          "[options]\norder = \"alternating\"\n"
                          "[[sets]]\ndip = 10\ndip_direction = 0\ncount = 30\n"
                          "size = { distribution = \"lognormal\", mean = 3.0, sd = 1.0 }\n"
                          "[[sets]]\ndip = 80\ndip_direction = 90\ncount = 20\n"
                          "size = { distribution = \"exponential\", mean = 2.0 }\n"));
  REQUIRE(js.joints.size() == 50);
  std::vector<double> area[2];
  for (std::size_t i = 0; i < js.joints.size(); ++i) {
    const int set = js.joints[i].set;
    CHECK(set == (i < 40 ? static_cast<int>(i % 2) : 0));  // then the rest of the larger set
    area[set].push_back(slice::polygon_area(js.joints[i]));
  }
  for (const auto& a : area) CHECK(std::is_sorted(a.rbegin(), a.rend()));  // largest first
}

// ---- Bad input ------------------------------------------------------------------------------

TEST_CASE("bad stochastic sets name the line, the key and the fix", "[stochastic][bad-input]") {
  const std::string head = "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n";
  const std::string set = head + "[[sets]]\nname = \"J1\"\ndip = 5\ndip_direction = 9\n";  // :3-6
  const std::string lognormal = "size = { distribution = \"lognormal\", mean = 2.0, sd = 1.0 }\n";
  check_message(parse_error(set + "density = 0.1\nsize = { distribution = \"lognormal\", mean = "
                                  "2.0, sd = -1.0 }\n"),
                {"bad.toml:8", "'sd' in 'size' of [[sets]] \"J1\"", "-1", "standard deviation"});
  check_message(parse_error(set + "density = 0.1\nfisher_kappa = -2\n" + lognormal),
                {"bad.toml:8", "'fisher_kappa' in [[sets]] \"J1\"", "-2, below 0", ">= 0"});
  check_message(parse_error(set + "p32 = 0.5\n"),
                {"bad.toml:7", "'p32' in [[sets]] \"J1\"", "no 'size'", "add size ="});
  check_message(
      parse_error(set + "p10 = 1\nscanline = { from = [5, 5, 5], to = [5, 5, 12] }\n" + lognormal),
      {"bad.toml:8", "scanline of [[sets]] \"J1\" leaves the domain", "'to'", "inside"});
  check_message(parse_error(set + "p10 = 1\n" + lognormal),
                {"bad.toml:3", "missing key 'scanline'", "[[sets]] \"J1\""});
  check_message(parse_error(set + "density = 1e3\n" + lognormal),
                {"bad.toml:7", "would draw about", "more than max_joints = 1000000",
                 "raise max_joints in [scene]"});
  check_message(parse_error("[scene]\nmax_joints = 100\n" + set + "count = 101\n" + lognormal),
                {"bad.toml:9", "more than max_joints = 100"});
  check_message(parse_error(set + "count = 10\ndensity = 0.1\n" + lognormal),
                {"bad.toml:8", "gives both 'count' and 'density'"});
  check_message(parse_error(set + "count = 2.5\n" + lognormal),
                {"bad.toml:7", "'count'", "whole number"});
  check_message(parse_error(set + "count = 10\nsize = { distribution = \"lognormal\", mean = 2.0, "
                                  "std = 1.0 }\n"),
                {"bad.toml:8", "unknown key 'std'", "did you mean 'sd'?"});
  check_message(parse_error(set + "count = 10\nsize = { distribution = \"normal\", mean = 2.0 }\n"),
                {"bad.toml:8", "\"normal\"", "fixed | lognormal | exponential | power-law"});
  check_message(parse_error(set + "count = 10\nsize = { distribution = \"power-law\", exponent = "
                                  "2, min = 5, max = 1 }\n"),
                {"bad.toml:8", "'max'", "min < max"});
  check_message(parse_error(set + "count = 10\nshape = \"square\"\n"),
                {"bad.toml:8", "'shape'", "no 'size'"});
  check_message(parse_error(set + "count = 10\n" + lognormal +
                            "shape = \"rectangle\"\naspect = "
                            "0.5\n"),
                {"bad.toml:10", "'aspect'", "below 1"});
  check_message(parse_error(set + "count = 10\n" + lognormal + "sides = 6\n"),
                {"bad.toml:9", "'sides' in [[sets]] \"J1\" applies to polygons and ellipses"});
  check_message(parse_error(set + "count = 10\n" + lognormal + "shape = \"polygon\"\n"),
                {"bad.toml:3", "missing key 'sides'"});
  check_message(parse_error(set + "count = 10\n" + lognormal + "shape = \"elipse\"\n"),
                {"bad.toml:9", "did you mean \"ellipse\"?"});
  check_message(parse_error(set + "count = 10\noffset = 1\n" + lognormal),
                {"bad.toml:8", "'offset'", "regular sets"});
  check_message(parse_error(head + "[[sets]]\ndip = 0\ndip_direction = 0\np10 = 1\n"
                                   "scanline = { from = [5, 0, 5], to = [5, 10, 5] }\n"),
                {"bad.toml:6", "cannot be reached", "scanline lies in the plane"});
  check_message(parse_error("[scene]\nmax_joints = 0\n" + head),
                {"bad.toml:2", "'max_joints'", "below 1"});
  check_message(parse_error(set + "fisher_kapa = 3\ncount = 1\n"),
                {"bad.toml:7", "did you mean 'fisher_kappa'?"});
}

TEST_CASE("generation stops at max_joints drawn joints", "[stochastic][bad-input]") {
  // The parser's estimate lets this through (60 kept x box volume / domain volume = about 90
  // drawn); the generator's own count still stops a set that draws more than max_joints.
  auto scene = slice::parse_scene(
      scene_text(1, 10,
                 "[[sets]]\nname = \"J1\"\ndip = 5\ndip_direction = 9\ncount = 60\nsize = { "
                 "distribution = \"fixed\", value = 1 }\n",
                 "max_joints = 500\n"),
      "s.toml");
  CHECK(slice::generate_joints(scene).joints.size() == 60);
  scene.max_joints = 61;
  check_message(error_of([&] { (void)slice::generate_joints(scene); }),
                {"s.toml", "[[sets]] \"J1\" drew max_joints = 61 joints", "raise max_joints"});
}

TEST_CASE("/sets attributes: read back, older files without them, bad names refused",
          "[stochastic][h5io]") {
  test::TempDir tmp;
  const auto js = generate(scene_text(
      3, 20,
      "[[sets]]\nname = \"J1\"\ndip = 30\ndip_direction = 60\nfisher_kappa = 12\ncount = 40\n"
      "size = { distribution = \"power-law\", exponent = 2.2, min = 1, max = 9 }\n"
      "shape = \"ellipse\"\naspect = 2\nfit = \"equal-area\"\nrotation = 15\n"));
  const auto file = tmp / "j.h5";
  slice::write_joints(file, js, {"test", "0", "test", "s.toml", "0"});
  // Keep the JointSystem alive: a reference into a temporary's set dangled (ASan found it).
  const slice::JointSystem back = slice::read_joints(file);
  const auto& s = back.sets.at(0);
  CHECK(s.intensity == slice::SetIntensity::count);
  CHECK(s.count == 40);
  CHECK(s.fisher_kappa == 12);
  CHECK(s.size.distribution == slice::SizeDistribution::power_law);
  CHECK(s.size.exponent == 2.2);
  CHECK(s.shape == slice::JointShape::ellipse);
  CHECK(s.fit == slice::EllipseFit::equal_area);
  CHECK(s.sides == 16);
  CHECK(s.rotation_fixed);
  CHECK(s.rotation_deg == 15);
  CHECK(s.joint_count == 40);
  CHECK(s.stream_seed == js.sets[0].stream_seed);
  CHECK(s.achieved_p32 == js.sets[0].achieved_p32);
  auto edit = [&](const std::function<void(const slice::h5::Group&)>& change) {
    slice::h5::File f = slice::h5::File::open(file, {file.string(), ""}, true);
    change(f.root().open_group("sets").open_group("000"));
    f.close();
  };
  edit([](const slice::h5::Group& g) {
    g.remove_attribute("shape");
    g.write_attribute<std::string>("shape", "circle");
  });
  check_message(error_of([&] { (void)slice::read_joints(file); }),
                {"j.h5", "/sets/000 attribute shape is \"circle\"", "square, rectangle",
                 "regenerate it with slice-joints"});
  // A file from before stochastic sets: no 'intensity', so a regular set.
  edit([](const slice::h5::Group& g) { g.remove_attribute("intensity"); });
  CHECK(slice::read_joints(file).sets.at(0).intensity == slice::SetIntensity::spacing);
}

// Field data as it is mapped (issue 26, item 6): Fisher scatter on regular (spacing) sets, and
// the [[sets]] mapping window and trace_length keys (their parsing, refusals, and the /sets
// attributes that record the traces). The trace statistics against independent traces and
// against the theory of discs: tests/property/trace_property_test.cpp.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "slice/stochastic.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using slice::Vec3;

namespace {

std::string num(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

std::string cube_scene(std::uint64_t seed, double side, const std::string& sets) {
  return "[scene]\nseed = " + std::to_string(seed) +
         "\n[domain]\nbox = { min = [0, 0, 0], max = [" + num(side) + ", " + num(side) + ", " +
         num(side) + "] }\n" + sets;
}

slice::JointSystem generate(const std::string& text) {
  return slice::generate_joints(slice::parse_scene(text, "test.toml"));
}

std::string parse_error(const std::string& text) {
  return test::error_of([&] { (void)slice::parse_scene(text, "bad.toml"); });
}

// The maximum-likelihood estimate of the Fisher concentration from the mean resultant length
// rbar = R / N: the root of coth k - 1 / k = rbar (by bisection; A(k) increases).
double kappa_mle(double rbar) {
  double lo = 1e-6, hi = 1e6;
  for (int i = 0; i < 200; ++i) {
    const double k = std::sqrt(lo * hi);
    (1 / std::tanh(k) - 1 / k < rbar ? lo : hi) = k;
  }
  return std::sqrt(lo * hi);
}

}  // namespace

TEST_CASE(
    "Fisher scatter on a regular set: each plane's pole, the mean and kappa within "
    "sampling error",
    "[field][fisher][statistics]") {
  // A 200 m cube at spacing 0.1: some 2,000 to 3,400 planes per case.
  const double kappas[] = {5, 20, 100};
  const double orientations[][2] = {{85, 9}, {8, 122}, {40, 250}};
  int cases = 0;
  for (const std::uint64_t seed : {1u, 2u, 77u})
    for (const double kappa : kappas)
      for (const auto& o : orientations) {
        CAPTURE(seed, kappa, o[0], o[1]);
        const auto js = generate(
            cube_scene(seed, 200,
                       "[[sets]]\ndip = " + num(o[0]) + "\ndip_direction = " + num(o[1]) +
                           "\nspacing = 0.1\noffset = 0.05\nfisher_kappa = " + num(kappa) + "\n"));
        const Vec3 mean = slice::normal_from_dip(o[0], o[1]);
        const Vec3 middle(100, 100, 100);  // the domain's vertex mean
        REQUIRE(js.joints.size() > 1900);
        Vec3 sum = Vec3::Zero();
        double last = -1e300;
        for (const auto& j : js.joints) {
          CHECK(j.persistent());
          CHECK(j.plane.normal.z() >= 0);
          CHECK(j.plane.normal.isApprox(slice::normal_from_dip(j.dip_deg, j.dip_direction_deg)));
          // Each plane keeps its place: through its centre, which lies on the mean normal's line
          // through the vertex mean, at offset + k spacing along it, in increasing k.
          CHECK(std::abs(j.plane.distance(j.centre)) < 1e-9);
          CHECK((j.centre - middle).cross(mean).norm() < 1e-9);
          const double along = mean.dot(j.centre);
          const double k = (along - 0.05) / 0.1;
          CHECK_THAT(k, WithinAbs(std::round(k), 1e-6));
          CHECK(along > last);
          last = along;
          sum += j.plane.normal.dot(mean) < 0 ? Vec3(-j.plane.normal) : j.plane.normal;
        }
        const double n = static_cast<double>(js.joints.size()), r = sum.norm();
        const double k_hat = kappa_mle(r / n);
        // The estimate's standard error, 1 / sqrt(N A'(k)), A(k) = coth k - 1/k.
        const double a_prime = 1 / (kappa * kappa) - 1 / std::pow(std::sinh(kappa), 2);
        const double se = 1 / std::sqrt(n * a_prime);
        // Fisher (1953): the 99% cone of the mean, cos a99 = 1 - (N - R)/R (100^(1/(N-1)) - 1).
        const double a99 = std::acos(1 - (n - r) / r * (std::pow(100.0, 1 / (n - 1)) - 1));
        const double off = std::acos(std::min(1.0, sum.normalized().dot(mean)));
        INFO("N " << n << ": kappa estimate " << k_hat << " (se " << se << "), mean " << off
                  << " rad off (a99 " << a99 << ")");
        CHECK(std::abs(k_hat - kappa) < 3.5 * se);
        CHECK(off < a99);
        CHECK(js.sets[0].stream_seed == slice::set_stream_seed(seed, 0));
        ++cases;
      }
  CHECK(cases == 27);
}

TEST_CASE("a regular set without fisher_kappa, or with 0, has every plane at the mean",
          "[field][fisher]") {
  const std::string set = "[[sets]]\ndip = 35\ndip_direction = 300\nspacing = 1.5\n";
  const auto plain = generate(cube_scene(9, 20, set));
  const auto zero = generate(cube_scene(9, 20, set + "fisher_kappa = 0\n"));
  const auto other_seed = generate(cube_scene(10, 20, set));
  REQUIRE(plain.joints.size() > 10);
  REQUIRE(zero.joints.size() == plain.joints.size());
  const Vec3 n = slice::normal_from_dip(35, 300);
  for (std::size_t i = 0; i < plain.joints.size(); ++i) {
    for (const auto* js : {&zero, &other_seed}) {
      const auto& j = js->joints[i];
      CHECK(j.plane.normal == plain.joints[i].plane.normal);
      CHECK(j.plane.d == plain.joints[i].plane.d);
      CHECK(j.centre == plain.joints[i].centre);
      CHECK(j.dip_deg == 35);
      CHECK(j.dip_direction_deg == 300);
    }
    CHECK(plain.joints[i].plane.normal == n);
  }
  // With scatter, the seed chooses the poles; the same seed, the same planes.
  const auto a = generate(cube_scene(9, 20, set + "fisher_kappa = 50\n"));
  const auto b = generate(cube_scene(9, 20, set + "fisher_kappa = 50\n"));
  const auto c = generate(cube_scene(10, 20, set + "fisher_kappa = 50\n"));
  REQUIRE(a.joints.size() == plain.joints.size());
  std::size_t same = 0;
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    CHECK(a.joints[i].plane.normal == b.joints[i].plane.normal);
    CHECK(a.joints[i].centre == plain.joints[i].centre);  // the planes keep their places
    same += a.joints[i].plane.normal == c.joints[i].plane.normal ? 1 : 0;
  }
  CHECK(same == 0);
}

TEST_CASE("mapping and trace_length: parsed, recorded in joints.h5 and read back",
          "[field][traces]") {
  test::TempDir tmp;
  const std::string text = cube_scene(
      4, 40,
      "[[sets]]\nname = \"J1\"\ndip = 70\ndip_direction = 30\nfisher_kappa = 20\ncount = 4000\n"
      "size = { distribution = \"lognormal\", mean = 4, sd = 2 }\n"
      "mapping = { point = [20, 20, 20], dip = 90, dip_direction = 180, width = 30, height = 12 "
      "}\ntrace_length = { mean = 2.5, sd = 1.25 }\n"
      "[[sets]]\nname = \"J2\"\ndip = 10\ndip_direction = 100\nspacing = 3\nfisher_kappa = 40\n"
      "mapping = { point = [20, 20, 20], dip = 90, dip_direction = 180, width = 30, height = 12 "
      "}\n[[sets]]\nname = \"J3\"\ndip = 50\ndip_direction = 200\nspacing = 5\n");
  const auto scene = slice::parse_scene(text, "test.toml");
  const auto& m = scene.sets[0].mapping;
  CHECK(m.given);
  CHECK(m.centre == Vec3(20, 20, 20));
  CHECK(m.dip_deg == 90);
  CHECK(m.dip_direction_deg == 180);
  CHECK(m.width == 30);
  CHECK(m.height == 12);
  CHECK(m.field_mean == 2.5);
  CHECK(m.field_sd == 1.25);
  CHECK(scene.sets[1].mapping.given);
  CHECK(scene.sets[1].mapping.field_mean == 0);
  CHECK_FALSE(scene.sets[2].mapping.given);

  const auto js = slice::generate_joints(scene);
  const auto& t1 = js.sets[0].traces;
  CHECK(t1.count > 50);
  CHECK(t1.censored[0] + t1.censored[1] + t1.censored[2] == t1.count);
  CHECK(t1.mean > 0);
  CHECK(t1.sd > 0);
  CHECK(t1.p21 > 0);
  // A regular set's traces are persistent lines: censored at both ends, one per plane that
  // crosses the window (12 m high, planes about 3 m apart, nearly horizontal).
  const auto& t2 = js.sets[1].traces;
  CHECK(t2.censored[2] == t2.count);
  CHECK(t2.count >= 3);
  CHECK(t2.complete_mean == 0);

  const std::string file = (tmp / "j.h5").string();
  slice::write_joints(file, js, {"test", "0", "test", "s.toml", "0"});
  const auto back = slice::read_joints(file);
  for (std::size_t s = 0; s < 3; ++s) {
    const auto& a = js.sets[s];
    const auto& b = back.sets[s];
    CHECK(b.mapping.given == a.mapping.given);
    CHECK(b.mapping.centre == a.mapping.centre);
    CHECK(b.mapping.width == a.mapping.width);
    CHECK(b.mapping.field_sd == a.mapping.field_sd);
    CHECK(b.traces.count == a.traces.count);
    CHECK(b.traces.censored == a.traces.censored);
    CHECK(b.traces.mean == a.traces.mean);
    CHECK(b.traces.sd == a.traces.sd);
    CHECK(b.traces.complete_mean == a.traces.complete_mean);
    CHECK(b.traces.p21 == a.traces.p21);
  }
}

TEST_CASE("bad mapping and trace_length keys name the line, the key and the fix",
          "[field][bad-input]") {
  const std::string head = cube_scene(
      1, 40, "[[sets]]\nname = \"J1\"\ndip = 70\ndip_direction = 30\ncount = 40\n");  // 9 lines
  const std::string window =
      "mapping = { point = [20, 20, 20], dip = 90, dip_direction = 180, width = 30, height = 12 "
      "}\n";
  struct Case {
    std::string text;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {head + "trace_length = { mean = 2 }\n",
       {"bad.toml:10", "'trace_length'", "needs the window", "add mapping"}},
      {head + "mapping = { point = [20, 20, 20], dip = 90, dip_direction = 180, width = 50, "
              "height = 12 }\n",
       {"bad.toml:10", "mapping window of [[sets]] \"J1\" leaves the domain", "shrink"}},
      {head + "mapping = { point = [20, 20, 20], dip = 90, dip_direction = 180, height = 12 }\n",
       {"bad.toml:10", "'width'", "add width"}},
      {head + "mapping = { point = [20, 20, 20], dip = 95, dip_direction = 180, width = 5, "
              "height = 2 }\n",
       {"bad.toml:10", "'dip'", "95"}},
      {head + "mapping = { point = [20, 20, 20], dip = 90, dip_direction = 180, width = 5, "
              "height = 0 }\n",
       {"bad.toml:10", "'height'", "> 0"}},
      {head + "mapping = { point = [20, 20, 20], dip = 90, dip_direction = 180, width = 5, "
              "height = 2, size = 3 }\n",
       {"bad.toml:10", "'size'"}},
      {head + "mapping = [20, 20, 20]\n", {"bad.toml:10", "'mapping'"}},
      {head + window + "trace_length = { mean = -2 }\n", {"bad.toml:11", "'mean'", "> 0"}},
      {head + window + "trace_length = { mean = 2, sd = 0 }\n", {"bad.toml:11", "'sd'", "> 0"}},
      {head + window + "trace_length = { mean = 2, median = 1 }\n", {"bad.toml:11", "'median'"}},
      {"[scene]\ndimension = 2\n[domain]\nbox = { min = [0, 0], max = [10, 10] }\n[[sets]]\n"
       "dip = 30\ndip_direction = 90\nspacing = 1\nmapping = { point = [5, 0, 5], dip = 90, "
       "dip_direction = 0, width = 2, height = 2 }\n",
       {"bad.toml:9", "'mapping'", "2-D"}},
  };
  for (const auto& c : cases) {
    const std::string msg = parse_error(c.text);
    INFO("scene:\n" << c.text << "\nmessage: " << msg);
    CHECK(msg.find('\n') == std::string::npos);
    for (const auto& w : c.words) CHECK_THAT(msg, Contains(w));
  }
}

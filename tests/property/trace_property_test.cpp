// Traces on a mapping window ([[sets]] mapping, slice/traces.hpp), on random scenes with fixed
// seeds: (1) the statistics slice-joints reports equal those of traces computed here another
// way (the line where the two planes meet, clipped by the half-planes of the polygon's edges and
// of the window); (2) the traces of generated discs reproduce the trace distribution that the
// discs' sizes imply, within sampling error: the count of traces, their total length (P21), and
// the mean length of the traces seen whole.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "slice/stochastic.hpp"
#include "slice/traces.hpp"
#include "support/support.hpp"

using slice::Vec3;

namespace {

constexpr double kPi = std::numbers::pi;

std::string num(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

struct Seen {
  double length = 0;
  int censored = 0;  // ends cut by the window's border
};

// The trace of j on window w: the line where the joint's plane meets the mapping plane, as
// x0 + t d, kept where it is inside every edge of the polygon (left of each edge, seen from
// the joint's upward normal) and inside the window's four sides. An end is censored when a side
// of the window, not an edge of the polygon, ends it.
std::optional<Seen> trace_by_half_planes(const slice::Joint& j, const slice::TraceMapping& w,
                                         double tol) {
  const slice::JointFrame f = slice::plane_frame(w.dip_deg, w.dip_direction_deg);
  const Vec3 n1 = j.plane.normal, n2 = f.n;
  const Vec3 d = n1.cross(n2);
  if (d.norm() < 1e-12) return std::nullopt;
  const double h1 = j.plane.d, h2 = n2.dot(w.centre);
  const Vec3 x0 = (h1 * n2.cross(d) + h2 * d.cross(n1)) / d.squaredNorm();
  const Vec3 dir = d.normalized();
  double t0 = -std::numeric_limits<double>::infinity(), t1 = -t0;
  bool window0 = true, window1 = true;
  // a + b t >= 0.
  const auto keep = [&](double a, double b, bool window) {
    if (b > 0 && -a / b > t0) {
      t0 = -a / b;
      window0 = window;
    } else if (b < 0 && -a / b < t1) {
      t1 = -a / b;
      window1 = window;
    } else if (b == 0 && a < 0) {
      t1 = t0 - 1;  // empty
    }
  };
  for (const auto& [axis, half] : {std::pair{f.u, 0.5 * w.width}, std::pair{f.v, 0.5 * w.height}})
    for (const double s : {1.0, -1.0})
      keep(half - s * axis.dot(x0 - w.centre), -s * axis.dot(dir), true);
  const std::vector<Vec3> poly = slice::joint_polygon(j);
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec3 m = n1.cross(poly[(i + 1) % poly.size()] - poly[i]);
    keep(m.dot(x0 - poly[i]), m.dot(dir), false);
  }
  if (!(t1 - t0 > tol)) return std::nullopt;
  return Seen{t1 - t0, (window0 ? 1 : 0) + (window1 ? 1 : 0)};
}

struct Stats {
  std::int64_t count = 0;
  std::array<std::int64_t, 3> censored{};
  double sum = 0, sum2 = 0, complete = 0, complete2 = 0;
};

Stats stats_of(const slice::JointSystem& js, std::size_t set, double tol) {
  Stats s;
  for (const auto& j : js.joints) {
    if (j.set != static_cast<std::int32_t>(set)) continue;
    const auto t = trace_by_half_planes(j, js.sets[set].mapping, tol);
    if (!t) continue;
    ++s.count;
    ++s.censored[static_cast<std::size_t>(t->censored)];
    s.sum += t->length;
    s.sum2 += t->length * t->length;
    if (t->censored == 0) {
      s.complete += t->length;
      s.complete2 += t->length * t->length;
    }
  }
  return s;
}

}  // namespace

TEST_CASE("reported trace statistics equal traces computed independently (random scenes)",
          "[property][traces]") {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> u01(0, 1);
  const long cases = test::scaled_cases(30);
  long traces = 0;
  for (long c = 0; c < cases; ++c) {
    const auto angle = [&](double lo, double hi) {
      return num(std::round(lo + (hi - lo) * u01(rng)));
    };
    // A window of random orientation about the middle of a 40 m cube (it fits at any angle).
    const std::string window = "mapping = { point = [20, 20, 20], dip = " + angle(0, 90) +
                               ", dip_direction = " + angle(0, 359) +
                               ", width = " + num(5 + 20 * u01(rng)) +
                               ", height = " + num(5 + 15 * u01(rng)) + " }\n";
    const std::string set = "dip = " + angle(0, 90) + "\ndip_direction = " + angle(0, 359) + "\n";
    const std::string text =
        "[scene]\nseed = " + std::to_string(c) +
        "\n[domain]\nbox = { min = [0, 0, 0], max = [40, 40, 40] }\n"
        "[[sets]]\n" +
        set +
        "fisher_kappa = 15\ndensity = 0.06\n"
        "size = { distribution = \"lognormal\", mean = 5, sd = 3 }\nshape = \"ellipse\"\n"
        "aspect = 1.5\n" +
        window + "[[sets]]\n" + set + "fisher_kappa = 8\nspacing = 1.7\n" + window + "[[sets]]\n" +
        set + "count = 25\n" + window +  // persistent planes at random places
        "[[sets]]\n" + set +
        "p32 = 0.6\nsize = { distribution = \"power-law\", exponent = 2.5, "
        "min = 1, max = 30 }\nshape = \"rectangle\"\naspect = 3\n" +
        window;
    CAPTURE(c, text);
    const auto js = slice::generate_joints(slice::parse_scene(text, "case.toml"));
    const double tol = js.options.tolerance * js.length_scale;
    for (std::size_t s = 0; s < js.sets.size(); ++s) {
      CAPTURE(s);
      const Stats e = stats_of(js, s, tol);
      const slice::TraceStats& r = js.sets[s].traces;
      const double area = js.sets[s].mapping.width * js.sets[s].mapping.height;
      CHECK(r.count == e.count);
      CHECK(r.censored == e.censored);
      traces += e.count;
      if (e.count == 0) continue;
      const double n = static_cast<double>(e.count), mean = e.sum / n;
      CHECK_THAT(r.mean, Catch::Matchers::WithinRel(mean, 1e-9));
      CHECK_THAT(r.p21, Catch::Matchers::WithinRel(e.sum / area, 1e-9));
      if (e.count > 1) {
        const double sd = std::sqrt(std::max(0.0, (e.sum2 - n * mean * mean) / (n - 1)));
        CHECK_THAT(r.sd, Catch::Matchers::WithinAbs(sd, 1e-7 * mean));
      }
      if (e.censored[0] > 0)
        CHECK_THAT(r.complete_mean, Catch::Matchers::WithinRel(
                                        e.complete / static_cast<double>(e.censored[0]), 1e-9));
    }
  }
  CHECK(traces > 50 * cases);
}

TEST_CASE("traces of generated discs reproduce the trace distribution of their sizes",
          "[property][traces][statistics]") {
  // Discs (96-gons) of one orientation and diameter D from a distribution, centres a Poisson
  // process of density lambda, cut by a mapping plane at angle phi: the trace midpoints are a
  // Poisson process of intensity lambda E[D] sin(phi) per unit area, all traces run in one
  // direction (c, s) in the window's (u, v) frame, and a disc of diameter D leaves a chord
  // l = D sqrt(1 - r^2), r uniform in [0, 1]: E[l^k | D] = c_k D^k, c1 = pi/4, c2 = 2/3,
  // c3 = 3 pi/16. So on a W x H window, with m_k = E[D^k]:
  //   traces meeting it   lambda sin(phi) (m1 W H + c1 m2 (c H + s W))
  //   traces seen whole   lambda sin(phi) (m1 W H - c1 m2 (c H + s W) + c2 m3 c s)
  //   their total length  lambda sin(phi) (c1 m2 W H - c2 m3 (c H + s W) + c3 m4 c s)
  //   total length inside the window (P21 W H): lambda sin(phi) E[area] W H.
  std::mt19937_64 rng(26006);
  std::uniform_real_distribution<double> u01(0, 1);
  const double c1 = kPi / 4, c2 = 2.0 / 3, c3 = 3 * kPi / 16;
  const long cases = test::scaled_cases(18);
  for (long c = 0; c < cases; ++c) {
    // The mapping plane normal to x, y or z, in a domain 2 m thick across it.
    const int axis = static_cast<int>(c % 3);
    const bool lognormal = (c / 3) % 2 == 1;
    const double W = 32, H = 22;
    std::string domain, window;
    if (axis == 0) {
      domain = "box = { min = [-1, 0, 0], max = [1, 40, 30] }";
      window = "point = [0, 20, 15], dip = 90, dip_direction = 90";
    } else if (axis == 1) {
      domain = "box = { min = [0, -1, 0], max = [40, 1, 30] }";
      window = "point = [20, 0, 15], dip = 90, dip_direction = 0";
    } else {
      domain = "box = { min = [0, 0, -1], max = [40, 30, 1] }";
      window = "point = [20, 15, 0], dip = 0, dip_direction = 0";
    }
    // A joint orientation at least 20 degrees off the mapping plane.
    double dip = 0, dd = 0, sin_phi = 0;
    const slice::JointFrame f = slice::plane_frame(axis == 2 ? 0 : 90, axis == 0 ? 90 : 0);
    do {
      dip = std::round(90 * u01(rng));
      dd = std::round(359 * u01(rng));
      sin_phi = slice::normal_from_dip(dip, dd).cross(f.n).norm();
    } while (sin_phi < std::sin(20 * kPi / 180));
    const Vec3 along = slice::normal_from_dip(dip, dd).cross(f.n).normalized();
    const double cu = std::abs(along.dot(f.u)), sv = std::abs(along.dot(f.v));
    double m[5];
    std::string size;
    if (lognormal) {
      const double mean = 2.5, sd = 1.0;
      const double s2 = std::log1p(sd * sd / (mean * mean)), zeta = std::log(mean) - s2 / 2;
      for (int k = 0; k < 5; ++k) m[k] = std::exp(k * zeta + k * k * s2 / 2);
      size = "{ distribution = \"lognormal\", mean = 2.5, sd = 1.0 }";
    } else {
      const double d = 1.5 + 2.5 * u01(rng);
      for (int k = 0; k < 5; ++k) m[k] = std::pow(d, k);
      size = "{ distribution = \"fixed\", value = " + num(d) + " }";
    }
    const double edge = cu * H + sv * W;
    // About 1,500 traces a case.
    const double lambda = 1500 / (sin_phi * (m[1] * W * H + c1 * m[2] * edge));
    const std::string text = "[scene]\nseed = " + std::to_string(100 + c) + "\n[domain]\n" +
                             domain + "\n[[sets]]\ndip = " + num(dip) +
                             "\ndip_direction = " + num(dd) + "\ndensity = " + num(lambda) +
                             "\nsize = " + size +
                             "\nshape = \"polygon\"\nsides = 96\nmapping = { " + window +
                             ", width = " + num(W) + ", height = " + num(H) + " }\n";
    CAPTURE(c, text);
    const auto js = slice::generate_joints(slice::parse_scene(text, "case.toml"));
    const slice::TraceStats& t = js.sets[0].traces;
    const Stats e = stats_of(js, 0, js.options.tolerance * js.length_scale);
    REQUIRE(t.count == e.count);

    const double rate = lambda * sin_phi;
    const double count = rate * (m[1] * W * H + c1 * m[2] * edge);
    const double whole = rate * (m[1] * W * H - c1 * m[2] * edge + c2 * m[3] * cu * sv);
    const double whole_length = rate * (c1 * m[2] * W * H - c2 * m[3] * edge + c3 * m[4] * cu * sv);
    const double p21 = rate * slice::shape_area_factor(js.sets[0]) * m[2];
    const double n0 = static_cast<double>(t.censored[0]);
    const double complete_sd = std::sqrt((e.complete2 - e.complete * e.complete / n0) / (n0 - 1));
    INFO("traces " << t.count << " (expected " << count << "), seen whole " << n0 << " (" << whole
                   << "), their mean " << t.complete_mean << " (" << whole_length / whole
                   << "), P21 " << t.p21 << " (" << p21 << ")");
    CHECK(std::abs(static_cast<double>(t.count) - count) < 3.5 * std::sqrt(count));
    CHECK(std::abs(n0 - whole) < 3.5 * std::sqrt(whole));
    CHECK(std::abs(t.complete_mean - whole_length / whole) < 3.5 * complete_sd / std::sqrt(n0));
    CHECK(std::abs(t.p21 - p21) < 3.5 * std::sqrt(e.sum2) / (W * H));
  }
}

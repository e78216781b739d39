// The reach test of the cut (libslice/src/slice/reach.hpp): reach_any and reach_list, four
// spheres at a time where the CPU has AVX2, against ReachQuery one sphere at a time, on random
// spheres and joints and on spheres that sit exactly on each of the test's thresholds, far from
// the origin too. The vector code must give the scalar answer for every sphere, bit for bit: the
// cut's figures and its blocks depend on which pairs pass. Fixed seeds; SLICE_PROPERTY_SCALE
// (support.hpp) runs a share.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "slice/reach.hpp"
#include "support/support.hpp"

namespace {

using slice::PreparedJoint;
using slice::ReachQuery;
using slice::SphereArrays;
using slice::Vec3;

constexpr std::uint64_t kSeed = 2929;

/// Spheres one array per coordinate.
struct Spheres {
  std::vector<double> x, y, z, r;
  void add(const Vec3& c, double radius) {
    x.push_back(c.x());
    y.push_back(c.y());
    z.push_back(c.z());
    r.push_back(radius);
  }
  SphereArrays arrays() const { return {x.data(), y.data(), z.data(), r.data(), r.size()}; }
};

/// A square joint of half side h about c in the plane of unit normal n, prepared as the cut
/// prepares it (persistent: no corners).
PreparedJoint square_joint(const Vec3& n, const Vec3& c, double h, bool persistent) {
  PreparedJoint p;
  p.plane = {n, n.dot(c)};
  p.centre = c;
  if (persistent) return p;
  const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  p.corners = {c + h * (u + v), c + h * (v - u), c - h * (u + v), c + h * (u - v)};
  p.radius = h * std::sqrt(2.0);
  p.lo = p.hi = p.corners.front();
  for (const Vec3& x : p.corners) {
    p.lo = p.lo.cwiseMin(x);
    p.hi = p.hi.cwiseMax(x);
    p.edges.push_back({n, 0});  // only their number counts here: a polygon
  }
  return p;
}

/// The spheres q holds for, one at a time.
std::vector<std::size_t> scalar_list(const ReachQuery& q, const Spheres& s) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < s.r.size(); ++i)
    if (q(s.x[i], s.y[i], s.z[i], s.r[i])) out.push_back(i);
  return out;
}

/// reach_list and reach_any, vectorised and not, against scalar_list; returns the number of
/// spheres that passed.
std::size_t check_all_ways(const ReachQuery& q, const Spheres& s, const std::string& what) {
  const std::vector<std::size_t> want = scalar_list(q, s);
  for (const bool vector : {true, false}) {
    INFO(what << (vector ? ", vectorised" : ", one at a time") << ", " << s.r.size() << " spheres");
    std::vector<std::size_t> got = {999999};  // reach_list appends
    slice::reach_list(q, s.arrays(), got, vector);
    got.erase(got.begin());
    REQUIRE(got == want);
    REQUIRE(slice::reach_any(q, s.arrays(), vector) == !want.empty());
  }
  return want.size();
}

/// A random unit vector.
Vec3 unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const Vec3 v(g(rng), g(rng), g(rng));
    if (v.norm() > 1e-3) return v.normalized();
  }
}

}  // namespace

TEST_CASE("reach_any and reach_list answer as the reach test one sphere at a time", "[reach]") {
  WARN("reach_any and reach_list vectorised on this CPU (AVX2): "
       << (slice::reach_vectorised() ? "yes" : "no, one sphere at a time only"));
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> u(0, 1);
  const long cases = test::scaled_cases(20000, 100);
  std::size_t passed = 0, spheres = 0;
  for (long k = 0; k < cases; ++k) {
    // Far from the origin in one case of four (the tests' 1e6 m offset), in units of 1e-3 to
    // 1e3; up to 70 spheres, so that every remainder of four is met.
    const double scale = std::pow(10.0, -3 + 6 * u(rng));
    const Vec3 offset = (k % 4 == 0 ? 1e6 : 0.0) * Vec3(1, -1, 0.5);
    const bool persistent = k % 5 == 0;
    const PreparedJoint pj = square_joint(unit(rng), offset + scale * Vec3(u(rng), u(rng), u(rng)),
                                          scale * (0.05 + 0.5 * u(rng)), persistent);
    const double tol = scale * 1e-9;
    const ReachQuery q(pj, tol);
    Spheres s;
    const auto n = static_cast<std::size_t>(u(rng) * 71);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 c = offset + scale * Vec3(u(rng), u(rng), u(rng));
      double r = scale * 0.2 * u(rng);
      // One sphere in three on a threshold of the test: its plane distance, its distance to the
      // polygon's sphere or a side of its box exactly r + tol (or as exactly as the rounding of
      // r allows); the scalar and the vector code must round them alike.
      switch (i % 12) {
        case 0:
          r = std::abs(q.a * c.x() + q.b * c.y() + q.c * c.z() - q.d) - tol;
          break;
        case 1:
          r = (c - pj.centre).norm() - q.pr;
          break;
        case 2:
          r = q.lo[0] - c.x();
          break;
        case 3:
          r = c.y() - q.hi[1];
          break;
        default:
          break;
      }
      s.add(c, r);
    }
    passed += check_all_ways(
        q, s, std::string(persistent ? "persistent" : "square") + " case " + std::to_string(k));
    spheres += n;
  }
  // The cases meet both answers often (not a test that only ever says no).
  CHECK(passed > spheres / 50);
  CHECK(passed < spheres / 2);
}

TEST_CASE("reach_list finds every sphere a joint reaches among spheres it all reaches or none",
          "[reach]") {
  const PreparedJoint pj = square_joint(Vec3(0, 0, 1), Vec3(0.5, 0.5, 0.5), 0.25, false);
  const ReachQuery q(pj, 1e-9);
  for (std::size_t n = 0; n <= 9; ++n) {
    Spheres hit, miss;
    for (std::size_t i = 0; i < n; ++i) {
      hit.add(Vec3(0.5 + 0.01 * double(i), 0.5, 0.5), 0.1);   // on the polygon
      miss.add(Vec3(0.5, 0.5, 0.7 + 0.01 * double(i)), 0.1);  // above it, out of reach
    }
    CHECK(check_all_ways(q, hit, "all hit") == n);
    CHECK(check_all_ways(q, miss, "all miss") == 0);
  }
}

TEST_CASE("GroupBoxes rules out only groups none of whose spheres the joint may reach", "[reach]") {
  std::mt19937_64 rng(kSeed + 1);
  std::uniform_real_distribution<double> u(0, 1);
  const long cases = test::scaled_cases(20000, 100);
  long ruled_out = 0, groups = 0;
  for (long k = 0; k < cases; ++k) {
    const double scale = std::pow(10.0, -3 + 6 * u(rng));
    const Vec3 offset = (k % 4 == 0 ? 1e6 : 0.0) * Vec3(-1, 0.5, 1);
    const bool persistent = k % 5 == 0;
    const PreparedJoint pj = square_joint(unit(rng), offset + scale * Vec3(u(rng), u(rng), u(rng)),
                                          scale * (0.05 + 0.3 * u(rng)), persistent);
    const double tol = scale * 1e-9;
    const ReachQuery q(pj, tol);
    // Up to eight groups of up to 12 spheres, each group about a random point; some empty.
    slice::GroupBoxes boxes;
    std::vector<bool> reached(slice::GroupBoxes::kMax, false);
    for (std::size_t g = 0; g < slice::GroupBoxes::kMax; ++g) {
      slice::SphereGroup group;
      const Vec3 at = offset + scale * Vec3(u(rng), u(rng), u(rng));
      const auto n = static_cast<std::size_t>(u(rng) * 13);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3 c = at + scale * 0.2 * Vec3(u(rng), u(rng), u(rng));
        // Now and then a sphere that just touches the joint's plane, within its tolerance.
        const double r = i == 0 && k % 3 == 0
                             ? std::abs(q.a * c.x() + q.b * c.y() + q.c * c.z() - q.d) - 0.5 * tol
                             : scale * 0.1 * u(rng);
        group.add(Eigen::Vector4d(c.x(), c.y(), c.z(), r));
        reached[g] = reached[g] || q(c.x(), c.y(), c.z(), r);
      }
      boxes.set(g, group.lo(), group.hi());
      REQUIRE(group.any_reached(q) == reached[g]);
    }
    const unsigned bits = boxes.may_reach(pj, tol);
    INFO("case " << k << (persistent ? ", persistent" : ", square"));
    REQUIRE(boxes.may_reach(pj, tol, false) == bits);  // the vector code's answer is the scalar's
    for (std::size_t g = 0; g < slice::GroupBoxes::kMax; ++g) {
      INFO("group " << g);
      if (reached[g]) REQUIRE((bits >> g & 1u) == 1u);
      ruled_out += reached[g] ? 0 : long(1 - (bits >> g & 1u));
      groups += reached[g] ? 0 : 1;
    }
  }
  // The boxes rule out many of the groups the joint does not reach (a test that says yes to
  // everything would pass the requirement above).
  CHECK(ruled_out > groups / 4);
}

// Tunnel zones (issue 16, item 3): the section frame, the regular polygon about the tunnel's
// circle, the regions against a direct point-in-prism test, the construction joints of
// cut = true, and one case per kind of bad tunnel, each with its line.
#include "slice/tunnel.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "slice/error.hpp"
#include "slice/scene.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec2;
using slice::Vec3;

namespace {

// A 40 m cube about the origin: lines 1 and 2. A zone appended starts on line 3.
const std::string kHead = "[domain]\nbox = { min = [-20, -20, -20], max = [20, 20, 20] }\n";

std::string error_of(const std::string& text) {
  try {
    (void)slice::parse_scene(text, "bad.toml");
  } catch (const slice::Error& e) {
    return e.what();
  }
  FAIL("no error for the scene:\n" << text);
  return {};
}

// Inside the union of the regions, as slice-cut decides removal (strictly inside one).
bool in_regions(const std::vector<slice::Region>& zones, const Vec3& x) {
  for (const auto& z : zones) {
    bool inside = true;
    for (const auto& p : z.planes) inside &= p.distance(x) < 0;
    if (inside) return true;
  }
  return false;
}

// Distance from x to the polygon's boundary.
double to_boundary(const std::vector<Vec2>& p, const Vec2& x) {
  double best = 1e300;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % p.size()];
    const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * (b - a) - x).norm());
  }
  return best;
}

// A horseshoe, clockwise (as a user might give it): a floor with an upward bump (a reflex
// vertex at (0, -1.5)), walls that bulge out, an arch. Star-shaped about (0, 0), not convex.
const std::vector<Vec2> kHorseshoeCw = {{-2, -2},   {-3.5, 0}, {-3, 2},  {-1.5, 3.4}, {0, 3.8},
                                        {1.5, 3.4}, {3, 2},    {3.5, 0}, {2, -2},     {0, -1.5}};

std::string outline_toml(const std::vector<Vec2>& p) {
  std::string s = "[";
  for (const auto& x : p) {
    s += (s.size() > 1 ? ", [" : "[") + std::to_string(x.x()) + ", " + std::to_string(x.y());
    s += "]";
  }
  return s + "]";
}

}  // namespace

TEST_CASE("the tunnel section frame is right-handed with v up", "[unit][tunnel]") {
  for (const Vec3& d : {Vec3(0, 1, 0), Vec3(1, 2, 0.3), Vec3(-3, 0.5, -1), Vec3(0, 0, 1),
                        Vec3(0, 0, -2), Vec3(1e-12, 0, 1)}) {
    CAPTURE(d.transpose());
    const slice::TunnelFrame f = slice::tunnel_frame(d);
    CHECK_THAT((f.d - d.normalized()).norm(), WithinAbs(0, 1e-15));
    CHECK_THAT(f.u.norm(), WithinAbs(1, 1e-15));
    CHECK_THAT(f.v.norm(), WithinAbs(1, 1e-15));
    CHECK_THAT(f.u.dot(f.d), WithinAbs(0, 1e-15));
    CHECK_THAT((f.u.cross(f.v) - f.d).norm(), WithinAbs(0, 1e-15));  // right-handed
    if (std::hypot(d.x(), d.y()) > 1e-6) {                           // not vertical:
      CHECK_THAT(f.u.z(), WithinAbs(0, 1e-15));                      // u horizontal
      CHECK(f.v.z() > 0);                                            // v up
    }
  }
  const slice::TunnelFrame north = slice::tunnel_frame({0, 1, 0});
  CHECK(north.u == Vec3(-1, 0, 0));  // seen from ahead, looking back South: u West, v Up
  CHECK(north.v == Vec3(0, 0, 1));
  const slice::TunnelFrame shaft = slice::tunnel_frame({0, 0, 1});
  CHECK(shaft.u == Vec3(1, 0, 0));
  CHECK(shaft.v == Vec3(0, 1, 0));
}

TEST_CASE("a round tunnel's polygon circumscribes its circle, floor flat", "[unit][tunnel]") {
  const auto n = GENERATE(3, 4, 7, 16, 1000);
  CAPTURE(n);
  const double r = 4;
  auto p = slice::regular_outline(r, n);
  REQUIRE(p.size() == std::size_t(n));
  CHECK_FALSE(slice::check_outline(p, 1e-9).has_value());  // valid and already counter-clockwise
  CHECK(slice::outline_convex(p));
  const double circum = r / std::cos(std::numbers::pi / n);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % p.size()];
    CHECK_THAT(a.norm(), WithinRel(circum, 1e-14));
    // Every side touches the circle: the distance of its line from the axis is r.
    CHECK_THAT((a.x() * b.y() - a.y() * b.x()) / (b - a).norm(), WithinRel(r, 1e-12));
  }
  CHECK_THAT(p.back().y(), WithinRel(-r, 1e-12));   // the side from the last vertex to the first
  CHECK_THAT(p.front().y(), WithinRel(-r, 1e-12));  //   is the floor, v = -r
  CHECK_THAT(slice::signed_area(p), WithinRel(n * r * r * std::tan(std::numbers::pi / n), 1e-12));
}

TEST_CASE("a tunnel zone removes the prism about its circle and nothing else", "[unit][tunnel]") {
  // A tilted axis, so that no coordinate is special.
  const Vec3 point(-5, -8, -3), dir = Vec3(0.3, 1, 0.2).normalized();
  const double R = 4, L = 14;
  const int n = 16;
  const auto s = slice::parse_scene(kHead +
                                        "[[zones]]\n"
                                        "tunnel = { point = [-5, -8, -3], direction = [0.3, 1, "
                                        "0.2], length = 14, radius = 4, sides = 16 }\n",
                                    "t.toml");
  REQUIRE(s.zones.size() == 1);                           // convex: one region,
  CHECK(s.zones[0].planes.size() == std::size_t(n + 2));  //   its sides and two ends
  CHECK(s.joints.empty());                                // cut = false: no joints
  const slice::TunnelFrame f = slice::tunnel_frame(dir);
  const double circum = R / std::cos(std::numbers::pi / n);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * std::numbers::pi * u01(rng), along = L * (0.001 + 0.998 * u01(rng));
    const Vec2 dir2(std::cos(a), std::sin(a));
    CAPTURE(k, a, along);
    CHECK(in_regions(s.zones, f.to_global(point, 0.99 * R * dir2, along)));
    CHECK_FALSE(in_regions(s.zones, f.to_global(point, 1.01 * circum * dir2, along)));
    CHECK_FALSE(in_regions(s.zones, f.to_global(point, 0.5 * R * dir2, -0.01)));
    CHECK_FALSE(in_regions(s.zones, f.to_global(point, 0.5 * R * dir2, L + 0.01)));
  }
  // The corners themselves, just inside and just outside.
  for (const auto& c : slice::regular_outline(R, n)) {
    CHECK(in_regions(s.zones, f.to_global(point, 0.999 * c, L / 2)));
    CHECK_FALSE(in_regions(s.zones, f.to_global(point, 1.001 * c, L / 2)));
  }
}

TEST_CASE("a horseshoe's fan of prisms covers exactly its outline", "[unit][tunnel]") {
  const auto s = slice::parse_scene(
      kHead + "[[zones]]\ntunnel = { point = [0, -10, 0], " +
          "direction = [0, 1, 0], length = 20, outline = " + outline_toml(kHorseshoeCw) + " }\n",
      "t.toml");
  REQUIRE(s.zones.size() == kHorseshoeCw.size());  // not convex: one prism per edge
  const slice::TunnelFrame f = slice::tunnel_frame({0, 1, 0});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uu(-4, 4), vv(-3, 5), ss(-1, 21);
  std::size_t inside = 0, checked = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec2 uv(uu(rng), vv(rng));
    const double along = ss(rng);
    // Points within 1e-6 of the surface are left out: there the tolerance decides.
    if (to_boundary(kHorseshoeCw, uv) < 1e-6 || std::abs(along) < 1e-6 ||
        std::abs(along - 20) < 1e-6)
      continue;
    const bool expect = test::in_polygon(kHorseshoeCw, uv) && along > 0 && along < 20;
    CAPTURE(uv.transpose(), along);
    CHECK(in_regions(s.zones, f.to_global({0, -10, 0}, uv, along)) == expect);
    inside += expect ? 1 : 0;
    ++checked;
  }
  CHECK(inside > checked / 4);
  // On a fan plane itself (the ray through a vertex, inside): still inside, the fan planes
  // overlap by the tolerance.
  for (const auto& c : kHorseshoeCw)
    CHECK(in_regions(s.zones, f.to_global({0, -10, 0}, 0.5 * c, 10)));
}

TEST_CASE("cut = true outlines the tunnel with construction joints", "[unit][tunnel]") {
  // The tunnel from y = -5 to y = 25 (domain -20..20): the start cap is inside, the end outside.
  const auto s = slice::parse_scene(
      kHead +
          "[[sets]]\nname = \"rock\"\ndip = 30\ndip_direction = 40\nspacing = 5\nstage = 2\n"
          "[[zones]]\ntunnel = { point = [1, -5, 2], direction = [0, 1, 0], length = 30, "
          "radius = 3, sides = 8 }\ncut = true\n"
          "[[zones]]\ntunnel = { point = [0, 0, -19], direction = [0, 0, 1], length = 10, outline "
          "= " +
          outline_toml(kHorseshoeCw) + " }\ncut = true\nstage = 1\n",
      "t.toml");
  REQUIRE(s.joint_places.size() == s.joints.size());
  // Round tunnel: 8 sides and the start cap; horseshoe shaft: 10 sides and a fan of 10
  // triangles at each end (its bottom lies 1 m above the domain's base: inside too).
  REQUIRE(s.joints.size() == 9 + 10 + 20);
  for (std::size_t i = 0; i < s.joints.size(); ++i) {
    const auto& j = s.joints[i];
    CAPTURE(i);
    CHECK(j.kind == slice::JointKind::construction);
    CHECK_FALSE(j.limits);
    CHECK(j.set == -1);
    CHECK(slice::polygon_area(j) > 0);
    // Its corners on its plane, on the surface of the zone's prism, and in the domain's
    // bounding region or on its faces.
    const auto& zones = i < 9 ? std::vector<slice::Region>{s.zones[0]}
                              : std::vector<slice::Region>(s.zones.begin() + 1, s.zones.end());
    for (const Vec3& x : slice::joint_polygon(j)) {
      CHECK_THAT(j.plane.distance(x), WithinAbs(0, 1e-12));
      double outside = -1e300;  // the largest distance outside any one region: ~0 on it
      for (const auto& z : zones) {
        double d = -1e300;
        for (const auto& p : z.planes) d = std::max(d, p.distance(x));
        outside = std::max(outside, -std::abs(d));
      }
      CHECK_THAT(outside, WithinAbs(0, 1e-8));
    }
  }
  // Stages: the round tunnel has none, so it comes after the rock set (stage 2): 3.
  CHECK(s.joint_places[0].stage == 3);
  CHECK(s.joint_places[9].stage == 1);
  // The side faces are exactly `length` long: a rectangle 30 m by the side's length.
  const double side = 2 * 3 * std::tan(std::numbers::pi / 8);
  CHECK_THAT(slice::polygon_area(s.joints[0]), WithinRel(30 * side, 1e-12));
  // The start cap is the octagon.
  CHECK_THAT(slice::polygon_area(s.joints[8]),
             WithinRel(8 * 9 * std::tan(std::numbers::pi / 8), 1e-12));

  // In the joint system: the rock set's planes, then the round tunnel's; the shaft's first.
  const auto js = slice::generate_joints(s);
  REQUIRE(js.joints.size() > s.joints.size());
  for (std::size_t i = 0; i < 30; ++i) CHECK(js.joints[i].kind == slice::JointKind::construction);
  CHECK(js.joints.back().kind == slice::JointKind::construction);
  CHECK(js.joints[30].kind == slice::JointKind::rock);
}

TEST_CASE("bad scene: tunnel zones", "[unit][tunnel][bad-input]") {
  struct Case {
    std::string zone;                // the [[zones]] entry, from line 3
    std::vector<std::string> words;  // in the message
  };
  const std::string t = "tunnel = { point = [0, 0, 0], direction = [0, 1, 0], length = 10";
  const Case cases[] = {
      {"[[zones]]\n" + t + ", radius = 3 }\ncut = 1\n", {"bad.toml:5", "'cut'", "true or false"}},
      {"[[zones]]\n" + t + ", radius = 3 }\n\nstage = 2\n",
       {"bad.toml:6", "'stage'", "cut = true"}},
      {"[[zones]]\nbox = { min = [0, 0, 0], max = [1, 1, 1] }\ncut = true\n",
       {"bad.toml:5", "'cut'", "tunnel, mesh and surface zones only"}},
      {"[[zones]]\nbox = { min = [0, 0, 0], max = [1, 1, 1] }\n" + t + ", radius = 3 }\n",
       {"bad.toml:4", "both 'tunnel' and 'box'"}},
      {"[[zones]]\n" + t + " }\n", {"bad.toml:4", "missing key 'radius'", "outline"}},
      {"[[zones]]\n" + t + ", radius = 3, outline = [[1, 0], [0, 1], [-1, -1]] }\n",
       {"bad.toml:4", "both 'radius' and 'outline'"}},
      {"[[zones]]\n" + t + ", radius = -3 }\n", {"bad.toml:4", "'radius'", "not > 0"}},
      {"[[zones]]\n" + t + ", radius = 3, sides = 2 }\n", {"bad.toml:4", "'sides'", "[3, 1000]"}},
      {"[[zones]]\n" + t + ", radius = 3, sides = 1001 }\n", {"bad.toml:4", "'sides'", "1001"}},
      {"[[zones]]\n" + t + ", radius = 3, sides = 6.0 }\n", {"bad.toml:4", "whole number"}},
      {"[[zones]]\n" + t + ", radus = 3 }\n", {"bad.toml:4", "did you mean 'radius'?"}},
      {"[[zones]]\ntunnel = { point = [0, 0, 0], direction = [0, 0, 0], length = 1, radius = 1 "
       "}\n",
       {"bad.toml:4", "'direction'", "no direction"}},
      {"[[zones]]\ntunnel = { point = [0, 0, 0], direction = [0, 1, 0], length = 0, radius = 1 "
       "}\n",
       {"bad.toml:4", "'length'", "not > 0"}},
      {"[[zones]]\ntunnel = { point = [0, 0, 0], direction = [0, 1, 0], radius = 1 }\n",
       {"bad.toml:4", "missing key 'length'"}},
      {"[[zones]]\ntunnel = { point = [50, 0, 0], direction = [0, 1, 0], length = 5, radius = 1 "
       "}\n",
       {"bad.toml:3", "no volume inside the domain"}},
      {"[[zones]]\ntunnel = 3\n", {"bad.toml:4", "must be a table"}},
      // Outlines: the line of the vertex at fault.
      {"[[zones]]\n" + t + ", outline = [\n  [1, 1], [2, 1], [2, 2],\n  [1, 2]] }\n",
       {"bad.toml:5", "not star-shaped about the axis"}},
      {"[[zones]]\n" + t + ", outline = [\n  [1, 1],\n  [-1, -1], [1, -1], [-1, 1]] }\n",
       {"bad.toml:5", "line through (0, 0)"}},
      {"[[zones]]\n" + t + ", outline = [[1, 0], [0, 1], [1, 0]] }\n",
       {"bad.toml:4", "the same point"}},
      {"[[zones]]\n" + t + ", outline = [[1, -1], [1, 0], [1, 1], [-1, 0]] }\n",
       {"bad.toml:4", "collinear", "remove vertex 2"}},
      {"[[zones]]\n" + t + ", outline = [[1, 0], [0, 1]] }\n", {"bad.toml:4", "at least 3"}},
      {"[[zones]]\n" + t + ", radius = 1, outline = 3 }\n", {"bad.toml:4", "both"}},
      {"[[zones]]\n" + t + ", outline = 3 }\n", {"bad.toml:4", "array of [u, v]"}},
      {"[[zones]]\n" + t + ", outline = [[1, 0], [0, 1], [-1, 0], [0, -1]], sides = 4 }\n",
       {"bad.toml:4", "'sides'", "round tunnel"}},
  };
  for (const auto& c : cases) {
    const std::string msg = error_of(kHead + c.zone);
    CAPTURE(c.zone, msg);
    for (const auto& w : c.words) CHECK_THAT(msg, Contains(w));
  }
  // A pentagram winds twice round the axis.
  std::string star = "[";
  for (int k = 0; k < 5; ++k) {
    const double a = 2 * std::numbers::pi * (2 * k % 5) / 5;
    star +=
        (k ? ", [" : "[") + std::to_string(std::cos(a)) + ", " + std::to_string(std::sin(a)) + "]";
  }
  CHECK_THAT(error_of(kHead + "[[zones]]\n" + t + ", outline = " + star + "] }\n"),
             Contains("winds 2 times"));
}

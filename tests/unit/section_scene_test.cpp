// 2-D scenes (docs/2d.md): a section in (x, z) parsed into joints with y = 0, and what a
// section cannot hold refused with the line and the fix.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "support/support.hpp"

namespace {

const std::string kHead =
    "[scene]\ndimension = 2\n[domain]\nbox = { min = [0, 0], max = [20, 10] }\n";

std::string error_of(const std::string& text) {
  return test::error_of([&] { slice::generate_joints(slice::parse_scene(text, "bad.toml")); });
}

void check_message(const std::string& msg, std::initializer_list<std::string> parts) {
  CAPTURE(msg);
  for (const std::string& p : parts) CHECK(msg.find(p) != std::string::npos);
}

}  // namespace

TEST_CASE("a 2-D scene gives lines and segments in (x, z) with y = 0", "[unit][scene][section]") {
  // dip 10 towards +x through (10, 5): z = 5 - (x - 10) tan 10.
  const double t = std::tan(10 * M_PI / 180);
  char seg[200];
  std::snprintf(seg, sizeof seg, "segment = [[5, %.17g], [15, %.17g]]\n", 5 + 5 * t, 5 - 5 * t);
  const std::string text = kHead +
                           "[[sets]]\ndip = 60\ndip_direction = 90\nspacing = 2.0\n"
                           "[[sets]]\ndip = 30\ndip_direction = 270\nspacing = 1.5\n"
                           "[[joints]]\ndip = 10\ndip_direction = 90\npoint = [10, 5]\n" +
                           seg;
  const slice::JointSystem js = slice::generate_joints(slice::parse_scene(text, "s.toml"));
  CHECK(js.dimension == 2);
  CHECK(js.domain.planes.size() == 4);  // no faces normal to y
  for (const auto& p : js.domain.planes) CHECK(p.normal.y() == 0);
  // The section's bounding radius: half the diagonal of 20 x 10.
  CHECK(js.length_scale == Approx(0.5 * std::sqrt(500.0)).epsilon(1e-15));
  std::size_t segments = 0;
  for (const auto& j : js.joints) {
    CHECK(j.plane.normal.y() == 0);
    CHECK(j.centre.y() == 0);
    if (j.persistent()) continue;
    ++segments;
    // The rectangle of the plane from y = -0.5 to 0.5 between the segment's ends.
    const auto corners = slice::joint_polygon(j);
    REQUIRE(corners.size() == 4);
    double ymin = 1, ymax = -1, xmin = 100, xmax = -100;
    for (const auto& c : corners) {
      ymin = std::min(ymin, c.y());
      ymax = std::max(ymax, c.y());
      xmin = std::min(xmin, c.x());
      xmax = std::max(xmax, c.x());
    }
    CHECK(ymin == Approx(-0.5).margin(1e-12));
    CHECK(ymax == Approx(0.5).margin(1e-12));
    CHECK(xmin == Approx(5).margin(1e-12));
    CHECK(xmax == Approx(15).margin(1e-12));
  }
  CHECK(segments == 1);
  // Set 1: lines x sin 60 + z cos 60 = 2 k inside the box: k = 1 .. 10 (the far corner is at
  // 20 sin 60 + 10 cos 60 = 22.3); set 2: -x sin 30 + z cos 30 = 1.5 k, k = -6 .. 5.
  CHECK(js.sets.at(0).candidates == 11);
  CHECK(js.sets.at(1).candidates == 12);
}

TEST_CASE("bad 2-D scenes are refused with the line and the fix", "[unit][scene][section]") {
  check_message(
      error_of("[scene]\ndimension = 4\n[domain]\nbox = { min = [0, 0], max = [1, 1] }\n"),
      {"bad.toml:2", "'dimension' in [scene] is 4, not 2 or 3"});
  check_message(error_of(kHead + "[[joints]]\ndip = 10\ndip_direction = 45\npoint = [1, 1]\n"),
                {"bad.toml:7", "dips towards +x or -x", "dip_direction = 90"});
  check_message(error_of(kHead + "[[joints]]\ndip = 10\ndip_direction = 90\npoint = [1, 1, 1]\n"),
                {"bad.toml:8", "'point' in [[joints]] #1 must be 2 numbers [x, z]"});
  check_message(error_of(kHead + "[[joints]]\ndip = 10\ndip_direction = 90\npoint = [1, 1]\n"
                                 "polygon = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]\n"),
                {"bad.toml:9", "'polygon' in [[joints]] #1 is for 3-D scenes", "segment"});
  check_message(error_of(kHead + "[[joints]]\ndip = 0\ndip_direction = 90\npoint = [1, 1]\n"
                                 "segment = [[0, 1], [2, 1.5]]\n"),
                {"bad.toml:9", "end 2 is 0.5 off the joint's line"});
  check_message(error_of(kHead + "[[joints]]\ndip = 0\ndip_direction = 90\npoint = [1, 1]\n"
                                 "segment = [[2, 1], [2, 1]]\n"),
                {"bad.toml:9", "has no length"});
  check_message(error_of(kHead + "[[sets]]\ndip = 10\ndip_direction = 90\ndensity = 0.1\n"),
                {"bad.toml:8", "regular lines (spacing)", "segment = [[x1, z1], [x2, z2]]"});
  check_message(error_of(kHead + "[[sets]]\ndip = 10\ndip_direction = 90\nspacing = 1\n"
                                 "fisher_kappa = 10\n"),
                {"bad.toml:9", "'fisher_kappa'", "not available for a 2-D scene's regular set"});
  check_message(error_of(kHead + "[options]\nfixed_faces = [\"-y\"]\n"),
                {"bad.toml:6", "names \"-y\" in a 2-D scene", "-x, +x, -z and +z"});
  check_message(
      error_of(kHead + "[[zones]]\ntunnel = { point = [1, 1], direction = [1, 0], length = 1, "
                       "radius = 1 }\n"),
      {"bad.toml:6", "'direction'", "is for 3-D tunnels", "point = [x, z]"});
  check_message(error_of("[scene]\ndimension = 2\n[domain]\nbox = { min = [0, 0, 0], max = "
                         "[1, 1, 1] }\n"),
                {"bad.toml:4", "must be 2 numbers [x, z]"});
  check_message(error_of("[scene]\n[domain]\nbox = { min = [0, 0, 0], max = [1, 1, 1] }\n"
                         "[[joints]]\ndip = 0\ndip_direction = 0\npoint = [0, 0, 0.5]\n"
                         "segment = [[0, 0], [1, 0]]\n"),
                {"bad.toml:8", "'segment' in [[joints]] #1 is for 2-D scenes", "polygon"});
}

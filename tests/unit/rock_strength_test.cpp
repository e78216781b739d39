// Issue 24: the tensile strength of joints (`tension` in [[joints]] and [[sets]]) and intact rock
// ([rock]) from the scene through joints.h5 (/joints/tension, the /sets attribute tension,
// /rock), files from before them (tension 0, no [rock]), and bad values (one line, file:line).
#include <catch2/catch.hpp>
#include <string>

#include "io/h5/h5.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;

namespace {

// Lines 1-2 the domain, 3-6 [rock], 7-11 a [[joints]] entry, 12-17 a set.
const std::string kScene = R"([domain]
box = { min = [0, 0, 0], max = [10, 10, 10] }
[rock]
friction_angle = 45
cohesion = 2e6
tension = 1e6
[[joints]]
dip = 30
dip_direction = 90
point = [5, 5, 5]
tension = 5e4
[[sets]]
name = "A"
dip = 0
dip_direction = 0
spacing = 2
tension = 1e3
)";

std::string error_of(const std::string& text) {
  try {
    (void)slice::parse_scene(text, "t.toml");
  } catch (const slice::Error& e) {
    return e.what();
  }
  FAIL("no error for the scene:\n" << text);
  return {};
}

void check_tensions(const slice::JointSystem& js, double joint, double set) {
  REQUIRE(js.joints.size() == 5);  // the [[joints]] entry and z = 2, 4, 6, 8
  for (const slice::Joint& j : js.joints) CHECK(j.tension == (j.set < 0 ? joint : set));
  REQUIRE(js.sets.size() == 1);
  CHECK(js.sets[0].tension == set);
}

}  // namespace

TEST_CASE("tension and [rock] go from the scene through joints.h5", "[unit][scene][h5io]") {
  const slice::Scene scene = slice::parse_scene(kScene, "t.toml");
  CHECK(scene.rock.given);
  CHECK(scene.rock.friction_angle_deg == 45);
  CHECK(scene.rock.cohesion == 2e6);
  CHECK(scene.rock.tension == 1e6);
  const slice::JointSystem js = slice::generate_joints(scene);
  check_tensions(js, 5e4, 1e3);

  test::TempDir dir;
  const auto file = dir / "j.h5";
  slice::write_joints(file, js, {"slice-test", "0", "slice-test", "t.toml", std::string(64, 'a')});
  const slice::JointSystem back = slice::read_joints(file);
  check_tensions(back, 5e4, 1e3);
  CHECK(back.rock.given);
  CHECK(back.rock.friction_angle_deg == 45);
  CHECK(back.rock.cohesion == 2e6);
  CHECK(back.rock.tension == 1e6);

  SECTION("a scene without [rock] writes no /rock; tension defaults to 0") {
    const auto plain = slice::generate_joints(
        slice::parse_scene("[domain]\nbox = { min = [0, 0, 0], max = [1, 1, 1] }\n", "p.toml"));
    slice::write_joints(dir / "p.h5", plain, {"t", "0", "t", "p.toml", std::string(64, 'a')});
    CHECK_FALSE(slice::read_joints(dir / "p.h5").rock.given);
  }
  SECTION("a file from before tension and [rock] reads as tension 0 and no [rock]") {
    {
      slice::h5::File f = slice::h5::File::open(file, {file.string(), ""}, true);
      f.root().open_group("joints").remove("tension");
      f.root().open_group("sets").open_group("000").remove_attribute("tension");
      f.root().remove("rock");
      f.close();
    }
    const slice::JointSystem old = slice::read_joints(file);
    check_tensions(old, 0, 0);
    CHECK_FALSE(old.rock.given);
  }
  SECTION("a negative tension in a file is refused, naming the row") {
    {
      slice::h5::File f = slice::h5::File::open(file, {file.string(), ""}, true);
      const auto g = f.root().open_group("joints");
      auto t = g.read<double>("tension");
      t.at(2) = -1;
      g.remove("tension");
      g.write<double>("tension", t);
      f.close();
    }
    try {
      (void)slice::read_joints(file);
      FAIL("no error");
    } catch (const slice::Error& e) {
      CHECK_THAT(e.what(), Contains("/joints/tension row 2 is -1"));
    }
  }
}

TEST_CASE("bad scene: tension and [rock]", "[unit][scene][bad-input]") {
  const std::string head = kScene.substr(0, kScene.find("[rock]"));
  const std::string joint = "[[joints]]\ndip = 30\ndip_direction = 90\npoint = [5, 5, 5]\n";
  const auto check = [](const std::string& msg, std::initializer_list<std::string> parts) {
    INFO("message: " << msg);
    CHECK(msg.find('\n') == std::string::npos);
    for (const auto& p : parts) CHECK_THAT(msg, Contains(p));
  };
  check(error_of(head + joint + "tension = -1\n"), {"t.toml:7", "'tension'", "< 0", "Pa"});
  check(error_of(head + "[[sets]]\nname = \"B\"\ndip = 0\ndip_direction = 0\nspacing = 1\n" +
                 "tension = -5\n"),
        {"t.toml:8", "'tension'", "[[sets]] \"B\""});
  check(error_of(head + "[rock]\ncohesion = -2\n"), {"t.toml:4", "'cohesion'", "[rock]"});
  check(error_of(head + "[rock]\ntension = -2\n"), {"t.toml:4", "'tension'", "[rock]"});
  check(error_of(head + "[rock]\nfriction_angle = 90\n"), {"t.toml:4", "'friction_angle'"});
  check(error_of(head + "[rock]\ncohesoin = 1\n"), {"t.toml:4", "did you mean 'cohesion'?"});
  check(error_of(head + "[rock]\ntension = \"high\"\n"), {"t.toml:4", "must be a number"});
  check(error_of(head + "[[rock]]\ncohesion = 1\n"), {"t.toml:3", "[rock]"});
}

// The removal zones listed by slice-info (index as slice-extract --near-zone takes it, kind,
// volume in the domain, what each removed, whether it removed rock) and slice-joints' warning
// for a zone above the ground surface, through the real tools on a scene of 2 m cubes whose
// zones and ground lie on joint planes, so every volume has a closed form.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using nlohmann::json;
using test::run_tool;

namespace {

// A 20 x 16 x 12 box cut into 2 m cubes by three persistent sets; the ground is flat at z = 8.
// Zones: 0 a box in the rock, 1 a box half above the ground, 2 a round tunnel (radius 2 about
// z = 10: z 8 to 12) wholly in the air, 3 a cut round tunnel (radius 0.9 about z = 3) in the
// rock, 4 the surface.
const char* kScene = R"([scene]
name = "zones"
[domain]
box = { min = [0, 0, 0], max = [20, 16, 12] }
[[sets]]
name = "x"
dip = 90
dip_direction = 90
spacing = 2
[[sets]]
name = "y"
dip = 90
dip_direction = 0
spacing = 2
[[sets]]
name = "z"
dip = 0
dip_direction = 0
spacing = 2
[[zones]]
box = { min = [4, 4, 2], max = [8, 8, 6] }
[[zones]]
box = { min = [12, 4, 6], max = [16, 8, 10] }
[[zones]]
tunnel = { point = [10, -1, 10], direction = [0, 1, 0], length = 18, radius = 2 }
[[zones]]
tunnel = { point = [10, -1, 3], direction = [0, 1, 0], length = 18, radius = 0.9 }
cut = true
[[zones]]
surface = "ground.obj"
)";

const char* kGround = R"(v -2 -2 8
v 22 -2 8
v 22 18 8
v -2 18 8
f 1 2 3
f 1 3 4
)";

// h5py: the file as written before /zones/kind and the six datasets beside it.
const char* kDropInfo =
    "for k in ['kind', 'entry', 'line', 'cut', 'above_ground', 'volume', "
    "'volume_above_ground']:\n    del f['zones'][k]";

// A 16-gon about a circle of radius r (docs/scenes.md, "Round tunnels"), 16 m long in the domain.
double tunnel_volume(double r) { return 16 * r * r * std::tan(M_PI / 16) * 16; }

json info_json(const std::string& file) {
  const auto r = run_tool("slice-info", {file, "--json"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return json::parse(r.out);
}

struct Files {
  std::string joints, blocks, geom;
  test::ToolRun joints_run;
};

Files make_files(const test::TempDir& tmp) {
  test::write_text(tmp / "s.toml", kScene);
  test::write_text(tmp / "ground.obj", kGround);
  Files f{(tmp / "j.h5").string(), (tmp / "b.h5").string(), (tmp / "g.h5").string(), {}};
  f.joints_run = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", f.joints});
  INFO(f.joints_run.err);
  REQUIRE(f.joints_run.exit_code == 0);
  REQUIRE(run_tool("slice-cut", {f.joints, "-o", f.blocks, "--prune"}).exit_code == 0);
  REQUIRE(run_tool("slice-vertices", {f.blocks, "-o", f.geom}).exit_code == 0);
  return f;
}

}  // namespace

TEST_CASE("slice-joints warns of a zone partly or wholly above the ground and not of one below",
          "[zones][info]") {
  const test::TempDir tmp;
  const Files f = make_files(tmp);
  const std::string& err = f.joints_run.err;
  CHECK_THAT(err, Contains("slice-joints: warning: [[zones]] #2 (box, line 22; zone 1) lies "
                           "partly above the ground surface ([[zones]] #5): 32 of its 64 in the "
                           "domain (50.0 %) is air, where it removes no rock"));
  CHECK_THAT(err, Contains("slice-joints: warning: [[zones]] #3 (tunnel, line 24; zone 2) lies "
                           "wholly above the ground surface ([[zones]] #5): all 203.686 of its "
                           "volume in the domain is air, so it removes no rock"));
  CHECK(err.find("#1 (") == std::string::npos);  // the box below the ground
  CHECK(err.find("#4 (") == std::string::npos);  // the tunnel below it
  // A warning, not chatter: -q keeps it.
  const auto quiet =
      run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", (tmp / "q.h5").string(), "-q"});
  CHECK(quiet.exit_code == 0);
  CHECK(quiet.err.find("warning: [[zones]] #2") != std::string::npos);
  CHECK(quiet.err.find("warning: [[zones]] #3") != std::string::npos);
}

TEST_CASE("slice-info lists each zone's kind and volume and what it removed", "[zones][info]") {
  const test::TempDir tmp;
  const Files f = make_files(tmp);
  const double box = 4 * 4 * 4, air_tunnel = tunnel_volume(2), rock_tunnel = tunnel_volume(0.9);

  SECTION("geom.h5: volumes removed, exact where the zone's faces are joints") {
    const json j = info_json(f.geom);
    CHECK(j["zones"] == 4);  // the counts stay as they were
    CHECK(j["zone_meshes"] == 1);
    const json& z = j["removal_zones"];
    REQUIRE(z.size() == 5);
    const char* kinds[] = {"box", "box", "tunnel", "tunnel", "surface"};
    const int lines[] = {20, 22, 24, 26, 29};
    for (int k = 0; k < 5; ++k) {
      CAPTURE(k);
      CHECK(z[k]["index"] == k);
      CHECK(z[k]["kind"] == kinds[k]);
      CHECK(z[k]["entry"] == k);
      CHECK(z[k]["line"] == lines[k]);
      CHECK(z[k]["cut"] == (k == 3));
    }
    // Zone 0, a box in the rock: 8 cubes.
    CHECK_THAT(z[0]["volume"].get<double>(), WithinRel(box, 1e-12));
    CHECK(z[0]["above_ground"] == "below");
    CHECK(z[0]["removed_blocks"] == 8);
    CHECK_THAT(z[0]["removed_volume"].get<double>(), WithinRel(box, 1e-9));
    CHECK(z[0]["removed_rock"] == true);
    CHECK(z[0]["warning"].is_null());
    // Zone 1, half above the ground: the cubes above belong to the surface (air).
    CHECK_THAT(z[1]["volume"].get<double>(), WithinRel(box, 1e-12));
    CHECK(z[1]["above_ground"] == "partly above");
    CHECK_THAT(z[1]["volume_above_ground"].get<double>(), WithinRel(box / 2, 1e-12));
    CHECK(z[1]["removed_blocks"] == 4);
    CHECK_THAT(z[1]["removed_volume"].get<double>(), WithinRel(box / 2, 1e-9));
    CHECK(z[1]["removed_rock"] == true);
    CHECK_THAT(z[1]["warning"].get<std::string>(), Contains("partly above the ground"));
    // Zone 2, in the air: no rock, though blocks' centres lie in it.
    CHECK_THAT(z[2]["volume"].get<double>(), WithinRel(air_tunnel, 1e-12));
    CHECK(z[2]["above_ground"] == "wholly above");
    CHECK_THAT(z[2]["volume_above_ground"].get<double>(), WithinRel(air_tunnel, 1e-12));
    CHECK(z[2]["removed_blocks"] == 0);
    CHECK(z[2]["removed_volume"] == 0.0);
    CHECK(z[2]["removed_rock"] == false);
    CHECK_THAT(z[2]["warning"].get<std::string>(), Contains("wholly above the ground"));
    // Zone 3, cut into the rock: exactly its prism.
    CHECK_THAT(z[3]["volume"].get<double>(), WithinRel(rock_tunnel, 1e-12));
    CHECK(z[3]["above_ground"] == "below");
    CHECK_THAT(z[3]["volume_above_ground"].get<double>(), WithinAbs(0, 1e-12));
    CHECK_THAT(z[3]["removed_volume"].get<double>(), WithinRel(rock_tunnel, 1e-9));
    CHECK(z[3]["removed_rock"] == true);
    // Zone 4, the surface: the air above z = 8, which it removes: no rock.
    CHECK_THAT(z[4]["volume"].get<double>(), WithinRel(20.0 * 16 * 4, 1e-12));
    CHECK(z[4]["above_ground"] == "not checked");
    CHECK(z[4]["removed_blocks"] == 10 * 8 * 2);
    CHECK_THAT(z[4]["removed_volume"].get<double>(), WithinRel(20.0 * 16 * 4, 1e-9));
    CHECK(z[4]["removed_rock"] == false);
    // Every removed block has one owner.
    double sum = j["removed_outside_zones"]["volume"].get<double>();
    for (const auto& e : z) sum += e["removed_volume"].get<double>();
    CHECK_THAT(sum, WithinRel(j["geometry"]["removed_volume"].get<double>(), 1e-12));

    const auto text = run_tool("slice-info", {f.geom});
    REQUIRE(text.exit_code == 0);
    CHECK_THAT(text.out, Contains("removal zones (index: as slice-extract --near-zone takes it):\n"
                                  "  0  box, [[zones]] #1 (line 20): 64 in the domain, below the "
                                  "ground; removed 8 blocks, 64, rock\n"));
    CHECK_THAT(text.out, Contains("  1  box, [[zones]] #2 (line 22): 64 in the domain, 32 of it "
                                  "above the ground; removed 4 blocks, 32, rock\n"));
    CHECK_THAT(text.out, Contains("  2  tunnel, [[zones]] #3 (line 24): 203.686 in the domain, "
                                  "wholly above the ground; removed 0 blocks, 0, no rock\n"));
    CHECK_THAT(text.out, Contains("  4  surface, [[zones]] #5 (line 29): 1280 in the domain; "
                                  "removed 160 blocks, 1280, the air above the ground\n"));
    CHECK_THAT(text.out, Contains("warning: [[zones]] #3 (tunnel, line 24; zone 2) lies wholly"));
    CHECK(text.out.find("\"removal_zones\"") == std::string::npos);  // not listed twice
  }

  SECTION("joints.h5: kinds and volumes in the domain; what was removed needs blocks") {
    const json j = info_json(f.joints);
    const json& z = j["removal_zones"];
    REQUIRE(z.size() == 5);
    CHECK(z[2]["kind"] == "tunnel");
    CHECK_THAT(z[2]["volume"].get<double>(), WithinRel(air_tunnel, 1e-12));
    for (const auto& e : z) {
      CHECK(e["removed_blocks"].is_null());
      CHECK(e["removed_volume"].is_null());
      CHECK(e["removed_rock"].is_null());
    }
    CHECK(j["removed_outside_zones"].is_null());
    const auto text = run_tool("slice-info", {f.joints});
    CHECK_THAT(text.out, Contains("what each zone removed needs blocks (slice-cut), its volume "
                                  "geom.h5 (slice-vertices)"));
  }

  SECTION("blocks.h5: blocks removed, no volumes") {
    const json j = info_json(f.blocks);
    const json& z = j["removal_zones"];
    CHECK(z[0]["removed_blocks"] == 8);
    CHECK(z[0]["removed_volume"].is_null());
    CHECK(z[0]["removed_rock"] == true);
    CHECK(z[2]["removed_rock"] == false);
  }

  SECTION("a file from before /zones/kind still reads: kinds unknown, the first zone owns") {
    const auto old = tmp / "old.h5";
    std::filesystem::copy_file(f.geom, old);
    test::edit_h5(old, kDropInfo);
    const json j = info_json(old.string());
    const json& z = j["removal_zones"];
    REQUIRE(z.size() == 5);
    for (const auto& e : z) {
      CHECK(e["kind"] == "unknown");
      CHECK(e["entry"].is_null());
      CHECK(e["above_ground"] == "not checked");
      CHECK(e["warning"].is_null());
    }
    // Without kinds the surface has no precedence: the zones listed first take the air's cubes.
    CHECK_THAT(z[1]["removed_volume"].get<double>(), WithinRel(box, 1e-9));
    CHECK_THAT(z[2]["removed_volume"].get<double>(), WithinRel(2 * 8 * 2 * 8.0, 1e-9));
    CHECK_THAT(z[4]["removed_volume"].get<double>(),
               WithinRel(20.0 * 16 * 4 - box / 2 - 256, 1e-9));
    // And an old joints.h5 still slices.
    const auto old_joints = tmp / "old-j.h5";
    std::filesystem::copy_file(f.joints, old_joints);
    test::edit_h5(old_joints, kDropInfo);
    const auto cut =
        run_tool("slice-cut", {old_joints.string(), "-o", (tmp / "old-b.h5").string()});
    INFO(cut.err);
    CHECK(cut.exit_code == 0);
    CHECK(info_json((tmp / "old-b.h5").string())["removal_zones"][0]["kind"] == "unknown");
    // Damaged files: a kind that is none, a region called a mesh, some of the seven datasets
    // without the others.
    const auto bad = (tmp / "bad.h5").string();
    const auto edited = [&](const std::string& edit) {
      std::filesystem::copy_file(f.geom, bad, std::filesystem::copy_options::overwrite_existing);
      test::edit_h5(bad, edit);
      return run_tool("slice-info", {bad});
    };
    test::check_refused(edited("f['zones/kind'][0] = 7"), "slice-info",
                        {"bad.h5", "/zones/kind row 0 is 7", "expected 0 box"});
    test::check_refused(edited("f['zones/kind'][0] = 3"), "slice-info",
                        {"/zones/kind row 0 is mesh but zone 0 is a region of half-spaces"});
    test::check_refused(edited("f['zones/cut'][1] = 2"), "slice-info",
                        {"/zones/cut row 1 is 2; expected 0 or 1"});
    test::check_refused(edited("del f['zones']['cut']"), "slice-info", {"/zones/cut is missing"});
  }
}

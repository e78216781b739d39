// Stochastic scenes through the real tools: the full pipeline on the paper's Table 3 scene with
// the slicer's invariants checked, byte-identical reruns, /sets in the files, bad input, plots.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "support/blocks_check.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using test::run_tool;

TEST_CASE("table3-lognormal: slice-joints, slice-cut, slice-prune -- the invariants hold",
          "[tools][stochastic]") {
  test::TempDir tmp;
  const auto joints = test::run_pipeline(tmp, "table3-lognormal.toml", test::Stage::joints);
  const auto blocks = (tmp / "blocks.h5").string(), pruned = (tmp / "pruned.h5").string();
  const auto cut = run_tool("slice-cut", {joints, "-o", blocks});
  INFO(cut.err);
  REQUIRE(cut.exit_code == 0);
  REQUIRE(run_tool("slice-prune", {blocks, "-o", pruned}).exit_code == 0);
  const auto bs = slice::read_blocks(pruned);
  CHECK(bs.pruned);
  // The data file's comment quotes this count (seed 2015).
  CHECK(bs.blocks.size() == 12599);
  CHECK(bs.joints.sets.size() == 3);
  for (const auto& s : bs.joints.sets) {
    CHECK(s.intensity == slice::SetIntensity::density);
    CHECK(s.size.distribution == slice::SizeDistribution::lognormal);
    CHECK(s.joint_count > 1000);
  }
  // Volumes add up to the domain's, points lie in exactly one block, no two blocks overlap,
  // every block has an inradius.
  const auto rep = test::check_invariants(bs, 20000, 8);
  CHECK(rep.overlapping_pairs == 0);
  CHECK(rep.pairs_checked > 0);
}

TEST_CASE("stochastic scenes give byte-identical joints.h5 and blocks.h5 on a rerun",
          "[tools][stochastic]") {
  test::TempDir tmp;
  for (const char* scene : {"table3-lognormal.toml", "genesis-limestone.toml"}) {
    CAPTURE(scene);
    const std::string in = test::data_path(scene).string();
    const std::string j = (tmp / "j.h5").string(), b = (tmp / "b.h5").string();
    REQUIRE(run_tool("slice-joints", {in, "-o", j}).exit_code == 0);
    const std::string first = test::read_bytes(j);
    REQUIRE(run_tool("slice-joints", {in, "-o", j}).exit_code == 0);
    CHECK(test::read_bytes(j) == first);
    if (std::string(scene) == "genesis-limestone.toml") {  // the smaller one through slice-cut
      REQUIRE(run_tool("slice-cut", {j, "-o", b, "--prune"}).exit_code == 0);
      const std::string blocks = test::read_bytes(b);
      REQUIRE(run_tool("slice-cut", {j, "-o", b, "--prune"}).exit_code == 0);
      CHECK(test::read_bytes(b) == blocks);
    }
  }
}

TEST_CASE("genesis-limestone: four sets, each intensity met, introduced set by set",
          "[tools][stochastic]") {
  test::TempDir tmp;
  const auto js =
      slice::read_joints(test::run_pipeline(tmp, "genesis-limestone.toml", test::Stage::joints));
  REQUIRE(js.sets.size() == 4);
  CHECK(js.options.order == slice::JointOrder::by_set);
  using I = slice::SetIntensity;
  CHECK(js.sets[0].intensity == I::count);
  CHECK(js.sets[0].joint_count == 12);
  CHECK(js.sets[1].intensity == I::p32);
  CHECK_THAT(js.sets[1].achieved_p32, Catch::Matchers::WithinRel(0.12, 0.02));
  CHECK(js.sets[2].intensity == I::p10);
  CHECK_THAT(js.sets[2].achieved_p10, Catch::Matchers::WithinRel(0.4, 0.02));
  CHECK(js.sets[3].intensity == I::density);
  CHECK(js.sets[0].rotation_fixed);
  CHECK(js.sets[3].shape == slice::JointShape::ellipse);
  int last = 0;
  for (const auto& j : js.joints) {  // by-set: never back to an earlier set
    CHECK(j.set >= last);
    last = j.set;
  }
  const auto info = run_tool("slice-info", {(tmp / "joints.h5").string(), "--json"});
  REQUIRE(info.exit_code == 0);
  const auto j = nlohmann::json::parse(info.out);
  CHECK(j["joints"]["by_set"][2]["intensity"] == "p10");
  CHECK(j["joints"]["by_set"][2]["p10"] == js.sets[2].achieved_p10);
}

TEST_CASE("bad stochastic sets: exit 1, one line, nothing written", "[tools][stochastic]") {
  const std::string set =
      "[domain]\nbox = { min = [0, 0, 0], max = [4, 4, 4] }\n"
      "[[sets]]\nname = \"J1\"\ndip = 5\ndip_direction = 0\n";  // lines 1-6
  const std::string size = "size = { distribution = \"lognormal\", mean = 1.0, sd = 0.5 }\n";
  const std::vector<test::BadScene> cases = {
      {"negative sd",
       set + "density = 0.1\nsize = { distribution = \"lognormal\", mean = 1.0, sd = -0.5 }\n",
       {":8", "'sd'", "-0.5"}},
      {"kappa below 0",
       set + "fisher_kappa = -1\ndensity = 0.1\n" + size,
       {":7", "fisher_kappa", "below 0"}},
      {"p32 with no size", set + "p32 = 0.5\n", {":7", "p32", "no 'size'"}},
      {"scanline outside the domain",
       set + "p10 = 2\nscanline = { from = [-1, 2, 2], to = [3, 2, 2] }\n" + size,
       {":8", "scanline", "leaves the domain", "'from'"}},
      {"more than max_joints",
       set + "density = 1e6\n" + size,
       {":7", "more than max_joints = 1000000"}},
      {"more than a lower max_joints",
       "[scene]\nmax_joints = 50\n" + set + "count = 60\n" + size,
       {":9", "more than max_joints = 50"}},
  };
  test::check_bad_scenes(cases);
}

TEST_CASE("pipelines/plot draws the stereonet, sizes and volumes", "[tools][stochastic][plot]") {
  // pipelines/setup installs h5py and matplotlib: without them this test fails, not skips.
  REQUIRE(test::run_shell("/usr/bin/python3 -c 'import h5py, matplotlib' >/dev/null 2>&1") == 0);
  test::TempDir tmp;
  const auto joints = test::run_pipeline(tmp, "genesis-limestone.toml", test::Stage::joints);
  const auto blocks = (tmp / "blocks.h5").string();
  REQUIRE(run_tool("slice-cut", {joints, "-o", blocks, "--prune"}).exit_code == 0);
  const std::string plot = (test::data_path("..") / "pipelines" / "plot").string();
  const std::string cmd = "/usr/bin/python3 '" + plot + "' '" + blocks + "' -o '" +
                          (tmp / "png").string() + "' 2>/dev/null";
  REQUIRE(test::run_shell(cmd) == 0);
  for (const char* png : {"blocks-stereonet.png", "blocks-sizes.png", "blocks-volumes.png"}) {
    CAPTURE(png);
    const std::string bytes = test::read_bytes(tmp / "png" / png);
    REQUIRE(bytes.size() > 1000);
    CHECK(bytes.substr(1, 3) == "PNG");
  }
  // A file that is not a rockslice file: exit 1.
  test::write_text(tmp / "x.h5", "not hdf5");
  CHECK(test::run_shell("/usr/bin/python3 '" + plot + "' '" + (tmp / "x.h5").string() + "' -o '" +
                        (tmp / "png").string() + "' 2>/dev/null") != 0);
}

// Issue 13 item 5: realization sweeps set the seed on the command line.
TEST_CASE("slice-joints --seed N overrides [scene] seed", "[tools][stochastic]") {
  test::TempDir tmp;
  std::string scene = test::read_bytes(test::data_path("table3-lognormal.toml"));
  const auto at = scene.find("seed = 2015");
  REQUIRE(at != std::string::npos);
  const std::string given = (tmp / "given.h5").string(), flag = (tmp / "flag.h5").string(),
                    other = (tmp / "other.h5").string();
  // The scene with seed = 7 written in it, and the original with --seed 7, draw the same joints.
  std::string seven = scene;
  seven.replace(at, 11, "seed = 7   ");
  test::write_text(tmp / "seven.toml", seven);
  REQUIRE(run_tool("slice-joints", {(tmp / "seven.toml").string(), "-o", given}).exit_code == 0);
  const auto r = run_tool("slice-joints", {test::data_path("table3-lognormal.toml").string(), "-o",
                                           flag, "--seed", "7"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.err, Catch::Contains("seed 7"));
  REQUIRE(run_tool("slice-joints", {test::data_path("table3-lognormal.toml").string(), "-o", other})
              .exit_code == 0);
  const auto a = slice::read_joints(given), b = slice::read_joints(flag),
             c = slice::read_joints(other);
  CHECK(b.seed == 7);
  CHECK(c.seed == 2015);
  REQUIRE(a.joints.size() == b.joints.size());
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    CHECK(a.joints[i].centre == b.joints[i].centre);
    CHECK(a.joints[i].plane.normal == b.joints[i].plane.normal);
  }
  CHECK((c.joints.size() != b.joints.size() || c.joints[0].centre != b.joints[0].centre));
  // Not a seed: exit 1, one line, nothing written.
  for (const char* bad : {"-1", "x", "1.5"}) {
    CAPTURE(bad);
    const auto e = run_tool("slice-joints", {test::data_path("table3-lognormal.toml").string(),
                                             "-o", (tmp / "bad.h5").string(), "--seed", bad});
    CHECK(e.exit_code == 1);
    CHECK_FALSE(test::fs::exists(tmp / "bad.h5"));
  }
}

// Field data as it is mapped (issue 26, item 6) through the real tools: a regular set with
// Fisher scatter (planes that cross inside the domain) cut into blocks whose invariants hold;
// the traces on a mapping window printed by slice-joints and shown by slice-info; bad input.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "support/blocks_check.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using test::run_tool;

namespace {

// Two regular sets, one scattered, and a stochastic set of discs mapped on a vertical wall.
const std::string kScene = R"([scene]
name = "mapped"
seed = 31
[domain]
box = { min = [0, 0, 0], max = [20, 20, 20] }
[[sets]]
name = "bedding"
dip = 10
dip_direction = 140
spacing = 2.5
fisher_kappa = 25
mapping = { point = [10, 10, 10], dip = 90, dip_direction = 180, width = 16, height = 12 }
[[sets]]
name = "J1"
dip = 80
dip_direction = 60
spacing = 4
[[sets]]
name = "J2"
dip = 70
dip_direction = 300
density = 0.01
size = { distribution = "lognormal", mean = 6, sd = 2 }
shape = "polygon"
sides = 12
mapping = { point = [10, 10, 10], dip = 90, dip_direction = 180, width = 16, height = 12 }
trace_length = { mean = 4.2, sd = 1.9 }
)";

}  // namespace

TEST_CASE("a regular set with Fisher scatter is cut into valid blocks and its traces reported",
          "[tools][field]") {
  test::TempDir tmp;
  test::write_text(tmp / "s.toml", kScene);
  const std::string joints = (tmp / "j.h5").string(), blocks = (tmp / "b.h5").string();
  const auto run = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", joints});
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto js = slice::read_joints(joints);
  // The scattered planes are not parallel: some pair meets inside the domain. Over each
  // corner (x, y) of the domain's plan, the height of a plane is (d - n_x x - n_y y) / n_z; two
  // planes cross inside when their order swaps between corners where both are in the domain.
  std::vector<const slice::Joint*> planes;
  for (const auto& j : js.joints)
    if (j.set == 0) planes.push_back(&j);
  const auto height = [](const slice::Joint& j, double x, double y) {
    return (j.plane.d - j.plane.normal.x() * x - j.plane.normal.y() * y) / j.plane.normal.z();
  };
  std::size_t crossing = 0;
  for (std::size_t a = 0; a < planes.size(); ++a)
    for (std::size_t b = a + 1; b < planes.size(); ++b) {
      int below = 0, above = 0;
      for (int k = 0; k < 4; ++k) {
        const double x = (k & 1) ? 20 : 0, y = (k & 2) ? 20 : 0;
        const double za = height(*planes[a], x, y), zb = height(*planes[b], x, y);
        if (za < 0 || za > 20 || zb < 0 || zb > 20) continue;
        (za < zb ? below : above) += 1;
      }
      crossing += below > 0 && above > 0 ? 1 : 0;
    }
  const std::size_t bedding = planes.size();
  // As many planes as without scatter: they keep their places.
  std::string plain_text = kScene;
  plain_text.erase(plain_text.find("fisher_kappa = 25\n"), 18);
  const auto plain = slice::generate_joints(slice::parse_scene(plain_text, "plain.toml"));
  std::size_t plain_bedding = 0;
  for (const auto& j : plain.joints) plain_bedding += j.set == 0 ? 1 : 0;
  CHECK(bedding == plain_bedding);
  CHECK(bedding > 5);
  CHECK(crossing > 0);
  // slice-joints says, per mapped set, what the traces are and what was mapped.
  CHECK_THAT(run.err, Contains("set \"bedding\": " + std::to_string(js.sets[0].traces.count) +
                               " traces on its mapping window"));
  CHECK_THAT(run.err, Contains("set \"J2\": " + std::to_string(js.sets[2].traces.count) +
                               " traces on its mapping window"));
  CHECK_THAT(run.err, Contains("(mapped: mean 4.2, sd 1.9)"));
  CHECK(run.err.find("set \"J1\"") == std::string::npos);

  const auto cut = run_tool("slice-cut", {joints, "-o", blocks, "--prune"});
  INFO(cut.err);
  REQUIRE(cut.exit_code == 0);
  const auto bs = slice::read_blocks(blocks);
  CHECK(bs.blocks.size() > 100);
  const auto rep = test::check_invariants(bs, 20000, 5);
  CHECK(rep.overlapping_pairs == 0);
  CHECK(rep.pairs_checked > 0);

  const auto info = run_tool("slice-info", {joints, "--json"});
  REQUIRE(info.exit_code == 0);
  const auto j = nlohmann::json::parse(info.out);
  const auto& sets = j["joints"]["by_set"];
  REQUIRE(sets.size() == 3);
  CHECK_FALSE(sets[1].contains("traces"));
  const auto& t = sets[2]["traces"];
  CHECK(t["count"] == js.sets[2].traces.count);
  CHECK(t["mean"] == js.sets[2].traces.mean);
  CHECK(t["sd"] == js.sets[2].traces.sd);
  CHECK(t["p21"] == js.sets[2].traces.p21);
  CHECK(t["censored"][2] == js.sets[2].traces.censored[2]);
  CHECK(t["mapped_mean"] == 4.2);
  CHECK(t["mapped_sd"] == 1.9);
  CHECK(t["window"]["width"] == 16);
  CHECK(sets[0]["traces"]["mapped_mean"].is_null());
  CHECK(sets[0]["traces"]["censored"][2] == sets[0]["traces"]["count"]);
  // The blocks file carries the joints, and their traces, along.
  const auto info_b = run_tool("slice-info", {blocks, "--json"});
  REQUIRE(info_b.exit_code == 0);
  CHECK(nlohmann::json::parse(info_b.out)["joints"]["by_set"][2]["traces"]["count"] ==
        js.sets[2].traces.count);
}

TEST_CASE("bad mapping windows: exit 1, one line, nothing written", "[tools][field][bad-input]") {
  const std::string head =
      "[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 20] }\n[[sets]]\nname = \"J1\"\n"
      "dip = 70\ndip_direction = 300\ndensity = 0.01\n"
      "size = { distribution = \"fixed\", value = 3 }\n";  // 8 lines
  test::check_bad_scenes({
      {"window outside the domain",
       head + "mapping = { point = [10, 10, 10], dip = 90, dip_direction = 180, width = 16, "
              "height = 24 }\n",
       {"bad.toml:9", "mapping window", "leaves the domain"}},
      {"trace_length without a window",
       head + "trace_length = { mean = 3 }\n",
       {"bad.toml:9", "'trace_length'", "add mapping"}},
      {"a negative mapped mean",
       head + "mapping = { point = [10, 10, 10], dip = 90, dip_direction = 180, width = 16, "
              "height = 12 }\ntrace_length = { mean = -3 }\n",
       {"bad.toml:10", "'mean'"}},
  });
}

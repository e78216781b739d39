// The real tools on real files: exit codes, messages, outputs, determinism.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "slice/h5io.hpp"
#include "slice/hash.hpp"
#include "slice/scene.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using test::run_tool;

namespace {

const char* kGoodScene = R"([scene]
name = "two-sets"
[domain]
box = { min = [0, 0, 0], max = [4, 4, 4] }
[[sets]]
name = "A"
dip = 0
dip_direction = 0
spacing = 1.0
[[sets]]
name = "B"
dip = 90
dip_direction = 90
spacing = 2.0
)";

nlohmann::json info_json(const test::fs::path& file) {
  const auto r = run_tool("slice-info", {file.string(), "--json"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return nlohmann::json::parse(r.out);
}

}  // namespace

TEST_CASE("every tool answers --help and --version with exit 0", "[tools]") {
  for (const char* t : {"slice-joints", "slice-info"}) {
    CAPTURE(t);
    const auto help = run_tool(t, {"--help"});
    CHECK(help.exit_code == 0);
    CHECK_THAT(help.out, Catch::Contains("Usage"));
    const auto version = run_tool(t, {"--version"});
    CHECK(version.exit_code == 0);
    CHECK_THAT(version.out, Catch::Contains("rockslice"));
    const auto bad = run_tool(t, {"--no-such-option"});
    CHECK(bad.exit_code == 1);
  }
}

TEST_CASE("slice-joints writes joints.h5 that slice-info and h5dump read", "[tools]") {
  test::TempDir tmp;
  test::write_text(tmp / "s.toml", kGoodScene);
  const auto r =
      run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", (tmp / "j.h5").string()});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_FALSE(test::fs::exists(tmp / "j.h5.partial"));
  const auto j = info_json(tmp / "j.h5");
  CHECK(j["kind"] == "joints");
  CHECK(j["schema"] == "rockslice");
  CHECK(j["schema_version"] == 1);
  CHECK(j["joints"]["total"] == 3 + 1);  // z = 1, 2, 3 and x = 2
  CHECK(j["joints"]["by_set"][0]["joints"] == 3);
  CHECK(j["joints"]["by_set"][1]["joints"] == 1);
  CHECK_THAT(j["domain"]["volume"].get<double>(), Catch::Matchers::WithinRel(64.0, 1e-12));
  CHECK(j["provenance"]["tool"] == "slice-joints");
  CHECK(j["provenance"]["input_sha256"] == slice::sha256_file(tmp / "s.toml"));
  CHECK(test::run_shell("h5dump " + (tmp / "j.h5").string() + " >/dev/null 2>&1") == 0);

  const auto text = run_tool("slice-info", {(tmp / "j.h5").string()});
  CHECK(text.exit_code == 0);
  CHECK_THAT(text.out, Catch::Contains("kind: joints"));
}

TEST_CASE("slice-joints output is byte-identical on a rerun", "[tools]") {
  test::TempDir tmp;
  for (const char* scene : {"cube-3sets.toml", "table3-persistent.toml", "rock-slope.toml",
                            "table3-lognormal.toml", "genesis-limestone.toml"}) {
    CAPTURE(scene);
    const std::string in = test::data_path(scene).string();
    // Same command line both times: provenance records it.
    REQUIRE(run_tool("slice-joints", {in, "-o", (tmp / "a.h5").string()}).exit_code == 0);
    const std::string first = test::read_bytes(tmp / "a.h5");
    REQUIRE(run_tool("slice-joints", {in, "-o", (tmp / "a.h5").string()}).exit_code == 0);
    CHECK(test::read_bytes(tmp / "a.h5") == first);
  }
}

TEST_CASE("the example scenes give the expected joints", "[tools]") {
  test::TempDir tmp;
  SECTION("cube-3sets: three orthogonal sets at 1 m, nine planes each") {
    REQUIRE(run_tool("slice-joints",
                     {test::data_path("cube-3sets.toml").string(), "-o", (tmp / "j.h5").string()})
                .exit_code == 0);
    const auto j = info_json(tmp / "j.h5");
    CHECK(j["joints"]["total"] == 27);
    CHECK(j["joints"]["persistent"] == 27);
    CHECK(j["joints"]["by_set"].size() == 3);
    for (const auto& s : j["joints"]["by_set"]) CHECK(s["joints"] == 9);
    CHECK_THAT(j["domain"]["volume"].get<double>(), Catch::Matchers::WithinRel(1000.0, 1e-12));
  }
  SECTION("table3-persistent: 103 planes at 3.7 m (reference/table3-block-counts.md)") {
    REQUIRE(run_tool("slice-joints", {test::data_path("table3-persistent.toml").string(), "-o",
                                      (tmp / "j.h5").string()})
                .exit_code == 0);
    const auto j = info_json(tmp / "j.h5");
    CHECK(j["joints"]["total"] == 103);
    CHECK(j["joints"]["by_kind"]["rock"] == 103);
    CHECK_THAT(j["domain"]["volume"].get<double>(), Catch::Matchers::WithinRel(1e6, 1e-12));
  }
  SECTION("rock-slope: every joint kind, polygons, a zone, a non-box domain") {
    REQUIRE(run_tool("slice-joints",
                     {test::data_path("rock-slope.toml").string(), "-o", (tmp / "j.h5").string()})
                .exit_code == 0);
    const auto j = info_json(tmp / "j.h5");
    CHECK(j["joints"]["total"] == 22);
    CHECK(j["joints"]["persistent"] == 19);
    CHECK(j["joints"]["polygons"] == 3);
    CHECK(j["joints"]["deterministic"] == 5);
    CHECK(j["joints"]["by_kind"]["boundary"] == 1);
    CHECK(j["joints"]["by_kind"]["construction"] == 1);
    CHECK(j["joints"]["by_kind"]["rock"] == 20);
    CHECK(j["joints"]["by_set"][0]["joints"] == 12);  // bedding
    CHECK(j["joints"]["by_set"][1]["joints"] == 5);   // cross joints
    CHECK(j["zones"] == 1);
    CHECK(j["domain"]["planes"] == 6);
    CHECK_THAT(j["domain"]["volume"].get<double>(), Catch::Matchers::WithinRel(19500.0, 1e-12));
  }
}

TEST_CASE("bad input: exit 1, one line naming file, line and key, nothing written", "[tools]") {
  const std::string box = "[domain]\nbox = { min = [0, 0, 0], max = [4, 4, 4] }\n";
  const std::vector<test::BadScene> cases = {
      {"unknown key",
       box + "[[sets]]\ndip = 0\ndip_direction = 0\nspaceing = 1.0\n",
       {":6", "spaceing", "spacing"}},
      {"wrong type",
       box + "[[sets]]\ndip = \"steep\"\ndip_direction = 0\nspacing = 1.0\n",
       {":4", "dip"}},
      {"dip above 90",
       box + "[[sets]]\ndip = 95\ndip_direction = 0\nspacing = 1.0\n",
       {":4", "dip"}},
      {"dip direction 360",
       box + "[[sets]]\ndip = 5\ndip_direction = 360\nspacing = 1.0\n",
       {":5", "dip_direction"}},
      {"negative spacing",
       box + "[[sets]]\ndip = 5\ndip_direction = 0\nspacing = -1.0\n",
       {":6", "spacing"}},
      {"NaN", box + "[[sets]]\ndip = nan\ndip_direction = 0\nspacing = 1.0\n", {":4", "dip"}},
      {"box min >= max", "[domain]\nbox = { min = [0, 0, 0], max = [4, 0, 4] }\n", {":2", "box"}},
      {"no intensity",
       box + "[[sets]]\ndip = 5\ndip_direction = 0\nfisher_kappa = 20\n",
       {":3", "missing key 'spacing'", "density"}},
      // A regular set takes Fisher scatter (issue 26), but not a negative concentration.
      {"a negative fisher_kappa on a regular set",
       box + "[[sets]]\ndip = 5\ndip_direction = 0\nspacing = 1.0\nfisher_kappa = -20\n",
       {":7", "fisher_kappa", "below 0"}},
      {"TOML syntax", box + "[[sets]\n", {":3"}},
  };
  test::check_bad_scenes(cases);
}

TEST_CASE("bad input leaves an existing output untouched", "[tools]") {
  test::TempDir tmp;
  test::write_text(tmp / "good.toml", kGoodScene);
  test::write_text(tmp / "bad.toml", std::string(kGoodScene) + "spaceing = 3\n");
  REQUIRE(run_tool("slice-joints", {(tmp / "good.toml").string(), "-o", (tmp / "j.h5").string()})
              .exit_code == 0);
  const std::string before = test::read_bytes(tmp / "j.h5");
  const auto r =
      run_tool("slice-joints", {(tmp / "bad.toml").string(), "-o", (tmp / "j.h5").string()});
  CHECK(r.exit_code == 1);
  CHECK(test::read_bytes(tmp / "j.h5") == before);
  SECTION("a missing scene file") {
    const auto m =
        run_tool("slice-joints", {(tmp / "nope.toml").string(), "-o", (tmp / "j.h5").string()});
    CHECK(m.exit_code == 1);
    CHECK_THAT(m.err, Catch::Contains("nope.toml"));
    CHECK(test::read_bytes(tmp / "j.h5") == before);
  }
  SECTION("the output path is the input") {
    const auto m = run_tool("slice-joints",
                            {(tmp / "good.toml").string(), "-o", (tmp / "good.toml").string()});
    CHECK(m.exit_code == 1);
    CHECK(test::read_bytes(tmp / "good.toml") == kGoodScene);
  }
}

TEST_CASE("slice-info refuses what is not a rockslice file", "[tools]") {
  test::TempDir tmp;
  test::write_text(tmp / "x.h5", "not hdf5 at all");
  const auto r = run_tool("slice-info", {(tmp / "x.h5").string()});
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::Contains("x.h5"));
  const auto m = run_tool("slice-info", {(tmp / "missing.h5").string()});
  CHECK(m.exit_code == 1);
  CHECK_THAT(m.err, Catch::Contains("missing.h5"));
}

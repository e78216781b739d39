// Issue 14: pipelines/Snakefile reruns only what changed. Snakemake (Debian's 7.21) must be
// installed (pipelines/setup does it): a missing snakemake fails this test, it does not skip.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "support/support.hpp"

namespace {

using test::fs::path;

const path kRoot = path(SLICE_TEST_DATA_DIR).parent_path().parent_path();

void write_config(const test::TempDir& tmp, const std::string& scene,
                  const std::string& vtu_options) {
  test::write_text(tmp / "config.yaml",
                   "scenes:\n  cube: " + scene + "\nseeds: [1]\nout: " + (tmp / "out").string() +
                       "\ntools: " + SLICE_TOOLS_DIR + "\ncut_options: \"--prune\"\n" +
                       "vertices_options: \"\"\nexports: [vtu]\nvtu_options: \"" + vtu_options +
                       "\"\nyade_options: \"\"\nplots: false\nsummary: false\n");
}

// Runs the workflow; returns its log (stdout and stderr).
std::string snakemake(const test::TempDir& tmp, const std::string& options = "--cores 1") {
  const path log = tmp / "snakemake.log";
  const int code = test::run_shell("cd " + test::shell_quote(tmp.path()) + " && snakemake -s " +
                                   test::shell_quote(kRoot / "pipelines" / "Snakefile") +
                                   " --configfile " + test::shell_quote(tmp / "config.yaml") + " " +
                                   options + " > " + test::shell_quote(log) + " 2>&1");
  const std::string out = test::read_bytes(log);
  INFO(out);
  REQUIRE(code == 0);
  return out;
}

bool ran(const std::string& log, const std::string& rule) {
  return log.find("rule " + rule + ":") != std::string::npos;
}

}  // namespace

TEST_CASE("the Snakemake workflow reruns only what changed", "[tools][workflow][snakemake]") {
  test::TempDir tmp;
  const std::string scene = (tmp / "cube.toml").string();
  test::write_text(scene, test::read_bytes(test::data_path("cube-3sets.toml")));
  write_config(tmp, scene, "");

  const std::string first = snakemake(tmp);
  for (const char* rule : {"joints", "cut", "vertices", "export_vtu"}) CHECK(ran(first, rule));
  CHECK_FALSE(ran(first, "export_yade"));  // only the exports the config asks for
  CHECK(test::fs::exists(tmp / "out" / "cube" / "seed-1" / "blocks.vtu"));

  // Nothing changed: nothing runs.
  const std::string second = snakemake(tmp);
  CHECK_THAT(second, Catch::Contains("Nothing to be done"));

  // An export option changed: only that export.
  write_config(tmp, scene, "-v");
  const std::string third = snakemake(tmp);
  CHECK(ran(third, "export_vtu"));
  for (const char* rule : {"joints", "cut", "vertices"}) CHECK_FALSE(ran(third, rule));

  // The scene changed: everything below it.
  test::write_text(scene, test::read_bytes(test::data_path("cube-3sets.toml")) + "\n# edited\n");
  const std::string fourth = snakemake(tmp);
  for (const char* rule : {"joints", "cut", "vertices", "export_vtu"}) CHECK(ran(fourth, rule));
}

namespace {

// Rows of a CSV file as name -> value maps (the files pipelines/summary writes have no quoting).
std::vector<std::map<std::string, std::string>> read_csv(const path& file) {
  std::istringstream in(test::read_bytes(file));
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream cs(line);
    for (std::string c; std::getline(cs, c, ',');) cells.push_back(c);
    if (header.empty()) {
      header = cells;
      continue;
    }
    REQUIRE(cells.size() == header.size());
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

double number(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

}  // namespace

TEST_CASE("a realization sweep: one folder per seed, a summary over the seeds",
          "[tools][workflow][snakemake]") {
  test::TempDir tmp;
  const path scene = test::test_data_path("sweep.toml");
  test::write_text(tmp / "config.yaml", "scenes:\n  sweep: " + scene.string() +
                                            "\nseeds: 3\nout: " + (tmp / "out").string() +
                                            "\ntools: " + SLICE_TOOLS_DIR +
                                            "\nexports: []\nplots: true\nsummary: true\n");
  const std::string log = snakemake(tmp, "--cores 2");
  for (const char* rule : {"joints", "cut", "vertices", "plots", "summary"}) CHECK(ran(log, rule));

  // Each seed's blocks, read back with the library: the summary's table must agree with them.
  const path out = tmp / "out" / "sweep";
  std::map<int, std::size_t> kept;
  std::map<int, double> p32;
  for (int seed = 1; seed <= 3; ++seed) {
    const path dir = out / ("seed-" + std::to_string(seed));
    const slice::BlockSystem bs = slice::read_blocks(dir / "geom.h5");
    CHECK(bs.joints.seed == static_cast<std::uint64_t>(seed));  // --seed overrode [scene] seed
    REQUIRE(bs.geometry);
    double volume = 0;
    for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
      kept[seed] += (bs.blocks[b].flags & slice::kRemoved) == 0;
      volume += bs.geometry->volume[b];
    }
    CHECK(volume == Approx(8000.0).epsilon(1e-9));
    for (const auto& set : bs.joints.sets) p32[seed] += set.achieved_p32;
    for (const char* png : {"geom-stereonet.png", "geom-sizes.png", "geom-volumes.png"})
      CHECK(test::read_bytes(dir / "plots" / png).rfind("\x89PNG", 0) == 0);
  }
  // Realizations differ (else the seed did not reach the sets).
  CHECK(std::set<std::size_t>{kept[1], kept[2], kept[3]}.size() == 3);

  const auto table = read_csv(out / "summary" / "realizations.csv");
  REQUIRE(table.size() == 3);
  for (int seed = 1; seed <= 3; ++seed) {
    const auto& row = table[static_cast<std::size_t>(seed - 1)];
    CAPTURE(seed);
    CHECK(row.at("seed") == std::to_string(seed));
    CHECK(row.at("blocks") == std::to_string(kept[seed]));
    CHECK(number(row.at("rock_volume")) == Approx(8000.0).epsilon(1e-6));
    CHECK(number(row.at("p32_total")) == Approx(p32[seed]).epsilon(1e-6));
    CHECK(number(row.at("p32_total")) > 0);
    for (const char* set : {"set-1", "set-2", "set-3"}) {
      CHECK(number(row.at(std::string(set) + "_joints")) > 10);
      CHECK(number(row.at(std::string(set) + "_p10")) >= 0);
    }
    CHECK(number(row.at("median_volume")) <= number(row.at("v50")));
  }

  // The distributions: per seed non-decreasing from below 1 up to 1, the band ordered.
  const auto cdf = read_csv(out / "summary" / "volume-cdf.csv");
  REQUIRE(cdf.size() == 200);
  for (int seed = 1; seed <= 3; ++seed) {
    for (const std::string what : {"number_seed", "volume_seed"}) {
      const std::string column = what + std::to_string(seed);
      double last = 0;
      for (const auto& row : cdf) {
        const double f = number(row.at(column));
        CHECK(f >= last - 1e-12);
        last = f;
      }
      CHECK(last == Approx(1.0));
      CHECK(number(cdf.front().at(column)) < 0.01);
    }
  }
  const auto band = read_csv(out / "summary" / "volume-band.csv");
  REQUIRE(band.size() == 200);
  for (const auto& row : band) {
    for (const std::string what : {"number", "volume"}) {
      CHECK(number(row.at(what + "_p05")) <= number(row.at(what + "_median")));
      CHECK(number(row.at(what + "_median")) <= number(row.at(what + "_p95")));
    }
  }
  CHECK(test::read_bytes(out / "summary" / "volumes.png").rfind("\x89PNG", 0) == 0);

  // Nothing changed: nothing runs, the summary included.
  CHECK_THAT(snakemake(tmp), Catch::Contains("Nothing to be done"));
}

TEST_CASE("workflow paths are relative to the config file that names them",
          "[tools][workflow][snakemake]") {
  // The user's config beside its scene, snakemake run from another folder: the scene is found
  // beside the config (not in the repository) and `out` is that folder's too.
  test::TempDir tmp;
  test::fs::create_directories(tmp / "mine");
  test::fs::create_directories(tmp / "run");
  test::write_text(tmp / "mine" / "cube.toml",
                   test::read_bytes(test::data_path("cube-3sets.toml")));
  test::write_text(tmp / "mine" / "my.yaml",
                   std::string("scenes:\n  cube: cube.toml\nseeds: [1]\nout: results\ntools: ") +
                       SLICE_TOOLS_DIR + "\nexports: [vtu]\nplots: false\nsummary: false\n");
  const path log = tmp / "snakemake.log";
  const int code = test::run_shell("cd " + test::shell_quote(tmp / "run") + " && snakemake -s " +
                                   test::shell_quote(kRoot / "pipelines" / "Snakefile") +
                                   " --configfile ../mine/my.yaml --cores 1 > " +
                                   test::shell_quote(log) + " 2>&1");
  INFO(test::tail_of(log));
  REQUIRE(code == 0);
  CHECK(test::fs::exists(tmp / "mine" / "results" / "cube" / "seed-1" / "blocks.vtu"));
  CHECK_FALSE(test::fs::exists(tmp / "run" / "results"));
}

TEST_CASE("workflow config: seeds [true] and an empty scenes: one line, nothing run",
          "[tools][workflow][snakemake]") {
  test::TempDir tmp;
  const std::string scene = test::data_path("cube-3sets.toml").string();
  const std::string rest = "\nout: " + (tmp / "out").string() + "\ntools: " + SLICE_TOOLS_DIR +
                           "\nplots: false\nsummary: false\n";
  struct Case {
    std::string name, config;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {"seeds: [true]",
       "scenes:\n  cube: " + scene + "\nseeds: [true]" + rest,
       {"bad.yaml: seeds: [True] is not a list of seeds", "integers >= 0"}},
      {"seeds: true", "scenes:\n  cube: " + scene + "\nseeds: true" + rest, {"seeds: True"}},
      {"an empty scenes:",
       "scenes:\nseeds: [1]" + rest,
       {"bad.yaml: scenes: None names no scene", "name: scene file"}},
      {"a scene without a file",
       "scenes:\n  cube:\nseeds: [1]" + rest,
       {"bad.yaml: scenes: cube: None is not a file name"}},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    test::write_text(tmp / "bad.yaml", c.config);
    const path out = tmp / "stdout", err = tmp / "stderr";
    const int code = test::run_shell("cd " + test::shell_quote(tmp.path()) + " && snakemake -s " +
                                     test::shell_quote(kRoot / "pipelines" / "Snakefile") +
                                     " --configfile bad.yaml --cores 1 > " +
                                     test::shell_quote(out) + " 2> " + test::shell_quote(err));
    const std::string e = test::read_bytes(err);
    INFO(e + test::read_bytes(out));
    CHECK(code == 1);
    CHECK(std::count(e.begin(), e.end(), '\n') == 1);
    CHECK_THAT(e, Catch::StartsWith("config: "));
    for (const auto& w : c.words) CHECK_THAT(e, Catch::Contains(w));
    CHECK_THAT(e, !Catch::Contains("Traceback") && !Catch::Contains("Error"));
    CHECK_FALSE(test::fs::exists(tmp / "out"));
  }
}

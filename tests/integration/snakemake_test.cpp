// Issue 14: pipelines/Snakefile reruns only what changed. Snakemake (Debian's 7.21) must be
// installed (pipelines/setup does it): a missing snakemake fails this test, it does not skip.
#include <catch2/catch.hpp>
#include <string>

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
                       "\"\nyade_options: \"\"\n");
}

// Runs the workflow; returns its log (stdout and stderr).
std::string snakemake(const test::TempDir& tmp) {
  const path log = tmp / "snakemake.log";
  const int code = test::run_shell("cd " + test::shell_quote(tmp.path()) + " && snakemake -s " +
                                   test::shell_quote(kRoot / "pipelines" / "Snakefile") +
                                   " --configfile " + test::shell_quote(tmp / "config.yaml") +
                                   " --cores 1 > " + test::shell_quote(log) + " 2>&1");
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

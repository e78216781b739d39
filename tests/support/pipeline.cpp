#include "support/pipeline.hpp"

#include <algorithm>
#include <catch2/catch.hpp>

namespace test {

std::string run_pipeline(const TempDir& tmp, const std::string& scene, Stage last) {
  const std::string joints = (tmp / "joints.h5").string(), blocks = (tmp / "blocks.h5").string(),
                    geom = (tmp / "geom.h5").string();
  const auto step = [](const std::string& tool, const std::vector<std::string>& args) {
    const auto r = run_tool(tool, args);
    INFO(tool << ": " << r.err);
    REQUIRE(r.exit_code == 0);
  };
  step("slice-joints", {data_path(scene).string(), "-o", joints});
  if (last == Stage::joints) return joints;
  step("slice-cut", {joints, "-o", blocks, "--prune"});
  if (last == Stage::blocks) return blocks;
  step("slice-vertices", {blocks, "-o", geom});
  return geom;
}

void check_bad_scenes(const std::vector<BadScene>& cases) {
  for (const auto& c : cases) {
    CAPTURE(c.name, c.text);
    TempDir tmp;
    write_text(tmp / "bad.toml", c.text);
    const auto out = tmp / "j.h5";
    const auto r = run_tool("slice-joints", {(tmp / "bad.toml").string(), "-o", out.string()});
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Catch::StartsWith("slice-joints: error: "));
    CHECK_THAT(r.err, Catch::Contains("bad.toml"));
    for (const auto& w : c.words) CHECK_THAT(r.err, Catch::Contains(w));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(fs::exists(tmp / "j.h5.partial"));
  }
}

void check_refused(const ToolRun& r, const std::string& tool,
                   const std::vector<std::string>& words) {
  INFO(r.err);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::StartsWith(tool + ": error: "));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  for (const auto& w : words) CHECK_THAT(r.err, Catch::Contains(w));
}

void edit_h5(const fs::path& file, const std::string& body) {
  const std::string script = "import h5py, numpy as np\nf = h5py.File(" +
                             shell_quote(file.string()) + ", 'r+')\n" + body + "\nf.close()\n";
  REQUIRE(run_shell("/usr/bin/python3 -c " + shell_quote(script)) == 0);
}

}  // namespace test

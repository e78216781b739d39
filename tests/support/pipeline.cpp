#include "support/pipeline.hpp"

#include <spawn.h>

#include <algorithm>
#include <catch2/catch.hpp>

extern char** environ;

namespace test {

namespace {

/// Runs one tool of a pipeline: exit 0 required, its stderr shown if not.
void step(const std::string& tool, const std::vector<std::string>& args) {
  const auto r = run_tool(tool, args);
  INFO(tool << ": " << r.err);
  REQUIRE(r.exit_code == 0);
}

}  // namespace

std::string run_pipeline(const TempDir& tmp, const std::string& scene, Stage last) {
  const std::string joints = (tmp / "joints.h5").string(), blocks = (tmp / "blocks.h5").string(),
                    geom = (tmp / "geom.h5").string();
  step("slice-joints", {data_path(scene).string(), "-o", joints});
  if (last == Stage::joints) return joints;
  step("slice-cut", {joints, "-o", blocks, "--prune"});
  if (last == Stage::blocks) return blocks;
  step("slice-vertices", {blocks, "-o", geom});
  return geom;
}

std::string geometry_of_text(const TempDir& tmp, const std::string& scene,
                             const std::string& prefix) {
  const std::string toml = (tmp / (prefix + "scene.toml")).string(),
                    joints = (tmp / (prefix + "joints.h5")).string(),
                    blocks = (tmp / (prefix + "blocks.h5")).string(),
                    geom = (tmp / (prefix + "geom.h5")).string();
  write_text(toml, scene);
  step("slice-joints", {toml, "-o", joints});
  step("slice-cut", {joints, "--prune", "-o", blocks});
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

std::string table3_2m_blocks(const TempDir& tmp) {
  std::string scene = read_bytes(data_path("table3-persistent.toml"));
  for (std::size_t p = 0; (p = scene.find("spacing = 3.7", p)) != std::string::npos;)
    scene.replace(p, 13, "spacing = 2.0");
  write_text(tmp / "t.toml", scene);
  const std::string joints = (tmp / "j.h5").string(), blocks = (tmp / "b.h5").string();
  REQUIRE(run_tool("slice-joints", {(tmp / "t.toml").string(), "-o", joints, "-q"}).exit_code == 0);
  REQUIRE(run_tool("slice-cut", {joints, "-o", blocks, "--prune", "-q"}).exit_code == 0);
  return blocks;
}

int spawn_tool(const std::string& tool, const std::vector<std::string>& args) {
  const std::string exe = (fs::path(SLICE_TOOLS_DIR) / tool).string();
  std::vector<std::string> all = {exe};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  REQUIRE(posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), environ) == 0);
  return pid;
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

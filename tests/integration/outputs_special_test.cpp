// Issue 42 regressions, run through the real tools: outputs that are special files (a FIFO, a
// device, /dev/stdout), stdout that refuses writes, a file size limit, option errors, and a
// second output failing after the first. Bad input is exit 1 with one line, the tool's name
// first; nothing is written and nothing on disk is damaged.
#include <sys/stat.h>
#include <sys/types.h>

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "support/pipeline.hpp"
#include "support/support.hpp"

using test::check_refused;
using test::run_tool;
using test::shell_quote;
using test::fs::path;

namespace {

/// Runs a tool through /bin/sh as `<prefix> exec <tool> <args> <redirect>`, stderr to a file:
/// for what run_tool cannot do (stdout on /dev/full or closed, a `ulimit -f`).
test::ToolRun run_redirected(const test::TempDir& tmp, const std::string& prefix,
                             const std::string& tool, const std::vector<std::string>& args,
                             const std::string& redirect) {
  // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on " " + string.
  std::string cmd = prefix;
  cmd += " exec ";
  cmd += shell_quote(path(SLICE_TOOLS_DIR) / tool);
  for (const std::string& a : args) {
    cmd += ' ';
    cmd += shell_quote(a);
  }
  const path err = tmp / "stderr.txt";
  cmd += ' ';
  cmd += redirect;
  cmd += " 2>";
  cmd += shell_quote(err);
  cmd += " </dev/null";
  test::ToolRun r;
  r.exit_code = test::run_shell("/bin/bash -c " + shell_quote(cmd));
  r.err = test::read_bytes(err);
  return r;
}

bool still_a_fifo(const path& p) { return test::fs::is_fifo(test::fs::symlink_status(p)); }

}  // namespace

TEST_CASE("special files as outputs: a FIFO, a device, /dev/stdout are refused, left as they were",
          "[robustness][tools][outputs]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry);
  const std::string scene = test::data_path("cube-3sets.toml").string();
  const path fifo = tmp / "fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
  // Links in the test's folder (no root needed; a run before the fix replaced the link, not
  // what it names): a device, and a process's descriptor (/dev/stdout -> /proc/self/fd/1,
  // here a regular file: run_tool sends stdout to one).
  const path null_link = tmp / "null.vtu", stdout_link = tmp / "stdout.py";
  test::fs::create_symlink("/dev/null", null_link);
  test::fs::create_symlink("/dev/stdout", stdout_link);

  check_refused(run_tool("slice-joints", {scene, "-o", fifo.string()}), "slice-joints",
                {"fifo", "FIFO", "not a regular file"});
  check_refused(run_tool("slice-export", {geom, "--format", "yade", "-o", fifo.string()}),
                "slice-export", {"FIFO", "-o"});
  check_refused(run_tool("slice-export", {geom, "--format", "vtu", "-o", null_link.string()}),
                "slice-export", {"null.vtu", "character device"});
  check_refused(run_tool("slice-export", {geom, "--format", "yade", "-o", stdout_link.string()}),
                "slice-export", {"stdout.py", "/proc/"});
  // A second output on a special file: the first is not written either.
  const path vtu = tmp / "blocks.vtu";
  check_refused(run_tool("slice-export",
                         {geom, "--format", "vtu", "-o", vtu.string(), "--joints", fifo.string()}),
                "slice-export", {"--joints", "FIFO"});
  CHECK_FALSE(test::fs::exists(vtu));

  CHECK(still_a_fifo(fifo));
  CHECK(test::fs::is_symlink(test::fs::symlink_status(null_link)));
  CHECK(test::fs::read_symlink(null_link) == "/dev/null");
  CHECK(test::fs::is_symlink(test::fs::symlink_status(stdout_link)));
  for (const char* name : {"fifo.partial", "null.vtu.partial", "stdout.py.partial"})
    CHECK_FALSE(test::fs::exists(tmp / name));
  // A symlink to a regular file is an output as before.
  const path file = tmp / "model.py", link = tmp / "link.py";
  test::fs::create_symlink(file, link);
  test::write_text(file, "old\n");
  CHECK(run_tool("slice-export", {geom, "--format", "yade", "-o", link.string(), "-q"}).exit_code ==
        0);
}

TEST_CASE("stdout refusing writes: slice-info exits 1 with the reason, not 0 with half the JSON",
          "[robustness][tools][stdout]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry);
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{geom, "--json"}, std::vector<std::string>{geom}}) {
    INFO(args.size());
    const auto full = run_redirected(tmp, "", "slice-info", args, ">/dev/full");
    check_refused(full, "slice-info", {"stdout", "No space left on device"});
    const auto closed = run_redirected(tmp, "", "slice-info", args, ">&-");
    check_refused(closed, "slice-info", {"stdout", "closed"});
  }
  // --help to /dev/full too; to a file as before.
  check_refused(run_redirected(tmp, "", "slice-info", {"--help"}, ">/dev/full"), "slice-info",
                {"stdout"});
  CHECK(run_tool("slice-info", {"--help"}).exit_code == 0);
  const auto ok = run_tool("slice-info", {geom, "--json"});
  CHECK(ok.exit_code == 0);
  CHECK(ok.out.back() == '\n');
}

TEST_CASE("a file size limit: the system's reason, exit 1 and no .partial, not SIGXFSZ",
          "[robustness][tools][outputs]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry);
  const std::string scene = test::data_path("cube-3sets.toml").string();
  const std::string blocks = (tmp / "blocks.h5").string();
  struct Case {
    std::string tool;
    std::vector<std::string> args;
    std::string out;
  };
  const std::vector<Case> cases = {
      {"slice-joints", {scene}, "j.h5"},
      {"slice-vertices", {blocks}, "g.h5"},
      {"slice-export", {geom, "--format", "vtu", "--vtu-compressor", "none"}, "b.vtu"},
      {"slice-export", {geom, "--format", "yade"}, "m.py"},
  };
  for (const Case& c : cases) {
    INFO(c.tool << " -o " << c.out);
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"-o", (tmp / c.out).string()});
    // 1 KiB: less than any of these outputs (a joints.h5 alone is several KiB).
    const auto r = run_redirected(tmp, "ulimit -f 1;", c.tool, args, ">/dev/null");
    check_refused(r, c.tool, {c.out, "File too large"});
    CHECK_FALSE(test::fs::exists(tmp / c.out));
    CHECK_FALSE(test::fs::exists(tmp / (c.out + ".partial")));
  }
}

TEST_CASE("option errors: one line, the tool's name first, no 330-character range",
          "[robustness][tools][options]") {
  struct Case {
    std::string tool;
    std::vector<std::string> args, words;
  };
  const std::vector<Case> cases = {
      {"slice-info", {"--bogus", "x.h5"}, {"--bogus", "slice-info --help"}},
      {"slice-export", {"g.h5", "-o", "b.vtu", "--threads", "0"}, {"--threads", "positive"}},
      {"slice-export", {"g.h5", "-o", "b.vtu", "--yade-steps", "many"}, {"--yade-steps", "many"}},
      {"slice-export", {"g.h5"}, {"--output is required"}},
      {"slice-cut", {"j.h5", "--prnue"}, {"--prnue"}},
      {"slice-joints", {}, {"required"}},
  };
  for (const Case& c : cases) {
    const auto r = run_tool(c.tool, c.args);
    check_refused(r, c.tool, c.words);
    CHECK(r.err.size() < 200);
  }
  const auto help = run_tool("slice-export", {"--help"});
  CHECK(help.exit_code == 0);
  CHECK_THAT(help.out, Catch::Contains("--joints"));
}

TEST_CASE(
    "slice-export --joints failing after the VTU: one line, none claiming the VTU was written",
    "[robustness][tools][outputs]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry);
  const path vtu = tmp / "blocks.vtu", joints = tmp / "joints.vtu";
  test::fs::create_directory(tmp / "joints.vtu.partial");  // where the joints' writer goes
  const auto r = run_tool(
      "slice-export", {geom, "--format", "vtu", "-o", vtu.string(), "--joints", joints.string()});
  check_refused(r, "slice-export", {"joints.vtu.partial"});
  CHECK_THAT(r.err, !Catch::Contains("-> "));
  CHECK_FALSE(test::fs::exists(vtu));
  CHECK_FALSE(test::fs::exists(joints));
  // Written, both lines come once both files are in place.
  test::fs::remove(tmp / "joints.vtu.partial");
  const auto ok = run_tool(
      "slice-export", {geom, "--format", "vtu", "-o", vtu.string(), "--joints", joints.string()});
  CHECK(ok.exit_code == 0);
  CHECK_THAT(ok.err, Catch::Contains("-> " + vtu.string()));
  CHECK_THAT(ok.err, Catch::Contains("-> " + joints.string()));
}

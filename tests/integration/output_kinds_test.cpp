// Every kind of output path with every tool that writes a file (issue 42): an existing file, a
// symlink to one, a dangling symlink, a FIFO, /dev/null and /dev/full, a symlink into /dev,
// /dev/stdout, a directory, a path in a missing folder and one in a read-only folder. A refusal
// is exit 1 and one line naming the path, and nothing on disk changes (types, bytes and link
// targets compared before and after); a symlink to a file, or a dangling one, is written where
// it leads and stays a link. slice-info's stdout is sent to the same kinds by the shell. Under
// a file size limit every writer gives the system's reason and the fix for it (ulimit -f), not
// "the disk is not full". The inputs are made once for all cases.
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "support/pipeline.hpp"
#include "support/support.hpp"

using test::check_refused;
using test::run_tool;
using test::shell_quote;
using test::fs::path;
namespace fs = test::fs;

namespace {

// The inputs of every writer, made once: a small scene's joints (6 planes: each
// output still above the 1 KiB limit of the last test), blocks as cut, pruned blocks and
// geometry, and a 2-D section's geometry (for --format udec).
struct Inputs {
  test::TempDir dir;
  std::string scene, joints, cut, blocks, geom, section_geom;
  Inputs();
};

Inputs::Inputs()
    : scene((dir / "kinds.toml").string()),
      joints((dir / "joints.h5").string()),
      cut((dir / "cut.h5").string()),
      blocks((dir / "blocks.h5").string()),
      geom((dir / "geom.h5").string()),
      section_geom((dir / "section-geom.h5").string()) {
  test::write_text(scene, R"([scene]
name = "kinds"
[domain]
box = { min = [0, 0, 0], max = [10, 10, 10] }
[[sets]]
name = "J1"
dip = 30
dip_direction = 20
spacing = 4
[[sets]]
name = "J2"
dip = 80
dip_direction = 120
spacing = 5
)");
  const std::string section_joints = (dir / "section-joints.h5").string();
  const std::string section_blocks = (dir / "section-blocks.h5").string();
  const std::vector<std::pair<std::string, std::vector<std::string>>> runs = {
      {"slice-joints", {scene, "-o", joints}},
      {"slice-cut", {joints, "-o", cut}},
      {"slice-prune", {cut, "-o", blocks}},
      {"slice-vertices", {blocks, "-o", geom}},
      {"slice-joints", {test::data_path("tunnel-section.toml").string(), "-o", section_joints}},
      {"slice-cut", {section_joints, "--prune", "-o", section_blocks}},
      {"slice-vertices", {section_blocks, "-o", section_geom}},
  };
  for (const auto& [tool, args] : runs) {
    const auto r = run_tool(tool, args);
    INFO(tool << ": " << r.err);
    REQUIRE(r.exit_code == 0);
  }
}

const Inputs& inputs() {
  static const Inputs in;
  return in;
}

// A tool's run with one output under test: `before` + {option, path} + `after`.
struct Writer {
  std::string tool;
  std::vector<std::string> before;
  std::string option;  // the output option under test
  std::string name;    // the output's file name (its extension matters to some writers)
  std::vector<std::string> after;
};

// Every writer: each tool's -o, and the second outputs (slice-cut --stats, slice-export
// --joints and --3dec-commands) with the first output in `aux`, a folder of its own.
std::vector<Writer> writers(const Inputs& in, const path& aux) {
  const std::string a = aux.string();
  return {
      {"slice-joints", {in.scene}, "-o", "j.h5", {}},
      {"slice-cut", {in.joints}, "-o", "b.h5", {}},
      {"slice-cut", {in.joints, "-o", a + "/b.h5"}, "--stats", "stats.json", {}},
      {"slice-prune", {in.cut}, "-o", "p.h5", {}},
      {"slice-vertices", {in.blocks}, "-o", "g.h5", {}},
      {"slice-export", {in.geom, "--format", "vtu"}, "-o", "b.vtu", {}},
      {"slice-export", {in.geom, "--format", "vtu", "-o", a + "/b.vtu"}, "--joints", "j.vtu", {}},
      {"slice-export", {in.geom, "--format", "yade"}, "-o", "m.py", {}},
      {"slice-export", {in.geom, "--format", "yade-potential-blocks"}, "-o", "pb.py", {}},
      {"slice-export",
       {in.geom, "--format", "3dec"},
       "-o",
       "m.3dgrid",
       {"--3dec-commands", a + "/m.dat"}},
      {"slice-export",
       {in.geom, "--format", "3dec", "-o", a + "/m.3dgrid"},
       "--3dec-commands",
       "c.dat",
       {}},
      {"slice-export", {in.section_geom, "--format", "udec"}, "-o", "m.udec", {}},
      {"slice-export", {in.joints, "--format", "fab"}, "-o", "d.fab", {}},
      {"slice-extract", {in.geom, "--box", "0,0,0,5,5,5"}, "-o", "x.h5", {}},
      {"slice-stability", {in.geom, "--free-faces", "+z"}, "-o", "s.h5", {}},
  };
}

// What a folder holds, to compare before and after: each entry's type, and a file's bytes, a
// link's target, a folder's permissions. Devices by their numbers.
std::map<std::string, std::string> snapshot(const path& dir) {
  std::map<std::string, std::string> s;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const path p = e.path();
    struct stat st {};
    REQUIRE(::lstat(p.c_str(), &st) == 0);
    std::string what = std::to_string(st.st_mode);
    // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on " " + string.
    what += ' ';
    if (S_ISLNK(st.st_mode)) what += fs::read_symlink(p).string();
    if (S_ISREG(st.st_mode)) what += test::read_bytes(p);
    s[fs::relative(p, dir).string()] = what;
  }
  for (const char* dev : {"/dev/null", "/dev/full"}) {
    struct stat st {};
    REQUIRE(::lstat(dev, &st) == 0);
    s[dev] = std::to_string(st.st_mode) + " " + std::to_string(st.st_rdev);
  }
  return s;
}

// The kinds of output path. `make` prepares one in `dir` and returns the path to give the tool
// (`name`: the writer's file name); `written`: whether the run writes (exit 0) rather than being
// refused; `check` then looks at what it wrote.
struct Kind {
  std::string what;
  std::function<std::string(const path& dir, const std::string& name)> make;
  bool written = false;
  std::function<void(const path& dir, const std::string& name)> check = {};
};

const bool kRoot = ::geteuid() == 0;

std::vector<Kind> kinds() {
  const std::string old = "old content\n";
  return {
      {"an existing regular file",
       [=](const path& d, const std::string& n) {
         test::write_text(d / n, old);
         return (d / n).string();
       },
       true,
       [=](const path& d, const std::string& n) {
         CHECK(fs::is_regular_file(fs::symlink_status(d / n)));
         CHECK(test::read_bytes(d / n) != old);
       }},
      {"a symlink to a regular file",
       [=](const path& d, const std::string& n) {
         test::write_text(d / ("real-" + n), old);
         fs::create_symlink("real-" + n, d / n);
         return (d / n).string();
       },
       true,
       [=](const path& d, const std::string& n) {  // the link kept, its file written
         REQUIRE(fs::is_symlink(fs::symlink_status(d / n)));
         CHECK(fs::read_symlink(d / n) == path("real-" + n));
         CHECK(test::read_bytes(d / ("real-" + n)) != old);
       }},
      {"a dangling symlink",
       [](const path& d, const std::string& n) {
         fs::create_symlink("new-" + n, d / n);
         return (d / n).string();
       },
       true,
       [](const path& d, const std::string& n) {  // the file it names made, the link kept
         REQUIRE(fs::is_symlink(fs::symlink_status(d / n)));
         CHECK(fs::is_regular_file(fs::symlink_status(d / ("new-" + n))));
         CHECK(fs::file_size(d / ("new-" + n)) > 0);
       }},
      {"a dangling symlink into a missing folder",
       [](const path& d, const std::string& n) {
         fs::create_symlink("nowhere/" + n, d / n);
         return (d / n).string();
       }},
      {"a FIFO",
       [](const path& d, const std::string& n) {
         REQUIRE(::mkfifo((d / n).c_str(), 0644) == 0);
         return (d / n).string();
       }},
      {"/dev/null", [](const path&, const std::string&) { return std::string("/dev/null"); }},
      {"/dev/full", [](const path&, const std::string&) { return std::string("/dev/full"); }},
      {"a symlink into /dev",
       [](const path& d, const std::string& n) {
         fs::create_symlink("/dev/null", d / n);
         return (d / n).string();
       }},
      {"/dev/stdout (a link to /proc/self/fd/1)",
       [](const path&, const std::string&) { return std::string("/dev/stdout"); }},
      {"a directory",
       [=](const path& d, const std::string& n) {
         fs::create_directory(d / n);
         test::write_text(d / n / "inside.txt", old);
         return (d / n).string();
       }},
      {"a path in a missing folder",
       [](const path& d, const std::string& n) { return (d / "missing" / n).string(); }},
      // Root writes into a read-only folder (permissions do not bind it): there the run writes,
      // and the test checks what root sees; as anyone else it is refused.
      {"a path in a read-only folder",
       [](const path& d, const std::string& n) {
         fs::create_directory(d / "ro");
         fs::permissions(d / "ro", fs::perms::owner_read | fs::perms::owner_exec);
         return (d / "ro" / n).string();
       },
       kRoot,
       [](const path& d, const std::string& n) {
         CHECK(fs::is_regular_file(fs::symlink_status(d / "ro" / n)));
         CHECK_FALSE(fs::exists(d / "ro" / (n + ".partial")));
       }},
  };
}

// No .partial anywhere under `dir`.
void check_no_partial(const path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir))
    CHECK(e.path().extension() != ".partial");
}

// Runs `cmd` through bash with stderr in `err`; the exit code (for shell redirections and
// ulimit, which run_tool cannot do).
test::ToolRun run_bash(const std::string& cmd, const path& err) {
  test::ToolRun r;
  // The group's redirection first: bash's own refusal to open a path goes to `err` too.
  r.exit_code = test::run_shell(
      "/bin/bash -c " + shell_quote("{ " + cmd + "; } 2>" + shell_quote(err)) + " </dev/null");
  r.err = fs::exists(err) ? test::read_bytes(err) : std::string();
  fs::remove(err);
  return r;
}

}  // namespace

TEST_CASE(
    "every kind of output path, with every tool's every output: written through links, "
    "refused with one line, nothing changed",
    "[robustness][tools][outputs][output-kinds]") {
  const Inputs& in = inputs();
  test::TempDir tmp;
  int n = 0;
  for (const Kind& kind : kinds()) {
    for (const Writer& w : writers(in, tmp / "aux")) {
      const path dir = tmp / std::to_string(n++);
      fs::create_directories(dir);
      fs::create_directories(tmp / "aux");
      const std::string out = kind.make(dir, w.name);
      std::vector<std::string> args = w.before;
      args.insert(args.end(), {w.option, out});
      args.insert(args.end(), w.after.begin(), w.after.end());
      args.push_back("-q");
      INFO(kind.what << ": " << w.tool << " ... " << w.option << " " << out);
      const auto before = snapshot(dir);
      const auto r = run_tool(w.tool, args);
      if (kind.written) {
        INFO(r.err);
        CHECK(r.exit_code == 0);
        CHECK(r.err.empty());
        kind.check(dir, w.name);
      } else {
        check_refused(r, w.tool, {out});
        CHECK(snapshot(dir) == before);
        CHECK(fs::is_empty(tmp / "aux"));  // the run's other output is not written either
      }
      check_no_partial(dir);
      fs::permissions(dir, fs::perms::owner_all);
      if (fs::exists(dir / "ro")) fs::permissions(dir / "ro", fs::perms::owner_all);
      fs::remove_all(tmp / "aux");
    }
  }
}

TEST_CASE("slice-info --json to every kind of path the shell opens: a refused write is exit 1",
          "[robustness][tools][outputs][output-kinds]") {
  const Inputs& in = inputs();
  test::TempDir tmp;
  const path err = tmp / "stderr.txt";
  const std::string info =
      shell_quote(path(SLICE_TOOLS_DIR) / "slice-info") + " " + shell_quote(in.geom) + " --json";
  const std::string json = run_tool("slice-info", {in.geom, "--json"}).out;
  REQUIRE(json.size() > 100);
  const auto to = [&](const path& p) {
    return run_bash("exec " + info + " >" + shell_quote(p), err);
  };

  // Written: a file, a link to one (kept), a dangling link (the shell makes its file).
  test::write_text(tmp / "old.json", "old\n");
  CHECK(to(tmp / "old.json").exit_code == 0);
  CHECK(test::read_bytes(tmp / "old.json") == json);
  test::write_text(tmp / "real.json", "old\n");
  fs::create_symlink("real.json", tmp / "link.json");
  CHECK(to(tmp / "link.json").exit_code == 0);
  CHECK(fs::is_symlink(fs::symlink_status(tmp / "link.json")));
  CHECK(test::read_bytes(tmp / "real.json") == json);
  fs::create_symlink("made.json", tmp / "dangling.json");
  CHECK(to(tmp / "dangling.json").exit_code == 0);
  CHECK(test::read_bytes(tmp / "made.json") == json);
  // /dev/null takes every byte: exit 0. A FIFO with a reader gets the JSON.
  CHECK(to("/dev/null").exit_code == 0);
  REQUIRE(::mkfifo((tmp / "fifo").c_str(), 0644) == 0);
  const auto via_fifo =
      run_bash("cat " + shell_quote(tmp / "fifo") + " >" + shell_quote(tmp / "from-fifo.json") +
                   " & " + info + " >" + shell_quote(tmp / "fifo") + "; rc=$?; wait; exit $rc",
               err);
  CHECK(via_fifo.exit_code == 0);
  CHECK(test::read_bytes(tmp / "from-fifo.json") == json);
  CHECK(fs::is_fifo(fs::symlink_status(tmp / "fifo")));
  // /dev/full and a link into it refuse the write: exit 1, one line naming stdout and why.
  fs::create_symlink("/dev/full", tmp / "full.json");
  for (const path& p : {path("/dev/full"), tmp / "full.json"}) {
    INFO(p);
    const auto r = to(p);
    check_refused(r, "slice-info", {"stdout", "No space left on device"});
  }
  CHECK(fs::is_symlink(fs::symlink_status(tmp / "full.json")));
  // A directory, a missing folder, a read-only folder (as anyone but root): the shell cannot
  // open them and never starts slice-info; bash says why (exit 1) and nothing is made.
  fs::create_directory(tmp / "dir.json");
  fs::create_directory(tmp / "ro");
  fs::permissions(tmp / "ro", fs::perms::owner_read | fs::perms::owner_exec);
  const auto before = snapshot(tmp.path());
  for (const path& p : {tmp / "dir.json", tmp / "missing" / "x.json"}) {
    INFO(p);
    const auto r = to(p);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, !Catch::Contains("slice-info"));
  }
  const auto ro = to(tmp / "ro" / "x.json");
  CHECK(ro.exit_code == (kRoot ? 0 : 1));  // root writes there: the JSON, whole
  if (kRoot) CHECK(test::read_bytes(tmp / "ro" / "x.json") == json);
  if (kRoot) fs::remove(tmp / "ro" / "x.json");
  CHECK(snapshot(tmp.path()) == before);
  fs::permissions(tmp / "ro", fs::perms::owner_all);
}

TEST_CASE("a file size limit: every writer says File too large and to raise ulimit -f",
          "[robustness][tools][outputs][output-kinds]") {
  const Inputs& in = inputs();
  test::TempDir tmp;
  const path err = tmp / "stderr.txt";
  for (const Writer& w : writers(in, tmp / "aux")) {
    fs::create_directories(tmp / "aux");
    const path out = tmp / w.name;
    std::string cmd = "ulimit -f 1; exec " + shell_quote(path(SLICE_TOOLS_DIR) / w.tool);
    std::vector<std::string> args = w.before;
    args.insert(args.end(), {w.option, out.string()});
    args.insert(args.end(), w.after.begin(), w.after.end());
    for (const std::string& a : args) {
      cmd += ' ';
      cmd += shell_quote(a);
    }
    INFO(cmd);
    const auto r = run_bash(cmd + " >/dev/null", err);
    // 1 KiB: less than each of these outputs, or than the first output of a run with two.
    check_refused(r, w.tool, {"File too large", "ulimit -f", "1024 bytes"});
    CHECK_THAT(r.err, !Catch::Contains("disk is not full"));
    CHECK_FALSE(fs::exists(out));
    check_no_partial(tmp.path());
    fs::remove_all(tmp / "aux");
  }
  // slice-info's stdout to a file past the limit.
  const auto r =
      run_bash("ulimit -f 1; exec " + shell_quote(path(SLICE_TOOLS_DIR) / "slice-info") + " " +
                   shell_quote(in.geom) + " --json >" + shell_quote(tmp / "info.json"),
               err);
  check_refused(r, "slice-info", {"stdout", "File too large", "ulimit -f"});
  CHECK_THAT(r.err, !Catch::Contains("make room on the disk"));
}

TEST_CASE(
    "an output that is a link into a missing folder is refused before any input is read, as a "
    "path in a missing folder is",
    "[robustness][tools][outputs][output-kinds]") {
  // The first check of every output looked at the folder of the link, not of the file it
  // leads to: a link into a missing folder passed it and the run failed only when it wrote,
  // after all the work. Each writer here gets an input that does not exist, so a refusal that
  // names the output (and not the input) shows the output was checked first.
  const Inputs& in = inputs();
  test::TempDir tmp;
  int n = 0;
  for (const Writer& w : writers(in, tmp / "aux")) {
    for (const bool link : {false, true}) {
      const path dir = tmp / std::to_string(n++);
      fs::create_directories(dir);
      fs::create_directories(tmp / "aux");
      std::string out = (dir / "nowhere" / w.name).string();
      if (link) {
        fs::create_symlink("nowhere/" + w.name, dir / w.name);
        out = (dir / w.name).string();
      }
      std::vector<std::string> args = w.before;
      args.front() = (dir / "no-input.h5").string();
      args.insert(args.end(), {w.option, out});
      args.insert(args.end(), w.after.begin(), w.after.end());
      INFO(w.tool << " ... " << w.option << " " << out);
      const auto r = run_tool(w.tool, args);
      check_refused(r, w.tool, {out, (dir / "nowhere").string() + " does not exist"});
      CHECK_THAT(r.err, !Catch::Contains("no-input"));
      CHECK(fs::is_empty(tmp / "aux"));
      fs::remove_all(tmp / "aux");
    }
  }
}

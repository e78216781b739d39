// The fuzzers' saved findings (tests/fuzz/regressions/, README there) through the real tools:
// each input is read (exit 0) or refused with one line (exit 1), never an internal error
// (exit 2) or a crash. .ci/fuzz replays the same files in the sanitized fuzz targets.
#include <algorithm>
#include <catch2/catch.hpp>
#include <vector>

#include "support/support.hpp"

namespace {

using test::fs::path;

// The files of tests/fuzz/<kind>/<target>/ (kind: regressions or corpus), sorted.
std::vector<path> files_of(const char* kind, const std::string& target) {
  const path dir = path(SLICE_TEST_DATA_DIR).parent_path() / "fuzz" / kind / target;
  std::vector<path> files;
  if (!test::fs::is_directory(dir)) return files;
  for (const auto& e : test::fs::directory_iterator(dir))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<path> saved(const std::string& target) { return files_of("regressions", target); }

void check_answer(const test::ToolRun& r, const std::string& tool) {
  INFO(r.err);
  REQUIRE((r.exit_code == 0 || r.exit_code == 1));
  if (r.exit_code == 1) {
    CHECK(r.err.rfind(tool + ": error: ", 0) == 0);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
}

}  // namespace

TEST_CASE("slice-joints answers every scene the fuzzer saved with exit 0 or 1", "[tools][fuzz]") {
  const auto files = saved("scene");
  REQUIRE(!files.empty());
  for (const auto& f : files) {
    CAPTURE(f.filename().string());
    test::TempDir tmp;
    check_answer(test::run_tool("slice-joints", {f.string(), "-o", (tmp / "j.h5").string()}),
                 "slice-joints");
  }
}

TEST_CASE("slice-info answers every HDF5 file the fuzzer saved with exit 0 or 1", "[tools][fuzz]") {
  const auto files = saved("h5");
  REQUIRE(!files.empty());
  for (const auto& f : files) {
    CAPTURE(f.filename().string());
    check_answer(test::run_tool("slice-info", {f.string()}), "slice-info");
  }
}

// HDF5 1.10.8 alone allocates without end on these (a local heap whose free list loops: 16.9 GB
// before being killed). The readers' checked driver refuses them at once; under a 4 GB memory
// limit, so that a regression fails here instead of taking the machine.
TEST_CASE("the tools refuse a local heap whose free list loops, in bounded memory",
          "[tools][fuzz]") {
  int files = 0;
  for (const auto& f : saved("h5")) {
    if (f.filename().string().rfind("hdf5-local-heap-loop-", 0) != 0) continue;
    ++files;
    CAPTURE(f.filename().string());
    test::TempDir tmp;
    for (const std::string tool : {"slice-info", "slice-vertices", "slice-export"}) {
      const std::string out = (tmp / "out.h5").string();
      const std::string args = tool == "slice-info"     ? ""
                               : tool == "slice-export" ? " --format 3dec -o " + out
                                                        : " -o " + out;
      const std::string cmd = "ulimit -v 4000000; timeout 60 " +
                              test::shell_quote(test::fs::path(SLICE_TOOLS_DIR) / tool) + " " +
                              test::shell_quote(f) + args + " >/dev/null 2>" +
                              test::shell_quote(tmp / "err");
      CAPTURE(tool);
      CHECK(test::run_shell(cmd) == 1);
      const std::string err = test::read_bytes(tmp / "err");
      CHECK(err.rfind(tool + ": error: " + f.string() + ": ", 0) == 0);
      CHECK(err.find("has a list of free blocks that loops (damaged file)") != std::string::npos);
      CHECK(std::count(err.begin(), err.end(), '\n') == 1);
      CHECK_FALSE(test::fs::exists(out));
    }
  }
  CHECK(files == 2);
}

// HDF5 1.10.8 itself dies of SIGSEGV on these (in H5Aexists and H5Lexists: a corrupt attribute
// message, a corrupt local heap). The tools' crash handler answers like any bad input: exit 1,
// one line naming the file, no output left behind.
TEST_CASE("the tools answer files that crash HDF5 with exit 1 and nothing written",
          "[tools][fuzz]") {
  const auto files = saved("hdf5-crash");
  REQUIRE(files.size() >= 2);
  for (const auto& f : files) {
    CAPTURE(f.filename().string());
    check_answer(test::run_tool("slice-info", {f.string()}), "slice-info");
    test::TempDir tmp;
    const test::ToolRun cut =
        test::run_tool("slice-cut", {f.string(), "-o", (tmp / "b.h5").string()});
    check_answer(cut, "slice-cut");
    CHECK(cut.exit_code == 1);
    CHECK(cut.err.find(f.string()) != std::string::npos);
    CHECK(test::fs::is_empty(tmp.path()));
  }
}

// Issue 12 item 5: the scenes mutate_scenes.py (and a hand) found that hung slice-joints, ran
// slice-cut out of memory or into exit 2. Each is now refused with one line or cut (regressions/
// big/ keeps the legitimate 0.2-1.1 million block jobs, which take 3-27 s, out of the suite).
TEST_CASE("the slow scenes the mutations found are refused or cut", "[tools][fuzz]") {
  const auto files = saved("slow");
  REQUIRE(files.size() >= 9);
  int refused = 0;
  for (const auto& f : files) {
    CAPTURE(f.filename().string());
    test::TempDir tmp;
    const std::string joints = (tmp / "j.h5").string();
    const auto j = test::run_tool("slice-joints", {f.string(), "-o", joints});
    check_answer(j, "slice-joints");
    if (j.exit_code != 0) {
      ++refused;
      continue;
    }
    const auto c = test::run_tool("slice-cut", {joints, "-o", (tmp / "b.h5").string()});
    check_answer(c, "slice-cut");
    refused += c.exit_code == 1 ? 1 : 0;
  }
  CHECK(refused == 5);  // two tolerances below precision, 1e7 and 1e8 blocks, 9e6 joints
}

// fuzz_obj, fuzz_stl: the seeds and the saved findings as the [[zones]] mesh of a small scene
// (read_mesh, then check_solid_mesh, as the fuzz targets do), under their target's extension.
// The seeds named -open, -inside-out or -wrong-count are refused, the other seeds read.
TEST_CASE("slice-joints answers the fuzzers' meshes with exit 0 or 1", "[tools][fuzz]") {
  std::size_t seeds = 0;
  for (const std::string target : {"obj", "stl"}) {
    auto files = files_of("corpus", target);
    seeds += files.size();
    for (const auto& f : saved(target)) files.push_back(f);
    for (const auto& f : files) {
      CAPTURE(f.string());
      test::TempDir tmp;
      const std::string mesh = "zone." + target;
      test::fs::copy_file(f, tmp / mesh);
      test::write_text(tmp / "s.toml",
                       "[domain]\nbox = { min = [-5, -5, -5], max = [5, 5, 5] }\n"
                       "[[zones]]\nmesh = \"" +
                           mesh + "\"\n");
      const auto r = test::run_tool("slice-joints",
                                    {(tmp / "s.toml").string(), "-o", (tmp / "j.h5").string()});
      check_answer(r, "slice-joints");
      const std::string name = f.filename().string();
      if (f.parent_path().parent_path().filename() == "corpus")
        CHECK(r.exit_code == (name.find("-open") != std::string::npos ||
                                      name.find("-inside-out") != std::string::npos ||
                                      name.find("-wrong-count") != std::string::npos
                                  ? 1
                                  : 0));
    }
  }
  CHECK(seeds >= 10);
}

// fuzz_export: each saved geom.h5 exported in the three formats the target writes. A YADE
// script that is written must be Python (compiled by Debian's python3, which YADE runs).
TEST_CASE("slice-export answers every geometry the fuzzer saved, its scripts compile",
          "[tools][fuzz][export]") {
  const auto files = saved("export");
  REQUIRE(!files.empty());
  for (const auto& f : files) {
    for (const std::string format : {"3dec", "yade", "yade-potential-blocks"}) {
      CAPTURE(f.filename().string(), format);
      test::TempDir tmp;
      const path out = tmp / (format == "3dec" ? "m.3dgrid" : "m.py");
      const auto r = test::run_tool("slice-export",
                                    {f.string(), "--format", format, "-o", out.string(), "-q"});
      check_answer(r, "slice-export");
      // The saved names of findings in the YADE writer: the fixed writer exports them.
      if (f.filename().string().rfind("yade-", 0) == 0 && format != "3dec") CHECK(r.exit_code == 0);
      // A tolerance that passed every check of /geometry: refused on read now.
      if (f.filename().string().rfind("options-tolerance-", 0) == 0) {
        CHECK(r.exit_code == 1);
        CHECK(r.err.find("/options attribute tolerance") != std::string::npos);
      }
      // A face naming a joint whose plane it is not on (a 3DEC contact of a block with itself).
      // The fuzzer's file also has /blocks/flags 255, which the readers now refuse first.
      if (f.filename().string().rfind("face-joint-", 0) == 0) {
        CHECK(r.exit_code == 1);
        CHECK((r.err.find("does not lie on joint") != std::string::npos ||
               r.err.find("/blocks/flags row") != std::string::npos));
      }
      if (r.exit_code != 0 || format == "3dec") continue;
      const std::string script = test::read_bytes(out);
      CHECK(script.find('\r') == std::string::npos);
      // Read as UTF-8 first, as Python reads a script it runs (compile() of bytes lets a
      // comment that is no UTF-8 pass; `python3 model.py` refuses it).
      CHECK(test::run_shell("/usr/bin/python3 -c 'import sys; compile(open(sys.argv[1], "
                            "encoding=\"utf-8\").read(), sys.argv[1], \"exec\")' " +
                            test::shell_quote(out)) == 0);
    }
  }
}

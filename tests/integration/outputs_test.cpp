// Outputs under faults of the environment (the third robustness audit), through the real tools:
// a second output that cannot be written, a full disk, and two runs on one output. Each test is
// named after what the audit found. The full-disk tests mount a small tmpfs, so they need root
// (the tests run as root, as the SLURM test does): without it they fail, they do not skip.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "support/pipeline.hpp"
#include "support/support.hpp"

using test::run_tool;
using test::fs::path;

namespace {

/// A tmpfs of `kib` KiB mounted on a fresh folder; unmounted when it goes out of scope.
class SmallDisk {
 public:
  explicit SmallDisk(const test::TempDir& tmp, int kib) : dir_(tmp / "disk") {
    test::fs::create_directories(dir_);
    INFO("mounting a tmpfs needs root: run the tests as root (pipelines/test does in CI)");
    REQUIRE(test::run_shell("mount -t tmpfs -o size=" + std::to_string(kib) + "k tmpfs " +
                            test::shell_quote(dir_)) == 0);
  }
  ~SmallDisk() { test::run_shell("umount " + test::shell_quote(dir_)); }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;
  const path& dir() const { return dir_; }
  /// Fills the disk but for `free_kib` KiB (0: full, not a byte free).
  void leave_free(int free_kib) const {
    const auto info = test::fs::space(dir_);
    const auto fill = std::uintmax_t(info.available) - std::uintmax_t(free_kib) * 1024;
    std::ofstream f(dir_ / "fill", std::ios::binary | std::ios::app);
    const std::string chunk(64 * 1024, 'x');
    std::uintmax_t n = 0;
    for (; n + chunk.size() <= fill; n += chunk.size()) f << chunk;
    f.write(chunk.data(), std::streamsize(fill - n));
    f.flush();
    REQUIRE(f);
    if (free_kib == 0) REQUIRE(test::fs::space(dir_).available == 0);
  }

 private:
  path dir_;
};

/// Exit 1, one line "<tool>: error: ..." holding every word; no .partial left in `dir`.
void check_refused(const test::ToolRun& r, const std::string& tool,
                   const std::vector<std::string>& words, const path& dir) {
  test::check_refused(r, tool, words);
  for (const auto& e : test::fs::directory_iterator(dir)) CHECK(e.path().extension() != ".partial");
}

}  // namespace

TEST_CASE("exit 1 yet the existing -o replaced: no output is renamed unless all are complete",
          "[robustness][tools][outputs]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "rock-slope.toml", test::Stage::geometry);
  const std::string joints = (tmp / "joints.h5").string();
  SmallDisk disk(tmp, 256);
  disk.leave_free(0);
  const std::string old = "an older output that must survive";
  const path blocks = tmp / "b.h5", vtu = tmp / "x.vtu";
  test::write_text(blocks, old);
  test::write_text(vtu, old);
  // slice-cut -o b.h5 --stats /full/s.json
  check_refused(run_tool("slice-cut", {joints, "-o", blocks.string(), "--stats",
                                       (disk.dir() / "s.json").string(), "-q"}),
                "slice-cut", {"s.json", "No space left on device"}, disk.dir());
  CHECK(test::read_bytes(blocks) == old);
  // slice-export -o x.vtu --joints /full/j.vtu
  check_refused(run_tool("slice-export", {geom, "--format", "vtu", "-o", vtu.string(), "--joints",
                                          (disk.dir() / "j.vtu").string(), "-q"}),
                "slice-export", {"j.vtu"}, disk.dir());
  CHECK(test::read_bytes(vtu) == old);
  // slice-export --format 3dec -o m.3dgrid --3dec-commands /full/m.dat
  const path grid = tmp / "m.3dgrid";
  test::write_text(grid, old);
  check_refused(
      run_tool("slice-export", {geom, "--format", "3dec", "-o", grid.string(), "--3dec-commands",
                                (disk.dir() / "m.dat").string(), "-q"}),
      "slice-export", {"m.dat"}, disk.dir());
  CHECK(test::read_bytes(grid) == old);
  for (const auto& e : test::fs::directory_iterator(tmp.path()))
    CHECK(e.path().extension() != ".partial");
}

TEST_CASE("a full disk crashed: every tool answers it with exit 1 and one line",
          "[robustness][tools][outputs]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "tunnel.toml", test::Stage::geometry);
  const std::string joints = (tmp / "joints.h5").string(), blocks = (tmp / "blocks.h5").string();
  // Free space at which each tool fails at once (0: not a byte, so every output fails, however
  // small), early (its first datasets) and late (the bulk of the blocks, /geometry, written by
  // slice-vertices' writing thread).
  for (const int free_kib : {0, 64, 600, 1500}) {
    CAPTURE(free_kib);
    SmallDisk disk(tmp, 2048);
    disk.leave_free(free_kib);
    const auto out = [&](const char* name) { return (disk.dir() / name).string(); };
    const struct {
      std::string tool;
      std::vector<std::string> args;
    } runs[] = {
        {"slice-joints", {test::data_path("tunnel.toml").string(), "-o", out("j.h5")}},
        {"slice-cut", {joints, "-o", out("b.h5")}},
        {"slice-prune", {blocks, "-o", out("p.h5")}},
        {"slice-vertices", {blocks, "-o", out("g.h5")}},
        {"slice-cut", {joints, "--prune", "-o", out("b.h5"), "--stats", out("s.json")}},
        {"slice-export", {geom, "--format", "yade", "-o", out("m.py")}},
        {"slice-extract", {geom, "--sphere", "15,10,15,8", "-o", out("s.h5")}},
        {"slice-export", {geom, "--format", "yade-potential-blocks", "-o", out("pb.py")}},
        {"slice-export", {geom, "--format", "3dec", "-o", out("m.3dgrid")}},
        {"slice-export", {geom, "--format", "vtu", "-o", out("m.vtu"), "--joints", out("j.vtu")}},
        {"slice-export", {geom, "--format", "vtu", "--vtu-compressor", "none", "-o", out("m.vtu")}},
        {"slice-bench-lp",
         {"-o", out("lp.csv"), "--rows", "8", "--count", "10", "--ipopt-count", "1", "--batch", "0",
          "--repeat", "1"}},
    };
    // slice-info writes nothing: it is the one tool not here.
    for (const auto& r : runs) {
      CAPTURE(r.tool);
      auto args = r.args;
      args.push_back("-q");
      const auto got = run_tool(r.tool, args);
      if (got.exit_code == 0 && free_kib > 0) continue;  // it fitted (joints.h5 is small)
      check_refused(got, r.tool, {"No space left on device"}, disk.dir());
      CHECK_THAT(got.err, !Catch::Contains("HDF5-DIAG"));
    }
  }
}

TEST_CASE("two runs on one -o: the second is refused while the first writes",
          "[robustness][tools][outputs]") {
  test::TempDir tmp;
  // A 125,313-block geometry takes about a second to write: long enough to start a second run.
  const std::string blocks = test::table3_2m_blocks(tmp);
  const path out = tmp / "g.h5", partial = tmp / "g.h5.partial";
  const pid_t pid = test::spawn_tool("slice-vertices", {blocks, "-o", out.string(), "-q"});
  const auto t0 = std::chrono::steady_clock::now();
  while (!test::fs::exists(partial) &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  REQUIRE(test::fs::exists(partial));
  ::kill(pid, SIGSTOP);  // the first run is alive, its .partial half written
  const auto second = run_tool("slice-vertices", {blocks, "-o", out.string(), "-q"});
  ::kill(pid, SIGCONT);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  INFO(second.err);
  CHECK(second.exit_code == 1);
  CHECK_THAT(second.err, Catch::Contains("another run is writing it"));
  CHECK(std::count(second.err.begin(), second.err.end(), '\n') == 1);
  // The first run was not disturbed: it finished and its output is whole.
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK_FALSE(test::fs::exists(partial));
  CHECK(run_tool("slice-info", {out.string()}).exit_code == 0);
}

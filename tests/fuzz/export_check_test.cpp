// fuzz_export's oracle checked on outputs made by hand (.ci/fuzz runs it before fuzzing): each
// broken output must stop the run (fuzz::finding aborts), each sound one must pass. A check
// that stops finding what it is for would let fuzz_export pass anything.
#include "export_check.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <string>

namespace {

int cases = 0, wrong = 0;

// Runs `check` in a child process (a finding aborts it) and compares with `broken`.
void expect(bool broken, const char* name, const std::function<void()>& check) {
  ++cases;
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) std::abort();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stderr);  // the finding's line: expected
    check();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  const bool found = !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  if (found != broken) {
    std::fprintf(stderr, "export_check_test: %s: %s\n", name,
                 found ? "a sound output is taken for broken" : "a broken output passes");
    ++wrong;
  }
}

}  // namespace

int main() {
  slice::ThreeDecStats st{};
  st.gridpoints = 3, st.faces = 1, st.blocks = 1, st.contacts = 0;
  const std::string grid =
      "* comment\nTOL 1e-6\nG 1 0 0 0\nG 2 1 0 0\nG 3 0 1 0\nF 1 1 2 3\nB 1 1 F 1 1 1\n";
  expect(false, "a sound grid", [&] { fuzz::check_grid(grid, st); });
  expect(true, "a grid with nan", [&] { fuzz::check_grid("G 1 nan 0 0\n", st); });
  expect(true, "a grid not ending a line", [&] { fuzz::check_grid("TOL 1", st); });
  expect(true, "grid counts not the stats'", [&] {
    slice::ThreeDecStats more = st;
    more.faces = 2;
    fuzz::check_grid(grid, more);
  });
  expect(true, "a face of gridpoints below it",
         [&] { fuzz::check_grid("G 1 0 0 0\nF 1 1 2 3\n", st); });
  expect(true, "a contact of a block with itself",
         [&] { fuzz::check_grid(grid + "JS 1 1-1\n", st); });
  expect(true, "a grid with \\r", [&] { fuzz::check_grid("* a\rb\n", st); });
  expect(false, "sound commands", [&] {
    fuzz::check_commands(
        "; nan\nmodel new\nblock import filename \"a nan\"\nmodel gravity 0 0 -9.81\n");
  });
  expect(true, "a command with inf", [&] { fuzz::check_commands("model gravity 0 0 inf\n"); });
  expect(true, "a command the writer never writes", [&] { fuzz::check_commands("model solve\n"); });
  const std::string py =
      "# it's\nA = '''a\nb'''\nBLOCKS = [\n  (1, 2e+30, \"s\\\"q\"),\n]\nx = nan_value + 1e5 + "
      "1.e3\n";
  expect(false, "a sound script", [&] { fuzz::check_python(py, 1, "m.py"); });
  expect(true, "BLOCKS rows not the bodies", [&] { fuzz::check_python(py, 2, "m.py"); });
  expect(true, "the name nan", [&] { fuzz::check_python("BLOCKS = [\n(nan,)\n]\n", 1, "m.py"); });
  expect(true, "the name inf", [&] { fuzz::check_python("BLOCKS = [\n]\nx = inf\n", 0, "m.py"); });
  expect(true, "a string open at the line's end",
         [&] { fuzz::check_python("BLOCKS = [\n]\nx = 'a\n", 0, "m.py"); });
  expect(true, "a string never closed",
         [&] { fuzz::check_python("BLOCKS = [\n]\nx = '''a\n", 0, "m.py"); });
  expect(true, "a bracket closed wrong",
         [&] { fuzz::check_python("BLOCKS = [\n]\nx = (1]\n", 0, "m.py"); });
  expect(true, "a bracket left open",
         [&] { fuzz::check_python("BLOCKS = [\n]\nx = (1\n", 0, "m.py"); });
  expect(true, "no UTF-8", [&] { fuzz::check_python("BLOCKS = [\n]\n# \xff\n", 0, "m.py"); });
  expect(true, "a \\r in a comment",
         [&] { fuzz::check_python("BLOCKS = [\n]\n# a\rb\n", 0, "m.py"); });
  expect(true, "no BLOCKS list", [&] { fuzz::check_python("x = 1\n", 0, "m.py"); });
  std::fprintf(stderr, "export_check_test: %d of %d cases right\n", cases - wrong, cases);
  return wrong == 0 ? 0 : 1;
}

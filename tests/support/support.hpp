#pragma once
// Test helpers shared by every test folder.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "slice/mesh.hpp"

namespace test {

namespace fs = std::filesystem;

/// A fresh directory under the system temp dir, removed with its content on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

/// A file of the repository's data/ folder, e.g. data_path("cube-3sets.toml").
fs::path data_path(const std::string& name);
/// A file of tests/data/ (small inputs made for the tests).
fs::path test_data_path(const std::string& name);

/// Writes text to a file (for bad-input scenes made inside a test).
void write_text(const fs::path& file, const std::string& text);
/// The whole content of a file, as bytes.
std::string read_bytes(const fs::path& file);

/// An ASCII STL file of the mesh's triangles (for the mesh tests).
std::string ascii_stl(const slice::TriangleMesh& mesh);

/// The message of the slice::Error that `f` throws ("" if it throws none).
std::string error_of(const std::function<void()>& f);

/// Point in polygon by the crossing number (the polygon in either orientation).
bool in_polygon(const std::vector<slice::Vec2>& polygon, const slice::Vec2& x);

struct ToolRun {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
/// Runs a built tool (e.g. "slice-joints") with arguments, no shell quoting issues for plain
/// paths; stdin is /dev/null.
ToolRun run_tool(const std::string& tool, const std::vector<std::string>& args);
/// s as one /bin/sh word: in single quotes, any single quote in it escaped.
std::string shell_quote(const std::string& s);
inline std::string shell_quote(const fs::path& p) { return shell_quote(p.string()); }

/// Runs any command line through /bin/sh; returns its exit code.
int run_shell(const std::string& command);
/// Runs `yade -n -x script args...` with its output in `log`; returns the exit code. Requires
/// yade on PATH (pipelines/setup installs it): a test fails, never skips, without it.
int run_yade(const std::string& script, const std::string& args, const fs::path& log);
/// Runs tests/data/yade_report.py on a model script: YADE writes the JSON `report` of what it
/// built and ran; its output goes to `log`. Returns YADE's exit code.
int run_yade_report(const fs::path& model, const fs::path& report, const fs::path& log);
/// The last `n` bytes of a file (a log, for a failing test's message).
/// The numbers of a line of Python tuples ("(1, 2.5, (3, 4)),"): parentheses and commas
/// dropped.
std::vector<double> numbers(const std::string& line);
std::string tail_of(const fs::path& file, std::size_t n = 2000);

/// The share of the property tests' random cases to run: $SLICE_PROPERTY_SCALE, a number in
/// (0, 1]; 1 (every case) when unset. The sanitizer run (.ci/sanitize) sets a fraction, so the
/// same tests make the same assertions on fewer random cases. Any other value throws (the test
/// fails and says why) rather than silently running all or none.
double property_scale();
/// How many of `full` random cases to run: full x property_scale(), rounded to a multiple of
/// `granule` (cases that come in groups, e.g. one block's 56 LPs), at least one granule.
long scaled_cases(long full, long granule = 1);

}  // namespace test

#include "support/support.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "slice/error.hpp"

namespace test {

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = fs::temp_directory_path() /
          ("rockslice-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

fs::path data_path(const std::string& name) { return fs::path(SLICE_DATA_DIR) / name; }
fs::path test_data_path(const std::string& name) { return fs::path(SLICE_TEST_DATA_DIR) / name; }

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  // In blocks, not a character at a time through istreambuf_iterator: the tests compare whole
  // HDF5 files of several MB this way, and the per-character loop was 12 % of the streamed
  // /geometry test's time (h5io_geometry_test.cpp, -O3). Any size (a pipe, a growing log): read
  // to the end.
  std::string bytes, block(std::size_t(1) << 16, '\0');
  while (in.read(block.data(), static_cast<std::streamsize>(block.size())) || in.gcount() > 0)
    bytes.append(block.data(), static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw std::runtime_error("cannot read " + file.string());
  return bytes;
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

int run_shell(const std::string& command) {
  const int status = std::system(command.c_str());
  if (status == -1) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

ToolRun run_tool(const std::string& tool, const std::vector<std::string>& args) {
  TempDir tmp;
  std::string cmd = shell_quote((fs::path(SLICE_TOOLS_DIR) / tool).string());
  for (const auto& a : args) {
    cmd += ' ';
    cmd += shell_quote(a);
  }
  cmd += " </dev/null >";
  cmd += shell_quote((tmp / "out").string());
  cmd += " 2>";
  cmd += shell_quote((tmp / "err").string());
  ToolRun r;
  r.exit_code = run_shell(cmd);
  r.out = read_bytes(tmp / "out");
  r.err = read_bytes(tmp / "err");
  return r;
}

double property_scale() {
  const char* v = std::getenv("SLICE_PROPERTY_SCALE");
  if (v == nullptr || *v == '\0') return 1.0;
  char* end = nullptr;
  const double x = std::strtod(v, &end);
  if (*end != '\0' || !(x > 0 && x <= 1))
    throw std::runtime_error(std::string("SLICE_PROPERTY_SCALE is \"") + v +
                             "\"; give a number in (0, 1], the share of random cases to run");
  return x;
}

long scaled_cases(long full, long granule) {
  const double groups =
      std::round(static_cast<double>(full) * property_scale() / static_cast<double>(granule));
  return std::max(1L, static_cast<long>(groups)) * granule;
}

std::string ascii_stl(const slice::TriangleMesh& mesh) {
  std::ostringstream s;
  s.precision(17);
  s << "solid mesh\n";
  for (const auto& t : mesh.triangles) {
    s << " facet normal 0 0 0\n  outer loop\n";
    for (const auto k : t) {
      const slice::Vec3& x = mesh.vertices[std::size_t(k)];
      s << "   vertex " << x.x() << ' ' << x.y() << ' ' << x.z() << "\n";
    }
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid mesh\n";
  return s.str();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const slice::Error& e) {
    return e.what();
  }
  return "";
}

bool in_polygon(const std::vector<slice::Vec2>& p, const slice::Vec2& x) {
  bool in = false;
  for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++)
    if ((p[i].y() > x.y()) != (p[j].y() > x.y()) &&
        x.x() < (p[j].x() - p[i].x()) * (x.y() - p[i].y()) / (p[j].y() - p[i].y()) + p[i].x())
      in = !in;
  return in;
}

int run_yade(const std::string& script, const std::string& args, const fs::path& log) {
  REQUIRE(run_shell("command -v yade >/dev/null 2>&1") == 0);  // pipelines/setup installs it
  return run_shell("yade -n -x " + shell_quote(script) + " " + args + " </dev/null >" +
                   shell_quote(log.string()) + " 2>&1");
}

int run_yade_report(const fs::path& model, const fs::path& report, const fs::path& log) {
  return run_yade(test_data_path("yade_report.py").string(),
                  shell_quote(model) + " " + shell_quote(report), log);
}

std::vector<double> numbers(const std::string& line) {
  std::string s = line;
  for (char& c : s)
    if (c == '(' || c == ')' || c == ',') c = ' ';
  std::istringstream in(s);
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  return v;
}

std::string tail_of(const fs::path& file, std::size_t n) {
  const std::string text = read_bytes(file);
  return text.substr(text.size() > n ? text.size() - n : 0);
}

}  // namespace test

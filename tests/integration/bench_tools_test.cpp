// slice-bench-lp end to end on small sets: the CSV docs/benchmarks.md's table and plot come from.
// It asserts what the tool writes and what exact certifies, never a time.
#include <catch2/catch.hpp>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/support.hpp"

using test::run_tool;

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
  return out;
}

}  // namespace

TEST_CASE("slice-bench-lp writes one CSV row per backend, problem and size", "[tools][bench]") {
  test::TempDir tmp;
  const auto csv = (tmp / "lp.csv").string();
  const auto run =
      run_tool("slice-bench-lp", {"-q", "-o", csv, "--rows", "8,20", "--count", "60",
                                  "--ipopt-count", "6", "--batch", "3", "--repeat", "2"});
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  std::ifstream in(csv);
  std::string line;
  REQUIRE(std::getline(in, line));
  CHECK(line == "backend,problem,rows,count,median_us,p90_us,max_abs_err,wrong_decisions");
  std::map<std::string, int> rows_of;  // backend -> rows in the CSV
  while (std::getline(in, line)) {
    const auto cells = split(line);
    REQUIRE(cells.size() == 8);
    CAPTURE(line);
    ++rows_of[cells[0]];
    const double median = std::stod(cells[4]), p90 = std::stod(cells[5]);
    CHECK(median > 0);
    CHECK(p90 >= median);
    CHECK(std::stoi(cells[3]) == (cells[0].rfind("ipopt", 0) == 0 ? 6 : 60));
    if (cells[0] == "exact") CHECK(std::stod(cells[6]) == 0);  // the reference itself
    if (cells[0] == "native") {
      CHECK(std::stod(cells[6]) < 1e-12);  // L = 1
      CHECK(cells[7] == "0");
    }
  }
  // 3 problems x 2 sizes for exact, native and ipopt; ipopt_batch for the 2 cut problems.
  CHECK(rows_of["exact"] == 6);
  CHECK(rows_of["native"] == 6);
  CHECK(rows_of["ipopt"] == 6);
  CHECK(rows_of["ipopt_batch"] == 4);
}

TEST_CASE("slice-bench-lp refuses a bad option with exit 1", "[tools][bench]") {
  test::TempDir tmp;
  const auto csv = tmp / "lp.csv";
  const auto run = run_tool("slice-bench-lp", {"-o", csv.string(), "--repeat", "0"});
  CHECK(run.exit_code == 1);
  CHECK_FALSE(std::filesystem::exists(csv));
}

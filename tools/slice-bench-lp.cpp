// slice-bench-lp: time against error of every LP backend on the same generated LP sets
// (docs/benchmarks.md, "LP backends"). A benchmark, not a test: it measures and reports, it asserts
// nothing.
//
// Sets: blocks of 8, 20, 50 and 200 LP rows (random planes tangent to a sphere, as the property
// tests make them), with
//   cut          a persistent plane: 60% at a random offset from the block's inscribed sphere,
//                20% touching the block (a supporting plane), 20% within 1e-13..1e-6 L of it
//   cut_polygon  the same planes with a 4-gon (8 rows) or 6-gon as the joint's extent; the
//                block has rows - edges faces
//   chebyshev    the block's Chebyshev ball (eq. 18)
// Errors are against exact (CGAL over Gmpzf); L = 1. Timing: steady_clock around each call of
// the library function (building the LP from the faces included); native, near the clock's
// resolution, is timed over groups of `--group` consecutive, different LPs (not one LP
// repeated, which would train the branch predictor on it), its median and p90 over the
// groups' per-LP times; each group is solved once to warm the caches (as in a run that slices
// one block after another), then timed `--repeat` times and the fastest kept: on a shared VM
// another job's burst only ever adds time, so the minimum is the code's own cost (a single
// timing moved the median by up to 40 % from one minute to the next). ipopt_batch stacks
// `--batch` cut tests into one block-diagonal Ipopt problem (LpSolver::solve_batch) and reports
// the batch time divided by its size (its median and p90 are over batches; count is LPs).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "../tests/support/lp_cases.hpp"  // header-only generators shared with the tests
#include "common/tool.hpp"
#include "slice/error.hpp"
#include "slice/lp.hpp"
#include "slice/output.hpp"

namespace {

using namespace test::lp;
using slice::LpBackend;
using slice::LpStatus;
using Clock = std::chrono::steady_clock;

enum class Problem { cut, cut_polygon, chebyshev };
const char* to_string(Problem p) {
  constexpr const char* names[] = {"cut", "cut_polygon", "chebyshev"};
  return names[static_cast<int>(p)];
}

struct Case {
  std::vector<Face> faces;
  Plane plane;
  std::vector<Plane> edges;
};

/// max n . x over the block, by the exact solver (for touching planes).
double support(slice::LpSolver& exact, const std::vector<Face>& faces, const Vec3& n) {
  slice::DenseLp lp;
  lp.reset(3);
  lp.maximise = true;
  lp.c.head<3>() = n;
  for (const Face& f : faces)
    lp.add_row(slice::LpVec(f.normal.x(), f.normal.y(), f.normal.z(), 0), f.d);
  const auto r = exact.solve(lp);
  if (r.status != LpStatus::optimal)
    throw slice::Error("slice-bench-lp", "a generated block is unbounded", "this is a bug");
  return r.objective;
}

std::vector<Case> make_set(Problem problem, int rows, int count, std::uint64_t seed,
                           slice::LpSolver& exact) {
  std::vector<Case> set;
  Rng rng(seed ^ (static_cast<std::uint64_t>(rows) << 32) ^
          (static_cast<std::uint64_t>(problem) << 48));
  const int n_edges = problem == Problem::cut_polygon ? (rows >= 20 ? 6 : 4) : 0;
  for (int i = 0; i < count; ++i) {
    RandomBlock b = random_block(rng, rows - n_edges, 1.0);
    Case c;
    const Vec3 n = rng.unit_vector();
    const double u = rng.uniform();
    if (u < 0.6) {
      c.plane = {n, n.dot(b.centre) + b.radius * rng.uniform(-3, 3)};
    } else {
      const double h = support(exact, b.faces, n);
      const double delta = u < 0.8 ? 0.0 : rng.log_uniform(-13, -6) * (rng.chance(0.5) ? 1 : -1);
      c.plane = {n, h - delta};
    }
    if (n_edges > 0) {
      // A regular n_edges-gon about a point of the plane near the block.
      const Vec3 e1 = rng.perpendicular(n), e2 = n.cross(e1);
      const Vec3 foot = b.centre - (n.dot(b.centre) - c.plane.d) * n;
      const Vec3 centre = foot + b.radius * rng.uniform(0, 1.5) * rng.perpendicular(n);
      const double r = b.radius * rng.log_uniform(-1, 0.3);
      const double phase = rng.uniform(0, 2 * std::numbers::pi);
      for (int k = 0; k < n_edges; ++k) {
        const double phi = phase + 2 * std::numbers::pi * k / n_edges;
        const Vec3 e = (std::cos(phi) * e1 + std::sin(phi) * e2).normalized();
        c.edges.push_back({e, e.dot(centre) + r * std::cos(std::numbers::pi / n_edges)});
      }
    }
    c.faces = std::move(b.faces);
    set.push_back(std::move(c));
  }
  return set;
}

/// The answer of one case: value (s* or radius), decision (cuts / has interior), status.
struct Answer {
  LpStatus status = LpStatus::failed;
  double value = 0;
  bool decision = false;
};

Answer solve_case(slice::LpSolver& solver, Problem p, const Case& c, const slice::Tolerances& tol) {
  if (p == Problem::chebyshev) {
    const auto r = slice::chebyshev_ball(solver, c.faces, tol);
    return {r.status, r.radius, r.radius > tol.geometry};
  }
  const auto r = slice::cut_test(solver, c.faces, c.plane, c.edges, tol);
  return {r.status, r.s, r.cuts};
}

struct Row {
  Row(std::string b, Problem p, int r) : backend(std::move(b)), problem(p), rows(r) {}
  std::string backend;
  Problem problem;
  int rows = 0;
  std::vector<double> us;  // per-solve times (ipopt_batch: per batch, divided by its size)
  long lps = 0;            // LPs solved
  double max_abs_err = 0;
  long wrong = 0;
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())) - 1);
  return v[std::min(k, v.size() - 1)];
}

void score(Row& row, const Answer& got, const Answer& exact) {
  ++row.lps;
  if (got.status != exact.status) {
    ++row.wrong;
    if (got.status != LpStatus::optimal || exact.status != LpStatus::optimal) {
      row.max_abs_err = std::numeric_limits<double>::infinity();
      return;
    }
  }
  row.max_abs_err = std::max(row.max_abs_err, std::abs(got.value - exact.value));
  row.wrong += got.decision != exact.decision;
}

}  // namespace

int main(int argc, char** argv) {
  tool::Tool t{"slice-bench-lp",
               "Time per solve against error (vs exact) of the LP backends on generated cut "
               "tests and Chebyshev balls; writes a CSV."};
  std::string out;
  std::uint64_t seed = 20150701;
  int count = 2000, ipopt_count = 200, batch = 50, group = 10, repeat = 5;
  std::vector<int> row_counts{8, 20, 50, 200};
  t.cli.add_option("-o,--output", out, "CSV file to write")->required();
  t.cli.add_option("--seed", seed, "seed of the generated sets")->capture_default_str();
  t.cli.add_option("--count", count, "LPs per set for native and exact")
      ->capture_default_str()
      ->check(CLI::Range(1, 10'000'000));
  t.cli.add_option("--ipopt-count", ipopt_count, "LPs per set for ipopt (the first ones)")
      ->capture_default_str()
      ->check(CLI::Range(0, 10'000'000));
  t.cli.add_option("--batch", batch, "cut tests per stacked Ipopt problem (0: no ipopt_batch)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100'000));
  t.cli.add_option("--group", group, "consecutive different LPs per native timing")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  t.cli
      .add_option("--repeat", repeat,
                  "timings per native group after a warm-up; the fastest is kept")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  t.cli.add_option("--rows", row_counts, "LP row counts of the sets")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(8, 100'000));

  return t.run(argc, argv, [&] {
    const auto tol = slice::Tolerances::from_scale(1.0, 1e-9);
    auto native = slice::make_solver(LpBackend::native);
    auto exact = slice::make_solver(LpBackend::exact);
    auto ipopt = slice::make_solver(LpBackend::ipopt);
    std::vector<Row> table;

    for (const Problem problem : {Problem::cut, Problem::cut_polygon, Problem::chebyshev}) {
      for (const int rows : row_counts) {
        const auto set = make_set(problem, rows, count, seed, *exact);
        t.say(std::string("set ") + to_string(problem) + " " + std::to_string(rows) +
              " rows: " + std::to_string(set.size()) + " LPs");
        std::vector<Answer> ref(set.size());
        Row ex{"exact", problem, rows};
        for (std::size_t i = 0; i < set.size(); ++i) {
          const auto t0 = Clock::now();
          ref[i] = solve_case(*exact, problem, set[i], tol);
          ex.us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
          ++ex.lps;
        }
        Row nat{"native", problem, rows};
        std::vector<Answer> got(set.size());
        for (std::size_t begin = 0; begin < set.size(); begin += static_cast<std::size_t>(group)) {
          const std::size_t end = std::min(set.size(), begin + static_cast<std::size_t>(group));
          double us = std::numeric_limits<double>::infinity();
          for (int pass = 0; pass <= repeat; ++pass) {  // pass 0 warms the caches
            const auto t0 = Clock::now();
            for (std::size_t i = begin; i < end; ++i)
              got[i] = solve_case(*native, problem, set[i], tol);
            const double t1 = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
            if (pass > 0) us = std::min(us, t1);
          }
          nat.us.push_back(us / static_cast<double>(end - begin));
        }
        for (std::size_t i = 0; i < set.size(); ++i) score(nat, got[i], ref[i]);
        const auto n_ipopt = std::min(set.size(), static_cast<std::size_t>(ipopt_count));
        Row ip{"ipopt", problem, rows};
        for (std::size_t i = 0; i < n_ipopt; ++i) {
          const auto t0 = Clock::now();
          const Answer a = solve_case(*ipopt, problem, set[i], tol);
          ip.us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
          score(ip, a, ref[i]);
        }
        table.push_back(std::move(ex));
        table.push_back(std::move(nat));
        if (n_ipopt > 0) table.push_back(std::move(ip));

        if (batch > 0 && problem != Problem::chebyshev && n_ipopt > 0) {
          Row ib{"ipopt_batch", problem, rows};
          for (std::size_t begin = 0; begin < n_ipopt; begin += static_cast<std::size_t>(batch)) {
            const std::size_t end = std::min(n_ipopt, begin + static_cast<std::size_t>(batch));
            const auto t0 = Clock::now();
            std::vector<slice::DenseLp> lps(end - begin);
            std::vector<slice::PlaneFrame> frames(end - begin);
            for (std::size_t i = begin; i < end; ++i)
              frames[i - begin] =
                  slice::cut_test_lp(set[i].faces, set[i].plane, set[i].edges, tol, lps[i - begin]);
            std::vector<slice::LpResult> res(end - begin);
            ipopt->solve_batch(lps, res);
            ib.us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() /
                            static_cast<double>(end - begin));
            for (std::size_t i = begin; i < end; ++i) {
              const auto r = slice::cut_test_result(res[i - begin], frames[i - begin], tol);
              score(ib, {r.status, r.s, r.cuts}, ref[i]);
            }
          }
          table.push_back(std::move(ib));
        }
      }
    }

    // Written atomically (output.hpp): a full disk leaves no half CSV and names its reason.
    std::ostringstream csv;
    csv << "backend,problem,rows,count,median_us,p90_us,max_abs_err,wrong_decisions\n";
    csv << std::setprecision(6);
    for (const Row& r : table)
      csv << r.backend << ',' << to_string(r.problem) << ',' << r.rows << ',' << r.lps << ','
          << percentile(r.us, 0.5) << ',' << percentile(r.us, 0.9) << ','
          << (r.backend == "exact" ? 0.0 : r.max_abs_err) << ',' << r.wrong << '\n';
    slice::write_text_file(out, csv.str());

    // Speed-ups per set, for people.
    for (const Row& r : table) {
      if (r.backend != "native") continue;
      std::ostringstream line;
      line << std::fixed << std::setprecision(3) << to_string(r.problem) << " " << r.rows
           << " rows: native " << percentile(r.us, 0.5) << " us";
      for (const Row& o : table)
        if (o.problem == r.problem && o.rows == r.rows && o.backend != "native")
          line << ", " << o.backend << " x" << std::setprecision(0)
               << percentile(o.us, 0.5) / percentile(r.us, 0.5) << std::setprecision(3);
      t.say(line.str());
    }
    t.say("wrote " + out);
  });
}

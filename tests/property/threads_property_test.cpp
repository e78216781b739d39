// Issue 15: threads change nothing but the time. The cut runs on one thread up to
// CutOptions::tasks blocks, then cuts each of those as an independent task; the blocks must come
// out exactly as one sequential subdivision makes them (tasks = 0), for every thread count and
// every task count, and the figures a run reports must not depend on the thread count.
#include <catch2/catch.hpp>
#include <random>
#include <sstream>

#include "slice/cut.hpp"
#include "slice/scene.hpp"
#include "support/blocks_check.hpp"
#include "support/compare.hpp"
#include "support/support.hpp"

namespace {

struct Run {
  slice::BlockSystem blocks;
  slice::CutStats cut;
  slice::PruneStats prune;
};

Run cut(const slice::JointSystem& js, std::size_t tasks, int threads) {
  slice::CutOptions opt;
  opt.tasks = tasks;
  opt.threads = threads;
  auto r = slice::cut_blocks(js, opt);
  Run run{std::move(r.blocks), r.stats, {}};
  run.prune = slice::prune_blocks(run.blocks, opt.backend, {}, false, threads);
  return run;
}

// Every figure but the times.
void check_same_figures(const Run& a, const Run& b) {
  const slice::CutStats &x = a.cut, &y = b.cut;
  CHECK(x.joints == y.joints);
  CHECK(x.joints_missing == y.joints_missing);
  CHECK(x.blocks == y.blocks);
  CHECK(x.splits == y.splits);
  CHECK(x.splits_undone == y.splits_undone);
  CHECK(x.pairs_skipped == y.pairs_skipped);
  CHECK(x.boundary == y.boundary);
  CHECK(x.removed == y.removed);
  CHECK(x.clusters == y.clusters);
  CHECK(x.fixed == y.fixed);
  CHECK(x.lps.cut_test == y.lps.cut_test);
  CHECK(x.lps.extents == y.lps.extents);
  CHECK(x.lps.chebyshev == y.lps.chebyshev);
  CHECK(x.lps.contact == y.lps.contact);
  CHECK(x.lps.failed == y.lps.failed);
  CHECK(x.decisions.resolved == y.decisions.resolved);
  CHECK(x.decisions.checked == y.decisions.checked);
  CHECK(x.decisions.changed == y.decisions.changed);
  CHECK(a.prune.faces_before == b.prune.faces_before);
  CHECK(a.prune.faces_after == b.prune.faces_after);
  CHECK(a.prune.lps == b.prune.lps);
  CHECK(a.prune.decisions.resolved == b.prune.decisions.resolved);
}

// The same blocks whatever the task and thread counts; the same figures for one task count.
void check_thread_invariance(const slice::JointSystem& js) {
  const Run reference = cut(js, 0, 1);  // one sequential subdivision, one thread
  for (const std::size_t tasks :
       {std::size_t(1), std::size_t(7), std::size_t(64), std::size_t(512)}) {
    const Run one = cut(js, tasks, 1);
    CAPTURE(tasks);
    test::check_same(reference.blocks, one.blocks);
    CHECK(one.cut.joints_missing == reference.cut.joints_missing);
    CHECK(one.cut.splits == reference.cut.splits);
    CHECK(one.cut.splits_undone == reference.cut.splits_undone);
    for (const int threads : {2, 3}) {
      CAPTURE(threads);
      const Run many = cut(js, tasks, threads);
      test::check_same(one.blocks, many.blocks);
      check_same_figures(one, many);
    }
  }
}

/// A random scene with all that the cut treats specially: persistent and polygon joints, a
/// boundary joint, construction joints exempt from the limits, a stochastic set, size limits, a
/// removal zone and fixed faces.
std::string random_scene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  std::ostringstream s;
  s.precision(17);
  s << "[scene]\nseed = " << seed << "\n[domain]\nbox = { min = [0, 0, 0], max = [10, 8, 6] }\n";
  s << "[options]\norder = \"" << (seed % 2 ? "as-given" : "largest-first") << "\"\n";
  if (seed % 3 == 0) s << "min_inscribed_diameter = 0.2\n";
  if (seed % 4 == 0) s << "fixed_faces = [\"-z\", \"+x\"]\n";
  s << "[[joints]]\ndip = " << 20 * u01(rng) << "\ndip_direction = " << 359 * u01(rng)
    << "\npoint = [5, 4, " << 1 + u01(rng) << "]\nkind = \"boundary\"\nkeep = \"below\"\n";
  for (int j = 0; j < 4; ++j) {
    s << "[[joints]]\ndip = " << 90 * u01(rng) << "\ndip_direction = " << 359 * u01(rng)
      << "\npoint = [" << 10 * u01(rng) << ", " << 8 * u01(rng) << ", " << 6 * u01(rng) << "]\n";
    if (j % 2) s << "kind = \"construction\"\nlimits = false\n";
  }
  for (int k = 0; k < 3; ++k) {
    s << "[[sets]]\ndip = " << 90 * u01(rng) << "\ndip_direction = " << 359 * u01(rng) << "\n";
    if (k == 0)
      s << "spacing = " << 0.8 + u01(rng) << "\n";
    else
      s << "fisher_kappa = 30\ndensity = " << 0.05 + 0.05 * u01(rng)
        << "\nsize = { distribution = \"lognormal\", mean = 3.0, sd = 1.0 }\n";
  }
  s << "[[zones]]\nbox = { min = [6, 0, 3], max = [10, 8, 6] }\n";
  return s.str();
}

}  // namespace

TEST_CASE("threads and tasks change no block of the example scenes", "[property][threads]") {
  // Smallest first: the sanitizer run (SLICE_PROPERTY_SCALE) takes the first ones.
  const char* scenes[] = {"cube-3sets.toml",      "rock-slope.toml", "genesis-limestone.toml",
                          "slope.toml",           "tunnel.toml",     "table3-persistent.toml",
                          "table3-lognormal.toml"};
  const long count = test::scaled_cases(7);
  for (long k = 0; k < count; ++k) {
    CAPTURE(scenes[k]);
    check_thread_invariance(slice::generate_joints(slice::load_scene(test::data_path(scenes[k]))));
  }
}

TEST_CASE("threads and tasks change no block of random scenes", "[property][threads]") {
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(40))));
  CAPTURE(seed);
  const auto js = slice::generate_joints(slice::parse_scene(random_scene(seed), "random.toml"));
  check_thread_invariance(js);
  // Split into tasks, the blocks still tile the domain without overlap.
  test::check_invariants(cut(js, 7, 2).blocks, 1000, 7);
}

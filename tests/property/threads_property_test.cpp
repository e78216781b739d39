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
  CHECK(x.settled_by_limit == y.settled_by_limit);
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

/// A random scene of polygon joints only (issue 29): two to four stochastic sets of every shape
/// and size distribution, each order, with and without the size and shape limits; the density
/// gives a few hundred to a few thousand blocks, so the default task count splits the cut too.
std::string random_polygon_scene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  const auto pick = [&](std::size_t n) { return std::size_t(u01(rng) * double(n)) % n; };
  std::ostringstream s;
  s.precision(17);
  const double side = 12 + 8 * u01(rng);
  s << "[scene]\nseed = " << seed << "\n[domain]\nbox = { min = [0, 0, 0], max = [" << side << ", "
    << 0.8 * side << ", " << 0.6 * side << "] }\n[options]\n";
  const char* orders[] = {"as-given", "largest-first", "by-set", "alternating"};
  s << "order = \"" << orders[pick(4)] << "\"\n";
  if (seed % 2 == 0) s << "min_inscribed_diameter = " << 0.05 + 0.1 * u01(rng) << "\n";
  if (seed % 3 == 0) s << "max_aspect_ratio = " << 6 + 20 * u01(rng) << "\n";
  const int sets = 2 + int(pick(3));
  for (int k = 0; k < sets; ++k) {
    s << "[[sets]]\ndip = " << 90 * u01(rng) << "\ndip_direction = " << 359 * u01(rng)
      << "\ndensity = " << (0.04 + 0.06 * u01(rng)) * 900 / (side * side * side) << "\n";
    if (k % 2 == 1) s << "fisher_kappa = " << 10 + 40 * u01(rng) << "\n";
    const double mean = 0.25 * side * (0.5 + u01(rng));
    switch (pick(3)) {
      case 0:
        s << "size = { distribution = \"lognormal\", mean = " << mean << ", sd = " << 0.3 * mean
          << " }\n";
        break;
      case 1:
        s << "size = { distribution = \"exponential\", mean = " << mean << " }\n";
        break;
      default:
        s << "size = { distribution = \"fixed\", value = " << mean << " }\n";
    }
    switch (pick(4)) {
      case 0:
        s << "shape = \"square\"\n";
        break;
      case 1:
        s << "shape = \"rectangle\"\naspect = " << 1 + 3 * u01(rng) << "\n";
        break;
      case 2:
        s << "shape = \"polygon\"\nsides = " << 3 + pick(6) << "\n";
        break;
      default:
        s << "shape = \"ellipse\"\nsides = 12\naspect = " << 1 + u01(rng) << "\n";
    }
  }
  return s.str();
}

}  // namespace

TEST_CASE("threads and tasks change no block of random polygon scenes", "[property][threads]") {
  // Polygon joints only: every cut is confined to the blocks its polygon reaches, so the blocks a
  // task is handed and the joints it is given are what threads could get wrong.
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(20))));
  CAPTURE(seed);
  const std::string scene = random_polygon_scene(seed);
  CAPTURE(scene);
  const auto js = slice::generate_joints(slice::parse_scene(scene, "random.toml"));
  for (const auto& j : js.joints) REQUIRE_FALSE(j.persistent());
  check_thread_invariance(js);
  // The default task count on 1, 2 and 3 threads: the same blocks and figures.
  const Run one = cut(js, slice::CutOptions{}.tasks, 1);
  CHECK(one.cut.splits > 50);
  for (const int threads : {2, 3}) {
    const Run many = cut(js, slice::CutOptions{}.tasks, threads);
    test::check_same(one.blocks, many.blocks);
    check_same_figures(one, many);
  }
}

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

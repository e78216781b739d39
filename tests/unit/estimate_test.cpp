// estimate_blocks against the exact Table 3 counts (../shared/reference/table3-block-counts.md)
// and against the slicer.
#include "slice/estimate.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/scene.hpp"
#include "support/support.hpp"

namespace {

slice::JointSystem table3(const std::string& spacing) {
  std::string scene = test::read_bytes(test::data_path("table3-persistent.toml"));
  const std::string to = "spacing = " + spacing;
  for (std::size_t p = 0; (p = scene.find("spacing = 3.7", p)) != std::string::npos; p += to.size())
    scene.replace(p, 13, to);
  return slice::generate_joints(slice::parse_scene(scene, "t.toml"));
}

}  // namespace

TEST_CASE("the arrangement count gives Table 3's exact block counts", "[unit][estimate]") {
  const std::pair<const char*, double> cases[] = {{"10.0", 1334}, {"5.8", 5926},   {"4.6", 11360},
                                                  {"3.7", 21108}, {"2.0", 125313}, {"1.0", 964156}};
  for (const auto& [spacing, blocks] : cases) {
    CAPTURE(spacing);
    const slice::BlockEstimate e = slice::estimate_blocks(table3(spacing));
    CHECK_FALSE(e.sampled);
    CHECK(e.blocks() == blocks);
  }
  const slice::BlockEstimate e = slice::estimate_blocks(table3("1.0"));
  CHECK(e.planes == 385);
  CHECK(e.lines == 37238);
  CHECK(e.points == 926532);
}

TEST_CASE("the estimate equals what the slicer makes of persistent joints", "[unit][estimate]") {
  for (const char* name : {"cube-3sets.toml", "table3-persistent.toml"}) {
    CAPTURE(name);
    const auto js = slice::generate_joints(slice::load_scene(test::data_path(name)));
    const auto r = slice::cut_blocks(js, {});
    CHECK(slice::estimate_blocks(js).blocks() == double(r.stats.blocks));
  }
}

TEST_CASE("absurd cuts are refused up front with the estimate", "[unit][estimate]") {
  // The audit's case: a 1e12 m box, three persistent sets at 1e9 m spacing. The audit guessed
  // ~1e10 blocks; the points alone are volume x |det(n1, n2, n3)| / spacing^3 = 1e36 x 0.93 /
  // 1e27, about 9.3e8 (Table 3 at 1 m: 926,532 points in 1e6 m3).
  std::string scene = test::read_bytes(test::data_path("table3-persistent.toml"));
  scene.replace(scene.find("max = [100, 100, 100]"), 21, "max = [1e12, 1e12, 1e12]");
  for (std::size_t p = 0; (p = scene.find("spacing = 3.7", p)) != std::string::npos; p += 13)
    scene.replace(p, 13, "spacing = 1e9");
  const auto js = slice::generate_joints(slice::parse_scene(scene, "big.toml"));
  const slice::BlockEstimate e = slice::estimate_blocks(js);
  CHECK_FALSE(e.sampled);
  CHECK(e.planes == 3863);
  CHECK(e.blocks() > 9e8);
  CHECK(e.blocks() < 1e9);
  try {
    (void)slice::cut_blocks(js, {});
    FAIL("cut_blocks accepted ~1e10 blocks");
  } catch (const slice::Error& err) {
    CHECK_THAT(err.what(), Catch::Contains("more than max_blocks = 2000000"));
    CHECK_THAT(err.what(), Catch::Contains("raise max_blocks"));
  }
  // A lower limit on the command line's behalf refuses the Table 3 scene at 3.7 m (21,108).
  slice::CutOptions opt;
  opt.max_blocks = 20000;
  CHECK_THROWS_WITH(slice::cut_blocks(table3("3.7"), opt),
                    Catch::Contains("21108 blocks") && Catch::Contains("max_blocks = 20000"));
}

TEST_CASE("polygon joints past max_blocks stop the cut as it runs", "[unit][estimate]") {
  auto js = slice::generate_joints(slice::load_scene(test::data_path("table3-lognormal.toml")));
  slice::CutOptions opt;
  opt.max_blocks = 500;
  // Tasks run in any order, so the message names no joint: the same for every thread count.
  for (const int threads : {1, 2}) {
    opt.threads = threads;
    CHECK_THROWS_WITH(slice::cut_blocks(js, opt),
                      Catch::Contains("the cut passed max_blocks = 500 blocks; raise max_blocks"));
  }
}

TEST_CASE("past the budget a strided sample of the pairs extrapolates the count",
          "[unit][estimate]") {
  // 0.0052 m spacing: 74,000 planes, 1.8e9 pairs; the points dominate and follow
  // volume x |det(n1, n2, n3)| / spacing^3 (each set's planes are evenly spaced).
  const auto js = table3("0.0052");
  const slice::BlockEstimate e = slice::estimate_blocks(js);
  CHECK(e.sampled);
  slice::Vec3 n[3];
  for (const auto& j : js.joints) n[j.set] = j.plane.normal;
  const double points = 1e6 * std::abs(n[0].dot(n[1].cross(n[2]))) / std::pow(0.0052, 3);
  CHECK_THAT(e.points, Catch::Matchers::WithinRel(points, 0.01));
  CHECK(e.blocks() > e.points);
}

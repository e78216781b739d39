// Slicing invariants on the examples and on random scenes (fixed seeds).
#include <catch2/catch.hpp>
#include <random>
#include <sstream>

#include "slice/cut.hpp"
#include "slice/lp.hpp"
#include "slice/scene.hpp"
#include "support/blocks_check.hpp"
#include "support/support.hpp"

using slice::Vec3;

namespace {

slice::BlockSystem slice_all(const slice::JointSystem& js, bool use_index = true) {
  slice::CutOptions opt;
  opt.use_index = use_index;
  auto r = slice::cut_blocks(js, opt);
  slice::prune_blocks(r.blocks, opt.backend);
  return std::move(r.blocks);
}

/// A random scene: a box, persistent and polygon joints of random orientation.
std::string random_scene(std::uint64_t seed, const Vec3& shift, double scale) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  std::ostringstream s;
  s.precision(17);
  const Vec3 lo = shift, hi = shift + scale * Vec3(4, 3, 2);
  s << "[domain]\nbox = { min = [" << lo.x() << ", " << lo.y() << ", " << lo.z() << "], max = ["
    << hi.x() << ", " << hi.y() << ", " << hi.z() << "] }\n";
  const int joints = 6 + int(seed % 7);
  for (int j = 0; j < joints; ++j) {
    const double dip = 90 * u01(rng), dd = 359.9 * u01(rng);
    const Vec3 p = shift + scale * Vec3(4 * u01(rng), 3 * u01(rng), 2 * u01(rng));
    s << "[[joints]]\ndip = " << dip << "\ndip_direction = " << dd << "\npoint = [" << p.x() << ", "
      << p.y() << ", " << p.z() << "]\n";
    if (u01(rng) < 0.5) {  // a square polygon in its own plane, 1 to 3 units across
      const double h = scale * (0.5 + u01(rng));
      s << "polygon_uv = [[" << -h << ", " << -h << "], [" << h << ", " << -h << "], [" << h << ", "
        << h << "], [" << -h << ", " << h << "]]\n";
    }
  }
  return s.str();
}

}  // namespace

TEST_CASE("invariants hold on the example scenes", "[property][cut]") {
  for (const char* name : {"cube-3sets.toml", "rock-slope.toml"}) {
    CAPTURE(name);
    const auto js = slice::generate_joints(slice::load_scene(test::data_path(name)));
    test::check_invariants(slice_all(js), 100000, 7);
  }
}

TEST_CASE("invariants hold on random scenes", "[property][cut]") {
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(30))));
  CAPTURE(seed);
  const auto js = slice::generate_joints(
      slice::parse_scene(random_scene(seed, Vec3::Zero(), 1.0), "random.toml"));
  const auto bs = slice_all(js);
  test::check_invariants(bs, 20000, seed);
}

TEST_CASE("results do not depend on a 1e6 m offset or on units", "[property][cut]") {
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(10))));
  CAPTURE(seed);
  const auto base = slice_all(
      slice::generate_joints(slice::parse_scene(random_scene(seed, Vec3::Zero(), 1.0), "a.toml")));
  const Vec3 shift(5e5, 5e6, 300);
  const auto moved = slice_all(
      slice::generate_joints(slice::parse_scene(random_scene(seed, shift, 1.0), "b.toml")));
  const auto mm = slice_all(slice::generate_joints(
      slice::parse_scene(random_scene(seed, Vec3::Zero(), 1000.0), "c.toml")));
  const auto km = slice_all(
      slice::generate_joints(slice::parse_scene(random_scene(seed, Vec3::Zero(), 1e-3), "d.toml")));
  REQUIRE(moved.blocks.size() == base.blocks.size());
  REQUIRE(mm.blocks.size() == base.blocks.size());
  REQUIRE(km.blocks.size() == base.blocks.size());
  for (std::size_t i = 0; i < base.blocks.size(); ++i) {
    CAPTURE(i);
    const auto& a = base.blocks[i];
    for (const auto* other : {&moved, &mm, &km}) {
      const auto& b = other->blocks[i];
      REQUIRE(b.faces.size() == a.faces.size());
      for (std::size_t f = 0; f < a.faces.size(); ++f) CHECK(b.faces[f].joint == a.faces[f].joint);
    }
    CHECK_THAT(km.blocks[i].inradius, Catch::Matchers::WithinRel(1e-3 * a.inradius, 1e-9));
    CHECK_THAT(moved.blocks[i].origin.x() - shift.x(),
               Catch::Matchers::WithinAbs(a.origin.x(), 1e-6));
    CHECK_THAT(moved.blocks[i].origin.y() - shift.y(),
               Catch::Matchers::WithinAbs(a.origin.y(), 1e-6));
    CHECK_THAT(moved.blocks[i].inradius, Catch::Matchers::WithinRel(a.inradius, 1e-6));
    CHECK_THAT(mm.blocks[i].inradius, Catch::Matchers::WithinRel(1000 * a.inradius, 1e-9));
    // At 5e6 m a double carries 5e6 * 2^-53 = 6e-10 m of rounding in every input coordinate,
    // so the shifted scene agrees to the scene tolerance (1e-9 L, L = 2.7 m), not to 1e-9
    // of a small block's inradius.
    CHECK_THAT(moved.blocks[i].inradius,
               Catch::Matchers::WithinAbs(a.inradius, 1e-9 * base.joints.length_scale));
  }
}

TEST_CASE("pruning keeps exactly the faces the redundancy LPs keep", "[property][cut][prune]") {
  // prune_blocks keeps a face without an LP when a point of it is surely inside the others;
  // here every face is decided by the exact LP against the faces kept so far, as eq. 8 says,
  // with the blocks' origins at their Chebyshev centres (as cut) and moved away (as a file may
  // have them).
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(30))));
  CAPTURE(seed);
  const auto js = slice::generate_joints(
      slice::parse_scene(random_scene(seed, Vec3(1e5, -2e3, 7), 1.0), "random.toml"));
  auto cut = slice::cut_blocks(js, slice::CutOptions{});
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2, 2);
  for (const bool moved : {false, true}) {
    CAPTURE(moved);
    slice::BlockSystem bs = cut.blocks;
    if (moved)
      for (auto& b : bs.blocks) {
        const Vec3 shift(u(rng), u(rng), u(rng));
        for (auto& f : b.faces) f.d -= f.normal.dot(shift);
        b.origin += shift;
      }
    const slice::Tolerances tol =
        slice::Tolerances::from_scale(js.length_scale, js.options.tolerance);
    auto exact = slice::make_solver(slice::LpBackend::exact);
    std::vector<std::vector<slice::Face>> expected;
    for (const auto& b : bs.blocks) {
      auto faces = b.faces;
      for (std::size_t f = 0; f < faces.size();) {
        if (slice::face_redundancy(*exact, faces, f, tol).redundant)
          faces.erase(faces.begin() + std::ptrdiff_t(f));
        else
          ++f;
      }
      expected.push_back(std::move(faces));
    }
    for (const bool check_solids : {true, false}) {
      auto pruned = bs;
      const auto st =
          slice::prune_blocks(pruned, slice::LpBackend::native, {}, false, 1, check_solids);
      CHECK(st.certified > 0);
      REQUIRE(pruned.blocks.size() == expected.size());
      for (std::size_t i = 0; i < expected.size(); ++i) {
        const auto& got = pruned.blocks[i].faces;
        REQUIRE(got.size() == expected[i].size());
        for (std::size_t f = 0; f < got.size(); ++f) {
          CHECK(got[f].normal == expected[i][f].normal);
          CHECK(got[f].d == expected[i][f].d);
        }
      }
    }
  }
}

TEST_CASE("every block's bounding sphere is that of its extents", "[property][cut]") {
  // A piece keeps the extremes its parent reaches inside it (no LP): the spheres must still be
  // the six extents LPs' on the piece's own faces.
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(30))));
  CAPTURE(seed);
  const auto js = slice::generate_joints(
      slice::parse_scene(random_scene(seed, Vec3(-3e4, 2e5, 1e3), 1.0), "random.toml"));
  const auto r = slice::cut_blocks(js, slice::CutOptions{});
  CHECK(r.stats.lps.extents < 6 * (2 * r.stats.splits + 1));  // some were inherited
  const slice::Tolerances tol =
      slice::Tolerances::from_scale(js.length_scale, js.options.tolerance);
  auto exact = slice::make_solver(slice::LpBackend::exact);
  const double eps = 1e-12 * js.length_scale;
  for (const auto& b : r.blocks.blocks) {
    const slice::Extents e = slice::extents(*exact, b.faces, tol);
    REQUIRE(e.status == slice::LpStatus::optimal);
    CHECK((b.origin + e.centre - b.bsphere.head<3>()).norm() <= eps);
    CHECK(std::abs(e.radius - b.bsphere[3]) <= eps);
  }
}

TEST_CASE("the grid index changes nothing but the work", "[property][cut]") {
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(10))));
  CAPTURE(seed);
  const auto js = slice::generate_joints(
      slice::parse_scene(random_scene(seed, Vec3::Zero(), 1.0), "random.toml"));
  const auto a = slice_all(js, true), b = slice_all(js, false);
  REQUIRE(a.blocks.size() == b.blocks.size());
  for (std::size_t i = 0; i < a.blocks.size(); ++i) {
    CHECK(a.blocks[i].origin == b.blocks[i].origin);
    CHECK(a.blocks[i].faces.size() == b.blocks[i].faces.size());
  }
}

TEST_CASE("the paper's Table 3 scene gives the reference block counts", "[property][cut][table3]") {
  // reference/table3-block-counts.md: counted by one LP per cell, independent of the slicer.
  struct Case {
    double spacing;
    std::size_t joints, blocks;
  };
  const auto c = GENERATE(Case{10.0, 38, 1334}, Case{5.8, 67, 5926}, Case{4.6, 84, 11360},
                          Case{3.7, 103, 21108});
  CAPTURE(c.spacing);
  std::string text = test::read_bytes(test::data_path("table3-persistent.toml"));
  const auto pos = text.find("spacing = 3.7");
  REQUIRE(pos != std::string::npos);
  std::string replaced = text;
  std::size_t at = 0;
  while ((at = replaced.find("spacing = 3.7", at)) != std::string::npos)
    replaced.replace(at, 13, "spacing = " + std::to_string(c.spacing)), at += 10;
  const auto js = slice::generate_joints(slice::parse_scene(replaced, "table3.toml"));
  REQUIRE(js.joints.size() == c.joints);
  slice::CutOptions opt;
  const auto r = slice::cut_blocks(js, opt);
  CHECK(r.blocks.blocks.size() == c.blocks);
  double volume = 0;
  auto pruned = r.blocks;
  slice::prune_blocks(pruned, opt.backend);
  for (const auto& b : pruned.blocks) volume += test::block_volume(b, 1e-9 * js.length_scale);
  CHECK_THAT(volume, Catch::Matchers::WithinRel(1e6, 1e-9));
}

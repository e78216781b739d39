// slice-cut's library: hand-checkable scenes with known answers, and the degenerate inputs of
// DESIGN section 10.
#include "slice/cut.hpp"

#include <catch2/catch.hpp>
#include <sstream>

#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "support/blocks_check.hpp"
#include "support/support.hpp"

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;

namespace {

slice::BlockSystem cut(const std::string& scene, bool prune = true,
                       slice::LpBackend backend = slice::LpBackend::native,
                       slice::CutStats* stats = nullptr) {
  const auto js = slice::generate_joints(slice::parse_scene(scene, "test.toml"));
  slice::CutOptions opt;
  opt.backend = backend;
  auto r = slice::cut_blocks(js, opt);
  if (prune) slice::prune_blocks(r.blocks, backend);
  if (stats) *stats = r.stats;
  return std::move(r.blocks);
}

const std::string kUnitCube = "[domain]\nbox = { min = [0, 0, 0], max = [1, 1, 1] }\n";

std::string joint(double dip, double dd, const Vec3& p, const std::string& extra = "") {
  std::ostringstream s;
  s.precision(17);
  s << "[[joints]]\ndip = " << dip << "\ndip_direction = " << dd << "\npoint = [" << p.x() << ", "
    << p.y() << ", " << p.z() << "]\n"
    << extra;
  return s.str();
}

}  // namespace

TEST_CASE("cube-3sets gives 1000 unit cubes with 6 faces each", "[cut]") {
  const auto js = slice::generate_joints(slice::load_scene(test::data_path("cube-3sets.toml")));
  auto r = slice::cut_blocks(js, {});
  const auto ps = slice::prune_blocks(r.blocks, slice::LpBackend::native);
  const auto& blocks = r.blocks.blocks;
  REQUIRE(blocks.size() == 1000);
  CHECK(r.stats.splits == 999);
  CHECK(ps.faces_after == 6000);
  const auto solver = slice::make_solver(slice::LpBackend::native);
  const auto tol = slice::Tolerances::from_scale(js.length_scale, js.options.tolerance);
  for (const auto& b : blocks) {
    CHECK(b.faces.size() == 6);
    CHECK_THAT(b.inradius, WithinRel(0.5, 1e-12));
    const auto e = slice::extents(*solver, b.faces, tol);
    for (int k = 0; k < 3; ++k) CHECK_THAT(e.max[k] - e.min[k], WithinRel(1.0, 1e-12));
    // The Chebyshev centre of a unit cube of the grid is at a half-integer point.
    for (int k = 0; k < 3; ++k)
      CHECK_THAT(b.origin[k] - std::floor(b.origin[k]), WithinAbs(0.5, 1e-12));
  }
  CHECK(r.blocks.pruned);
}

TEST_CASE("a unit cube cut by x = 0.5 gives two boxes of volume 0.5", "[cut]") {
  const auto bs = cut(kUnitCube + joint(90, 90, {0.5, 0.5, 0.5}));
  REQUIRE(bs.blocks.size() == 2);
  for (const auto& b : bs.blocks) {
    CHECK(b.faces.size() == 6);
    CHECK_THAT(test::block_volume(b, 1e-12), WithinRel(0.5, 1e-12));
    CHECK_THAT(b.inradius, WithinRel(0.25, 1e-12));
  }
}

TEST_CASE("degenerate joints neither crash nor make slivers nor lose volume", "[cut][degenerate]") {
  SECTION("a joint on a face of the domain cuts nothing") {
    CHECK(cut(kUnitCube + joint(90, 90, {1, 0.5, 0.5})).blocks.size() == 1);
    CHECK(cut(kUnitCube + joint(0, 0, {0.5, 0.5, 0})).blocks.size() == 1);
  }
  SECTION("a joint through a vertex only touches") {
    // The plane x + y + z = 0 touches the cube at the origin.
    const Vec3 n = Vec3(1, 1, 1).normalized();
    const auto dd = slice::dip_from_normal(n);
    CHECK(cut(kUnitCube + joint(dd.dip_deg, dd.dip_direction_deg, {0, 0, 0})).blocks.size() == 1);
  }
  SECTION("a joint along an edge only touches") {
    // The plane x + z = 0 dips East and touches the cube along the edge x = z = 0.
    CHECK(cut(kUnitCube + joint(45, 90, {0, 0.5, 0})).blocks.size() == 1);
  }
  SECTION("a joint through a vertex and across the cube cuts it") {
    // x + y + z = 1 passes through three vertices and cuts off a tetrahedron of volume 1/6.
    const Vec3 n = Vec3(1, 1, 1).normalized();
    const auto dd = slice::dip_from_normal(n);
    const auto bs = cut(kUnitCube + joint(dd.dip_deg, dd.dip_direction_deg, {1, 0, 0}));
    REQUIRE(bs.blocks.size() == 2);
    const double v0 = test::block_volume(bs.blocks[0], 1e-12);
    const double v1 = test::block_volume(bs.blocks[1], 1e-12);
    CHECK_THAT(std::min(v0, v1), WithinRel(1.0 / 6, 1e-9));
    CHECK_THAT(v0 + v1, WithinRel(1.0, 1e-12));
  }
  SECTION("two identical joints cut once") {
    const auto j = joint(90, 90, {0.5, 0.5, 0.5});
    const auto bs = cut(kUnitCube + j + j);
    CHECK(bs.blocks.size() == 2);
  }
  SECTION("a joint coplanar with an earlier joint's face cuts nothing new") {
    const auto bs = cut(kUnitCube + joint(90, 90, {0.5, 0, 0}) + joint(90, 270, {0.5, 0, 0}));
    CHECK(bs.blocks.size() == 2);
  }
  SECTION("near-parallel joints leave no sliver below the tolerance") {
    // Two vertical planes through the line x = y = 0.5 that differ by `angle`: the wedges
    // between them are at most 0.5 tan(angle) thick, about the cut tolerance (1e-9 * L,
    // L = 0.87 m) for 1e-7 degrees. Either a wedge is not cut off at all, or it is at least
    // the tolerance thick: its inscribed diameter is >= the tolerance.
    const double tol = 1e-9 * std::sqrt(0.75);
    for (const double angle : {1e-9, 1e-8, 1e-7, 1.0001e-7, 1e-6, 1e-5}) {
      CAPTURE(angle);
      const auto bs =
          cut(kUnitCube + joint(90, 90, {0.5, 0.5, 0.5}) + joint(90, 90 + angle, {0.5, 0.5, 0.5}));
      for (const auto& b : bs.blocks) CHECK(2 * b.inradius >= tol);
      test::check_invariants(bs, 20000, 1);
    }
  }
  SECTION("a joint wholly outside the domain cuts nothing") {
    slice::CutStats st;
    CHECK(cut(kUnitCube + joint(0, 0, {0.5, 0.5, 7}), true, slice::LpBackend::native, &st)
              .blocks.size() == 1);
    CHECK(st.joints_missing == 1);
  }
  SECTION("a polygon that only touches the cube cuts nothing") {
    // A square in the plane z = 0.5 whose edge lies on the cube's face x = 1.
    const auto bs = cut(kUnitCube + joint(0, 0, {1.5, 0.5, 0.5},
                                          "polygon = [[1, 0, 0.5], [2, 0, 0.5], [2, 1, 0.5], "
                                          "[1, 1, 0.5]]\n"));
    CHECK(bs.blocks.size() == 1);
  }
}

TEST_CASE("a polygon that reaches into a block cuts the whole block", "[cut][polygon]") {
  // Two boxes side by side (x = 0.5 splits the cube), then a small square at z = 0.5 reaching
  // only into the box x < 0.5: that box is cut through, the other is not.
  const auto bs = cut(kUnitCube + joint(90, 90, {0.5, 0.5, 0.5}) +
                      joint(0, 0, {0.2, 0.5, 0.5},
                            "polygon = [[0.1, 0.4, 0.5], [0.3, 0.4, 0.5], [0.3, 0.6, 0.5], "
                            "[0.1, 0.6, 0.5]]\n"));
  REQUIRE(bs.blocks.size() == 3);
  double small = 0;
  for (const auto& b : bs.blocks) small += test::block_volume(b, 1e-12) < 0.3 ? 1 : 0;
  CHECK(small == 2);  // two quarter boxes of 0.25
  test::check_invariants(bs, 20000, 2);
}

TEST_CASE("size and shape limits undo a split", "[cut][limits]") {
  const std::string opt = "[options]\nmin_inscribed_diameter = 0.3\n";
  // x = 0.1 would leave a 0.1 m slab (inscribed diameter 0.1): undone.
  slice::CutStats st;
  const auto bs =
      cut(kUnitCube + opt + joint(90, 90, {0.1, 0.5, 0.5}) + joint(90, 90, {0.5, 0.5, 0.5}), true,
          slice::LpBackend::native, &st);
  CHECK(bs.blocks.size() == 2);
  CHECK(st.splits_undone == 1);
  const std::string aspect = "[options]\nmax_aspect_ratio = 3\n";
  const auto bs2 =
      cut(kUnitCube + aspect + joint(90, 90, {0.2, 0.5, 0.5}), true, slice::LpBackend::native, &st);
  CHECK(bs2.blocks.size() == 1);
  CHECK(st.splits_undone == 1);
}

TEST_CASE("joint kinds: boundary blocks, construction clusters, removal zones", "[cut][kinds]") {
  const std::string scene = "[domain]\nbox = { min = [0, 0, 0], max = [4, 4, 4] }\n" +
                            joint(0, 0, {2, 2, 1}, "kind = \"boundary\"\nkeep = \"below\"\n") +
                            joint(90, 90, {2, 2, 2}, "kind = \"construction\"\n") +
                            joint(90, 0, {2, 3, 2}) + joint(0, 0, {2, 2, 3}) +
                            "[[zones]]\nbox = { min = [0, 3, 3], max = [4, 4, 4] }\n";
  slice::CutStats st;
  const auto bs = cut(scene, true, slice::LpBackend::native, &st);
  // z = 1 (boundary) splits the cube: the base is a boundary block, never cut again. The
  // upper part is cut by x = 2 (construction), y = 3 and z = 3: 2 * 2 * 2 = 8 blocks.
  REQUIRE(bs.blocks.size() == 9);
  std::size_t boundary = 0, removed = 0;
  for (const auto& b : bs.blocks) {
    if (b.flags & slice::kBoundary) {
      ++boundary;
      CHECK(b.origin.z() < 1);
      CHECK(b.cluster == -1);
    } else {
      // Every upper block touches its mirror across x = 2 with positive area.
      CHECK(b.cluster >= 0);
    }
    if (b.flags & slice::kRemoved) {
      ++removed;
      CHECK(b.origin.y() > 3);
      CHECK(b.origin.z() > 3);
    }
  }
  CHECK(boundary == 1);
  CHECK(removed == 2);
  CHECK(st.clusters == 4);
  test::check_invariants(bs, 20000, 3);
}

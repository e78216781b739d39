// slice-cut's library: hand-checkable scenes with known answers, and the degenerate inputs of
// docs/design.md, "Robustness".
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
  // A slab beside a parallel face: settled before the cut LP (whether or not it cuts).
  CHECK(st.splits_undone == 0);
  CHECK(st.settled_by_limit == 1);
  // x = 0.5 only, which cuts through the middle: proved without the LP.
  CHECK(st.cut_without_lp == 1);
  CHECK(st.lps.cut_test == 0);
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
    } else if (b.flags & slice::kRemoved) {
      CHECK(b.cluster == -1);  // a removed block joins no cluster
    } else {
      // Every kept upper block touches its mirror across x = 2 with positive area.
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
  CHECK(st.clusters == 3);  // the removed pair across x = 2 is no cluster
  test::check_invariants(bs, 20000, 3);
}

TEST_CASE("joint order matters for polygons: as-given against largest-first", "[cut][order]") {
  // A persistent set z = 5 and a small vertical polygon at y = 5 reaching only the upper
  // half (x 6..9, z 8..9.5). The [[joints]] entry comes first in as-given order: it cuts the
  // whole domain (a polygon that reaches a block cuts it through), then z = 5 cuts both
  // halves: 4 blocks. Largest-first puts the persistent plane first: the polygon then reaches
  // only the upper half: 3 blocks.
  const std::string base =
      "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n" +
      joint(90, 0, {7.5, 5, 8.75}, "polygon = [[6, 5, 8], [9, 5, 8], [9, 5, 9.5], [6, 5, 9.5]]\n") +
      "[[sets]]\nname = \"H\"\ndip = 0\ndip_direction = 0\nspacing = 5\n";
  CHECK(cut(base + "[options]\norder = \"as-given\"\n").blocks.size() == 4);
  CHECK(cut(base + "[options]\norder = \"by-set\"\n").blocks.size() == 4);
  CHECK(cut(base + "[options]\norder = \"alternating\"\n").blocks.size() == 4);
  const auto largest = cut(base + "[options]\norder = \"largest-first\"\n");
  CHECK(largest.blocks.size() == 3);
  test::check_invariants(largest, 20000, 4);
}

TEST_CASE("a boundary block is never cut again", "[cut][kinds]") {
  // z = 2 is a boundary joint keeping the side below; x = 5 then cuts only the part above.
  const std::string scene = "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n" +
                            joint(0, 0, {5, 5, 2}, "kind = \"boundary\"\nkeep = \"below\"\n") +
                            joint(90, 90, {5, 5, 5});
  const auto bs = cut(scene);
  REQUIRE(bs.blocks.size() == 3);
  std::size_t boundary = 0;
  for (const auto& b : bs.blocks)
    if (b.flags & slice::kBoundary) {
      ++boundary;
      CHECK_THAT(test::block_volume(b, 1e-12), WithinRel(200.0, 1e-12));  // 10 x 10 x 2 whole
    }
  CHECK(boundary == 1);
  SECTION("keep above flags the upper side, and blocks wholly above a persistent boundary") {
    const auto up =
        cut("[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n" + joint(90, 90, {3, 5, 5}) +
            joint(0, 0, {5, 5, 8}, "kind = \"boundary\"\nkeep = \"above\"\n") +
            joint(90, 90, {6, 5, 5}));
    // x = 3 first: two blocks; z = 8 cuts both, the tops become boundary blocks; x = 6 cuts
    // only the lower right block.
    REQUIRE(up.blocks.size() == 5);
    std::size_t n = 0;
    for (const auto& b : up.blocks) n += (b.flags & slice::kBoundary) && b.origin.z() > 8 ? 1 : 0;
    CHECK(n == 2);
  }
}

TEST_CASE("a rock joint through a construction cluster splits it in two", "[cut][kinds]") {
  // x = 5 (construction) makes one cluster of two blocks; y = 5 (rock) then cuts both: the two
  // blocks with y < 5 touch across x = 5, and so do the two with y > 5, but no block with
  // y < 5 touches one with y > 5 across the construction face: two clusters of two.
  const std::string scene = "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n" +
                            joint(90, 90, {5, 5, 5}, "kind = \"construction\"\n") +
                            joint(90, 0, {5, 5, 5});
  slice::CutStats st;
  const auto bs = cut(scene, true, slice::LpBackend::native, &st);
  REQUIRE(bs.blocks.size() == 4);
  CHECK(st.clusters == 2);
  for (const auto& a : bs.blocks)
    for (const auto& b : bs.blocks) {
      const bool same_side_y = (a.origin.y() < 5) == (b.origin.y() < 5);
      CHECK((a.cluster == b.cluster) == same_side_y);
    }
  SECTION("construction faces meeting only along an edge do not cluster") {
    // Two construction planes x = 5 and y = 5: diagonal blocks touch along the line x = y = 5
    // only, with no area: all four blocks are one cluster through their face contacts anyway,
    // so use a rock joint first to separate: y = 5 rock, then x = 5 construction: two clusters.
    const auto bs2 =
        cut("[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n" + joint(90, 0, {5, 5, 5}) +
                joint(90, 90, {5, 5, 5}, "kind = \"construction\"\n"),
            true, slice::LpBackend::native, &st);
    REQUIRE(bs2.blocks.size() == 4);
    CHECK(st.clusters == 2);
  }
}

TEST_CASE("a removed block joins no cluster, and nothing kept is joined through one",
          "[cut][kinds]") {
  // Construction joints x = 1, 2, 3 make a row of four blocks, all one cluster; a zone removes
  // the second. The first is then alone, and the third and fourth stay a cluster of two.
  const std::string row = "[domain]\nbox = { min = [0, 0, 0], max = [4, 1, 1] }\n" +
                          joint(90, 90, {1, 0.5, 0.5}, "kind = \"construction\"\n") +
                          joint(90, 90, {2, 0.5, 0.5}, "kind = \"construction\"\n") +
                          joint(90, 90, {3, 0.5, 0.5}, "kind = \"construction\"\n");
  slice::CutStats st;
  const auto all = cut(row, true, slice::LpBackend::native, &st);
  REQUIRE(all.blocks.size() == 4);
  CHECK(st.clusters == 1);
  const auto bs = cut(row + "[[zones]]\nbox = { min = [1, 0, 0], max = [2, 1, 1] }\n", true,
                      slice::LpBackend::native, &st);
  REQUIRE(bs.blocks.size() == 4);
  CHECK(st.clusters == 1);
  for (const auto& b : bs.blocks) {
    CAPTURE(b.origin.x());
    const bool removed = b.flags & slice::kRemoved;
    CHECK(removed == (b.origin.x() > 1 && b.origin.x() < 2));
    if (b.origin.x() < 2)
      CHECK(b.cluster == -1);
    else
      CHECK(b.cluster == 0);
  }
}

TEST_CASE("a zone removes exactly the blocks whose centre is inside", "[cut][kinds]") {
  // cube-3sets-like 4 x 4 x 1 grid of unit blocks; the zone x in (0.9, 2.6), y in (0, 1.2):
  // centres (1.5, 0.5) and (2.5, 0.5) are inside; (0.5, 0.5) and (3.5, 0.5) are not.
  const std::string scene =
      "[domain]\nbox = { min = [0, 0, 0], max = [4, 4, 1] }\n"
      "[[sets]]\ndip = 90\ndip_direction = 90\nspacing = 1\n"
      "[[sets]]\ndip = 90\ndip_direction = 0\nspacing = 1\n"
      "[[zones]]\nbox = { min = [0.9, 0, 0], max = [2.6, 1.2, 1] }\n";
  const auto bs = cut(scene);
  REQUIRE(bs.blocks.size() == 16);
  for (const auto& b : bs.blocks) {
    const bool inside = b.origin.x() > 0.9 && b.origin.x() < 2.6 && b.origin.y() < 1.2;
    CHECK(bool(b.flags & slice::kRemoved) == inside);
  }
}

TEST_CASE("the three LP backends give the same blocks on the rock slope", "[cut][lp]") {
  const auto js = slice::generate_joints(slice::load_scene(test::data_path("rock-slope.toml")));
  const auto run = [&](slice::LpBackend lp) {
    slice::CutOptions opt;
    opt.backend = lp;
    auto r = slice::cut_blocks(js, opt);
    slice::prune_blocks(r.blocks, lp);
    return std::move(r.blocks);
  };
  const auto native = run(slice::LpBackend::native);
  for (const auto lp : {slice::LpBackend::exact, slice::LpBackend::ipopt}) {
    CAPTURE(slice::to_string(lp));
    const auto other = run(lp);
    REQUIRE(other.blocks.size() == native.blocks.size());
    for (std::size_t i = 0; i < native.blocks.size(); ++i) {
      CAPTURE(i);
      const auto &a = native.blocks[i], &b = other.blocks[i];
      REQUIRE(a.faces.size() == b.faces.size());
      // The same planes (Chebyshev centres, hence origins, are not unique: a box has a
      // segment of them, and each backend may pick another point of it).
      const auto pa = test::global_planes(a), pb = test::global_planes(b);
      for (std::size_t f = 0; f < a.faces.size(); ++f) {
        CHECK(a.faces[f].joint == b.faces[f].joint);
        CHECK_THAT((pa[f].normal - pb[f].normal).norm(), WithinAbs(0, 1e-12));
        CHECK_THAT(pa[f].d, WithinAbs(pb[f].d, 1e-9));
      }
      CHECK(a.flags == b.flags);
      CHECK(a.cluster == b.cluster);
      CHECK_THAT(b.inradius, WithinRel(a.inradius, 1e-6));
    }
  }
}

TEST_CASE("fixed_faces fixes the blocks that touch the named faces of the domain", "[cut][kinds]") {
  // A 3 m cube of 27 unit blocks; -z has 9, +x has 9, both 3: 15 fixed blocks.
  const std::string grid =
      "[domain]\nbox = { min = [0, 0, 0], max = [3, 3, 3] }\n"
      "[[sets]]\ndip = 0\ndip_direction = 0\nspacing = 1\n"
      "[[sets]]\ndip = 90\ndip_direction = 90\nspacing = 1\n"
      "[[sets]]\ndip = 90\ndip_direction = 0\nspacing = 1\n";
  slice::CutStats st;
  const auto bs = cut(grid + "[options]\nfixed_faces = [\"-z\", \"+x\"]\n", true,
                      slice::LpBackend::native, &st);
  REQUIRE(bs.blocks.size() == 27);
  CHECK(st.fixed == 15);
  for (const auto& b : bs.blocks) {
    CAPTURE(b.origin.transpose());
    CHECK(bool(b.flags & slice::kFixed) == (b.origin.z() < 1 || b.origin.x() > 2));
    CHECK_FALSE(b.flags & slice::kBoundary);
  }
  CHECK(bs.joints.options.fixed_faces == 0b010010);  // bit k: kBoxFaceNames[k]: +x (1), -z (4)
  const auto none = cut(grid, true, slice::LpBackend::native, &st);
  CHECK(st.fixed == 0);
  for (const auto& b : none.blocks) CHECK_FALSE(b.flags & slice::kFixed);
}

// Issue 13 item 1: the user sets the sequence. as-given is file order across [[joints]] and
// [[sets]]; `stage = N` puts an entry after every entry of a lower stage.
TEST_CASE("the sequence: file order across [[joints]] and [[sets]], then stages", "[cut][order]") {
  const std::string domain = "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n";
  const std::string polygon =
      joint(90, 0, {7.5, 5, 8.75}, "polygon = [[6, 5, 8], [9, 5, 8], [9, 5, 9.5], [6, 5, 9.5]]\n");
  const std::string set = "[[sets]]\nname = \"H\"\ndip = 0\ndip_direction = 0\nspacing = 5\n";
  // The polygon first cuts the whole domain, then z = 5 cuts both halves: 4 blocks. The set
  // first leaves the polygon only the upper half: 3 blocks.
  for (const char* order : {"as-given", "by-set", "alternating"}) {
    CAPTURE(order);
    const std::string opt = std::string("[options]\norder = \"") + order + "\"\n";
    CHECK(cut(domain + opt + polygon + set).blocks.size() == 4);
    CHECK(cut(domain + opt + set + polygon).blocks.size() == 3);  // file order, sets first
    // stage = 2 puts the polygon after the set wherever it stands.
    CHECK(cut(domain + opt + polygon + "stage = 2\n" + set).blocks.size() == 3);
    CHECK(cut(domain + opt + set + "stage = 2\n" + polygon).blocks.size() == 4);
  }
  // largest-first orders within a stage: stage 1 (the polygon) before stage 2 (the set).
  const std::string largest = "[options]\norder = \"largest-first\"\n";
  CHECK(cut(domain + largest + polygon + set).blocks.size() == 3);
  CHECK(cut(domain + largest + polygon + set + "stage = 2\n").blocks.size() == 4);
}

// Issue 13 item 3: limits = false exempts a joint's cuts from the size and shape limits; the
// thin piece an exempt construction joint makes clusters with its neighbour across it.
TEST_CASE("limits = false keeps the cuts of an exempt joint", "[cut][limits]") {
  const std::string opt = "[options]\nmin_inscribed_diameter = 0.3\n";
  slice::CutStats st;
  // x = 0.1 would leave a 0.1 m slab: undone unless the joint is exempt.
  const auto normal =
      cut(kUnitCube + opt + joint(90, 90, {0.1, 0.5, 0.5}) + joint(90, 90, {0.5, 0.5, 0.5}), true,
          slice::LpBackend::native, &st);
  CHECK(normal.blocks.size() == 2);
  CHECK(st.settled_by_limit == 1);  // before the cut LP: a slab beside a parallel face
  const auto exempt = cut(kUnitCube + opt + joint(90, 90, {0.1, 0.5, 0.5}, "limits = false\n") +
                              joint(90, 90, {0.5, 0.5, 0.5}),
                          true, slice::LpBackend::native, &st);
  REQUIRE(exempt.blocks.size() == 3);
  CHECK(st.splits_undone == 0);
  CHECK(st.settled_by_limit == 0);
  CHECK(exempt.joints.joints.at(0).limits == false);
  // A later joint that would split the thin slab is still bound by the limit: y = 0.5 cuts the
  // two thick blocks but not the 0.1 m slab (its halves would be 0.1 m thin).
  const auto later = cut(kUnitCube + opt + joint(90, 90, {0.1, 0.5, 0.5}, "limits = false\n") +
                             joint(90, 90, {0.5, 0.5, 0.5}) + joint(90, 0, {0.5, 0.5, 0.5}),
                         true, slice::LpBackend::native, &st);
  CHECK(later.blocks.size() == 5);
  CHECK(st.splits_undone == 1);
  // A construction joint exempt from the limits: the slab clusters with its neighbour.
  const auto outline =
      cut(kUnitCube + opt +
              joint(90, 90, {0.1, 0.5, 0.5}, "kind = \"construction\"\nlimits = false\n") +
              joint(90, 90, {0.5, 0.5, 0.5}),
          true, slice::LpBackend::native, &st);
  REQUIRE(outline.blocks.size() == 3);
  CHECK(st.clusters == 1);
  for (const auto& b : outline.blocks)
    CHECK((b.cluster == 0) == (b.origin.x() < 0.5));  // the slab and the block beside it
}

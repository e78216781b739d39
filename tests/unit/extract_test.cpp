// slice/extract.hpp: region depths by hand (box, sphere, cylinder, the distance from a convex
// zone and from a mesh zone) and the selection rule on a row of four unit cubes: cut blocks
// fixed, the ring, touching blocks, clusters kept whole, removed blocks kept removed, refusals.
#include "slice/extract.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"
#include "slice/vertices.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;

namespace {

// [0, 4] x [0, 1] x [0, 1] cut by x = 1, 2, 3 into four unit cubes; pruned, with geometry. The
// blocks sorted by x: block i is [i, i + 1] x [0, 1] x [0, 1].
slice::BlockSystem row_of_cubes() {
  std::string scene = "[domain]\nbox = { min = [0, 0, 0], max = [4, 1, 1] }\n";
  for (int x = 1; x <= 3; ++x)
    scene +=
        "[[joints]]\ndip = 90\ndip_direction = 90\npoint = [" + std::to_string(x) + ", 0.5, 0.5]\n";
  auto r = slice::cut_blocks(slice::generate_joints(slice::parse_scene(scene, "row.toml")), {});
  slice::prune_blocks(r.blocks, slice::LpBackend::native);
  // Sorted by the x of the face facing +x (a domain face or a joint x = 1, 2, 3).
  const auto right = [](const slice::Block& b) {
    for (const auto& f : b.faces)
      if (f.normal.x() > 0.5) return b.origin.x() + f.d / f.normal.x();
    return 0.0;
  };
  std::sort(r.blocks.blocks.begin(), r.blocks.blocks.end(),
            [&](const auto& a, const auto& b) { return right(a) < right(b); });
  slice::compute_geometry(r.blocks);
  REQUIRE(r.blocks.blocks.size() == 4);
  for (std::size_t i = 0; i < 4; ++i)
    REQUIRE_THAT(r.blocks.geometry->centroid[i].x(), WithinAbs(double(i) + 0.5, 1e-12));
  return std::move(r.blocks);
}

slice::ExtractOptions box(const Vec3& lo, const Vec3& hi, double ring = 0) {
  slice::ExtractOptions o;
  o.region.shape = slice::RegionShape::box;
  o.region.a = lo;
  o.region.b = hi;
  o.ring = ring;
  return o;
}

std::vector<std::int64_t> fixed_rows(const slice::SubModel& s) {
  std::vector<std::int64_t> out;
  for (std::size_t k = 0; k < s.blocks.blocks.size(); ++k)
    if (s.blocks.blocks[k].flags & slice::kFixed) out.push_back(s.source_block[k]);
  return out;
}

using Ids = std::vector<std::int64_t>;

}  // namespace

TEST_CASE("region depths by hand", "[extract]") {
  const slice::JointSystem js;
  slice::ExtractRegion r;
  SECTION("box: the distance to the nearest face inside, negative outside") {
    r.shape = slice::RegionShape::box;
    r.a = {0, 0, 0};
    r.b = {4, 2, 10};
    const slice::RegionDepth d(r, js);
    CHECK_THAT(d({1, 1, 5}), WithinAbs(1, 1e-15));
    CHECK_THAT(d({3.5, 1, 5}), WithinAbs(0.5, 1e-15));
    CHECK(d({5, 1, 5}) < 0);
  }
  SECTION("sphere: radius - distance from the centre") {
    r.shape = slice::RegionShape::sphere;
    r.a = {1, 2, 3};
    r.radius = 5;
    const slice::RegionDepth d(r, js);
    CHECK_THAT(d({4, 6, 3}), WithinAbs(0, 1e-15));  // 3-4-5
    CHECK_THAT(d({1, 2, 3}), WithinAbs(5, 1e-15));
  }
  SECTION("cylinder: the nearest of the side and the two flat ends") {
    r.shape = slice::RegionShape::cylinder;
    r.a = {0, 0, 0};
    r.b = {0, 20, 0};
    r.radius = 15;
    const slice::RegionDepth d(r, js);
    CHECK_THAT(d({3, 10, 4}), WithinAbs(10, 1e-12));  // 5 from the axis
    CHECK_THAT(d({0, 2, 0}), WithinAbs(2, 1e-12));    // 2 from the end at y = 0
    CHECK_THAT(d({0, 19.5, 1}), WithinAbs(0.5, 1e-12));
    CHECK(d({0, 21, 0}) < 0);
    CHECK(d({16, 10, 0}) < 0);
  }
}

TEST_CASE("the depth near a zone is the distance minus the distance to the zone", "[extract]") {
  slice::JointSystem js;
  js.length_scale = 10;
  js.zones.push_back({slice::box_planes({0, 0, 0}, {1, 1, 1})});
  slice::ExtractRegion r;
  r.shape = slice::RegionShape::near_zone;
  r.radius = 2;
  const slice::RegionDepth d(r, js);
  CHECK_THAT(d({0.5, 0.5, 0.5}), WithinAbs(2, 1e-12));               // inside: distance 0
  CHECK_THAT(d({2, 0.5, 0.5}), WithinAbs(1, 1e-12));                 // a face 1 away
  CHECK_THAT(d({2, 2, 0.5}), WithinAbs(2 - std::sqrt(2.0), 1e-12));  // an edge
  CHECK_THAT(d({2, 2, 2}), WithinAbs(2 - std::sqrt(3.0), 1e-12));    // a corner
  CHECK_THAT(d({-1, -1, -1}), WithinAbs(2 - std::sqrt(3.0), 1e-12));

  SECTION("a mesh zone (after the /zones regions): the distance to its nearest triangle") {
    slice::TriangleMesh m;  // the cube [3, 4] x [0, 1] x [0, 1], outward
    for (int i = 0; i < 8; ++i)
      m.vertices.push_back({3.0 + (i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    REQUIRE_THAT(slice::check_solid_mesh(m, "cube"), WithinRel(1.0, 1e-12));
    js.zone_meshes.push_back(m);
    r.zones = {1};
    const slice::RegionDepth dm(r, js);
    CHECK_THAT(dm({5, 0.5, 0.5}), WithinAbs(1, 1e-12));
    CHECK_THAT(dm({3.5, 0.5, 0.5}), WithinAbs(2, 1e-12));  // inside
    CHECK_THAT(dm({5, 2, 2}), WithinAbs(2 - std::sqrt(3.0), 1e-12));
    r.zones = {};  // every zone: the nearer one counts
    const slice::RegionDepth both(r, js);
    CHECK_THAT(both({2, 0.5, 0.5}), WithinAbs(1, 1e-12));
    CHECK_THAT(both({2.5, 0.5, 0.5}), WithinAbs(1.5, 1e-12));
  }
  SECTION("a zone the file does not have is refused, naming the indices it has") {
    r.zones = {2};
    CHECK_THAT(test::error_of([&] { const slice::RegionDepth d2(r, js); }),
               Contains("no zone 2") && Contains("from 0 to 0"));
    CHECK_THAT(test::error_of([&] { const slice::RegionDepth d0(r, slice::JointSystem{}); }),
               Contains("has no zones"));
  }
}

TEST_CASE("bad regions are refused, naming the option", "[extract]") {
  auto o = box({0, 0, 0}, {1, 1, 1});
  o.region.b.y() = 0;
  CHECK_THAT(test::error_of([&] { o.validate(); }), Contains("--box") && Contains("on y"));
  o = box({0, 0, 0}, {1, 1, 1}, -1);
  CHECK_THAT(test::error_of([&] { o.validate(); }), Contains("--ring"));
  o.ring = 0;
  o.region.shape = slice::RegionShape::sphere;
  o.region.radius = -2;
  CHECK_THAT(test::error_of([&] { o.validate(); }), Contains("--sphere") && Contains("radius"));
  o.region.shape = slice::RegionShape::cylinder;
  o.region.radius = 1;
  o.region.b = o.region.a;
  CHECK_THAT(test::error_of([&] { o.validate(); }), Contains("--cylinder") && Contains("same"));
  o.region.b.x() = std::nan("");
  CHECK_THAT(test::error_of([&] { o.validate(); }), Contains("not finite"));
}

TEST_CASE("the selection rule on a row of four unit cubes", "[extract]") {
  const slice::BlockSystem bs = row_of_cubes();
  const slice::Geometry& g = *bs.geometry;

  SECTION("a box over x in [0.5, 2.5]: cubes 0 and 2 cut (fixed), cube 1 inside, 3 left out") {
    const auto s = slice::extract_blocks(bs, box({0.5, -1, -1}, {2.5, 2, 2}), "row.h5");
    CHECK(s.source_block == Ids{0, 1, 2});
    CHECK(fixed_rows(s) == Ids{0, 2});
    CHECK(s.stats.cut == 2);
    CHECK(s.stats.ring == 0);
    CHECK_THAT(s.stats.volume, WithinRel(3.0, 1e-12));
    // The rows of /geometry are the source's, unchanged.
    const slice::Geometry& sg = *s.blocks.geometry;
    REQUIRE(sg.volume.size() == 3);
    for (std::size_t k = 0; k < 3; ++k) {
      const auto b = std::size_t(s.source_block[k]);
      CHECK(sg.volume[k] == g.volume[b]);
      CHECK(sg.centroid[k] == g.centroid[b]);
      CHECK(sg.vertex_offset[k + 1] - sg.vertex_offset[k] ==
            g.vertex_offset[b + 1] - g.vertex_offset[b]);
      CHECK(s.blocks.blocks[k].faces.size() == bs.blocks[b].faces.size());
    }
    // A valid file by construction: it writes and reads back.
    test::TempDir dir;
    slice::write_blocks(dir / "sub.h5", s.blocks, {});
    const auto back = slice::read_blocks(dir / "sub.h5");
    CHECK(back.blocks.size() == 3);
    CHECK(back.geometry->volume == sg.volume);
  }
  SECTION("the ring: cube 1's vertices are 0.5 from the boundary") {
    CHECK(fixed_rows(slice::extract_blocks(bs, box({0.5, -1, -1}, {2.5, 2, 2}, 0.4), "r")) ==
          Ids{0, 2});
    const auto s = slice::extract_blocks(bs, box({0.5, -1, -1}, {2.5, 2, 2}, 0.5), "r");
    CHECK(fixed_rows(s) == Ids{0, 1, 2});
    CHECK(s.stats.ring == 1);
  }
  SECTION("a boundary on the joints: touching blocks are inside and, at ring 0, fixed") {
    const auto s = slice::extract_blocks(bs, box({1, -1, -1}, {3, 2, 2}), "r");
    CHECK(s.source_block == Ids{1, 2});  // cubes 0 and 3 only touch it: left out
    CHECK(fixed_rows(s) == Ids{1, 2});
    CHECK(s.stats.cut == 0);
    const auto big = slice::extract_blocks(bs, box({1, -1, -1}, {4, 2, 2}), "r");
    CHECK(big.source_block == Ids{1, 2, 3});
    CHECK(fixed_rows(big) == Ids{1, 3});  // cube 2 has no vertex on the boundary
  }
  SECTION("a cluster is kept whole and fixed whole") {
    auto c = bs;
    c.blocks[2].cluster = 7;
    c.blocks[3].cluster = 7;
    const auto s = slice::extract_blocks(c, box({0.5, -1, -1}, {2.5, 2, 2}), "r");
    CHECK(s.source_block == Ids{0, 1, 2, 3});
    CHECK(fixed_rows(s) == Ids{0, 2, 3});
    CHECK(s.stats.clusters == 1);
  }
  SECTION("removed blocks stay removed, never fixed; removed ones alone are refused") {
    auto c = bs;
    c.blocks[0].flags |= slice::kRemoved;
    c.blocks[3].flags |= slice::kRemoved;
    const auto s = slice::extract_blocks(c, box({0.5, -1, -1}, {2.5, 2, 2}), "r");
    CHECK(s.source_block == Ids{0, 1, 2});
    CHECK(fixed_rows(s) == Ids{2});
    CHECK(s.blocks.blocks[0].flags == slice::kRemoved);
    CHECK(s.stats.removed == 1);
    CHECK_THAT(s.stats.volume, WithinRel(2.0, 1e-12));
    CHECK_THAT(test::error_of([&] {
                 slice::extract_blocks(c, box({3.5, -1, -1}, {4.5, 2, 2}), "row.h5");
               }),
               Contains("row.h5") && Contains("keeps no block that is not removed"));
  }
  SECTION("a region away from every block is refused") {
    CHECK_THAT(test::error_of([&] {
                 slice::extract_blocks(bs, box({10, 10, 10}, {11, 11, 11}), "row.h5");
               }),
               Contains("row.h5") && Contains("keeps no block"));
  }
  SECTION("a sphere and a cylinder select by vertices too") {
    slice::ExtractOptions o;
    o.region.shape = slice::RegionShape::sphere;
    o.region.a = {0, 0.5, 0.5};
    // The vertices at x = 1 are sqrt(1.5) = 1.22 away, out, but the sphere bulges 0.2 through
    // the face x = 1 into cube 1: cube 0 and cube 1 are cut.
    o.region.radius = 1.2;
    const auto ball = slice::extract_blocks(bs, o, "r");
    CHECK(ball.source_block == Ids{0, 1});
    CHECK(fixed_rows(ball) == Ids{0, 1});
    CHECK(ball.stats.reached == 1);
    o.region.radius = 0.9;  // it reaches x = 0.9 only: cube 0 alone
    CHECK(slice::extract_blocks(bs, o, "r").source_block == Ids{0});
    o.region.shape = slice::RegionShape::cylinder;
    o.region.a = {-1, 0.5, 0.5};
    o.region.b = {1.5, 0.5, 0.5};
    o.region.radius = 1;
    const auto s = slice::extract_blocks(bs, o, "r");
    CHECK(s.source_block == Ids{0, 1});
    // Cube 0 is inside (its corners sqrt(0.5) from the axis, 0.29 from the side), cube 1 cut by
    // the end at x = 1.5.
    CHECK(fixed_rows(s) == Ids{1});
  }
}

TEST_CASE("a region that reaches into a block between its vertices cuts it", "[extract]") {
  // Cube 1 is [1, 2] x [0, 1] x [0, 1]; in each case none of its vertices is in the region.
  const slice::BlockSystem bs = row_of_cubes();
  slice::ExtractOptions o;
  const auto region = [&](slice::RegionShape shape, const Vec3& a, const Vec3& b, double r) {
    o.region.shape = shape;
    o.region.a = a;
    o.region.b = b;
    o.region.radius = r;
  };
  SECTION("a thin cylinder through it") {
    region(slice::RegionShape::cylinder, {1.5, -1, 0.5}, {1.5, 2, 0.5}, 0.3);
  }
  SECTION("a sphere bulging through its top face") {
    region(slice::RegionShape::sphere, {1.5, 0.5, 1.2}, Vec3::Zero(), 0.5);
  }
  SECTION("a box poking down into its top face") {
    region(slice::RegionShape::box, {1.2, 0.2, 0.8}, {1.8, 0.8, 1.5}, 0);
  }
  SECTION("the points within 0.4 of a zone 0.2 above its top face") {
    auto with_zone = bs;
    with_zone.joints.zones.push_back({slice::box_planes({1.4, -5, 1.2}, {1.6, 5, 1.3})});
    region(slice::RegionShape::near_zone, Vec3::Zero(), Vec3::Zero(), 0.4);
    const auto s = slice::extract_blocks(with_zone, o, "r");
    CHECK(s.source_block == Ids{1});
    CHECK(fixed_rows(s) == Ids{1});
    return;
  }
  const auto s = slice::extract_blocks(bs, o, "r");
  CHECK(s.source_block == Ids{1});
  CHECK(fixed_rows(s) == Ids{1});
  CHECK(s.stats.reached == 1);
  // Moved off by a little more than its depth inside, it reaches nowhere: refused.
  const double shift = o.region.shape == slice::RegionShape::cylinder ? 0.85 : 0.35;
  o.region.a.z() += shift;
  o.region.b.z() += shift;
  CHECK_THAT(test::error_of([&] { slice::extract_blocks(bs, o, "r"); }),
             Contains("keeps no block"));
}

// slice/vertices.hpp: hand-checkable polyhedra (box, tetrahedron, pyramid), the merging of
// vertices where four or more planes meet, faces without area, and rock-bridge fractions.
#include "slice/vertices.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/scene.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;

namespace {

// A block from global half-spaces n . x <= d (n need not be unit), origin `o`.
slice::Block block_of(const std::vector<std::pair<Vec3, double>>& planes, const Vec3& o) {
  slice::Block b;
  b.origin = o;
  for (const auto& [n, d] : planes) {
    const double len = n.norm();
    const slice::Plane g{n / len, d / len};
    const slice::Plane l = slice::to_local(g, o);
    b.faces.push_back({l.normal, l.d, -1});
  }
  b.inradius = 0;  // unknown: block_geometry finds an interior point itself if needed
  return b;
}

std::vector<std::pair<Vec3, double>> box(const Vec3& lo, const Vec3& hi) {
  return {{-Vec3::UnitX(), -lo.x()}, {Vec3::UnitX(), hi.x()},   {-Vec3::UnitY(), -lo.y()},
          {Vec3::UnitY(), hi.y()},   {-Vec3::UnitZ(), -lo.z()}, {Vec3::UnitZ(), hi.z()}};
}

const slice::JointSystem kNoJoints{};
const slice::Tolerances kTol = slice::Tolerances::from_scale(10, 1e-9);

// Checks every invariant of a block's geometry that does not depend on the shape.
void check_consistent(const slice::Block& b, const slice::BlockGeometry& g,
                      const slice::Tolerances& tol) {
  REQUIRE(g.loops.size() == b.faces.size());
  for (std::size_t f = 0; f < b.faces.size(); ++f) {
    CAPTURE(f);
    std::vector<Vec3> poly;
    for (const auto v : g.loops[f]) poly.push_back(g.vertices[std::size_t(v)] - b.origin);
    REQUIRE(poly.size() >= 3);
    // Newell's normal points along the face normal: the loop is counter-clockwise from outside.
    const Vec3 nw = slice::newell_normal(poly);
    CHECK_THAT(nw.normalized().dot(b.faces[f].normal), WithinAbs(1, 1e-12));
    CHECK_THAT(nw.norm() / 2, WithinRel(g.face_area[f], 1e-12));
    // The loop's vertices lie on the face's plane.
    for (const Vec3& x : poly)
      CHECK(std::abs(b.faces[f].normal.dot(x) - b.faces[f].d) <= tol.geometry);
  }
  // Every vertex satisfies every half-space.
  for (const Vec3& v : g.vertices)
    for (const auto& f : b.faces) CHECK(f.normal.dot(v - b.origin) - f.d <= tol.geometry);
  // No two vertices closer than the tolerance.
  for (std::size_t i = 0; i < g.vertices.size(); ++i)
    for (std::size_t j = i + 1; j < g.vertices.size(); ++j)
      CHECK((g.vertices[i] - g.vertices[j]).norm() > tol.geometry);
}

}  // namespace

TEST_CASE("a box: 8 vertices, volume, centroid and inertia by hand", "[vertices]") {
  // [0, a] x [0, b] x [0, c]: V = abc, centroid (a, b, c) / 2, Ixx = V (b^2 + c^2) / 12, no
  // products of inertia. Also far from the global origin (UTM-like coordinates).
  const double a = 2, bb = 3, c = 5, v = a * bb * c;
  for (const Vec3& shift : {Vec3(0, 0, 0), Vec3(5e5, 5e6, 300)}) {
    CAPTURE(shift.transpose());
    const auto blk = block_of(box(shift, shift + Vec3(a, bb, c)), shift + Vec3(0.7, 1.1, 2.0));
    const auto g = slice::block_geometry(blk, kNoJoints, kTol);
    CHECK(g.vertices.size() == 8);
    check_consistent(blk, g, kTol);
    CHECK_THAT(g.volume, WithinRel(v, 1e-12));
    CHECK_THAT((g.centroid - shift - Vec3(a, bb, c) / 2).norm(), WithinAbs(0, 1e-9));
    CHECK_THAT(g.inertia[0], WithinRel(v * (bb * bb + c * c) / 12, 1e-12));
    CHECK_THAT(g.inertia[1], WithinRel(v * (a * a + c * c) / 12, 1e-12));
    CHECK_THAT(g.inertia[2], WithinRel(v * (a * a + bb * bb) / 12, 1e-12));
    for (int k = 3; k < 6; ++k) CHECK_THAT(g.inertia[std::size_t(k)], WithinAbs(0, 1e-10));
    for (std::size_t f = 0; f < 6; ++f) {
      const double area = f < 2 ? bb * c : f < 4 ? a * c : a * bb;
      CHECK_THAT(g.face_area[f], WithinRel(area, 1e-12));
      CHECK(g.face_joint_fraction[f] == 1);
      CHECK(g.loops[f].size() == 4);
    }
  }
}

TEST_CASE("a tetrahedron: volume, centroid and inertia by hand", "[vertices]") {
  // x, y, z >= 0, x + y + z <= 1: V = 1/6, centroid (1/4, 1/4, 1/4). Integrals over it:
  // x^2 -> 1/60, xy -> 1/120. About the centroid: Ixx = 2/60 - V (2/16) = 1/80, and
  // integral of (x - 1/4)(y - 1/4) = 1/120 - V/16 = -1/480, so Ixy = +1/480.
  const Vec3 s(3, -4, 10);
  const auto blk = block_of({{-Vec3::UnitX(), -s.x()},
                             {-Vec3::UnitY(), -s.y()},
                             {-Vec3::UnitZ(), -s.z()},
                             {Vec3(1, 1, 1), 1 + s.sum()}},
                            s + Vec3(0.2, 0.2, 0.2));
  const auto g = slice::block_geometry(blk, kNoJoints, kTol);
  CHECK(g.vertices.size() == 4);
  check_consistent(blk, g, kTol);
  CHECK_THAT(g.volume, WithinRel(1.0 / 6, 1e-12));
  CHECK_THAT((g.centroid - s - Vec3(0.25, 0.25, 0.25)).norm(), WithinAbs(0, 1e-12));
  for (int k = 0; k < 3; ++k) CHECK_THAT(g.inertia[std::size_t(k)], WithinRel(1.0 / 80, 1e-12));
  for (int k = 3; k < 6; ++k) CHECK_THAT(g.inertia[std::size_t(k)], WithinRel(1.0 / 480, 1e-12));
  CHECK_THAT(g.face_area[3], WithinRel(std::sqrt(3.0) / 2, 1e-12));
  for (const auto& loop : g.loops) CHECK(loop.size() == 3);
}

TEST_CASE("a block whose origin is outside it still gets its geometry", "[vertices]") {
  // The dual hull needs a point inside: with the origin outside (a face with d < 0), the
  // Chebyshev centre is found by an LP first.
  const auto blk = block_of(box(Vec3(0, 0, 0), Vec3(1, 2, 3)), Vec3(5, -4, 1));
  REQUIRE(std::any_of(blk.faces.begin(), blk.faces.end(), [](const auto& f) { return f.d < 0; }));
  const auto g = slice::block_geometry(blk, kNoJoints, kTol);
  CHECK(g.vertices.size() == 8);
  check_consistent(blk, g, kTol);
  CHECK_THAT(g.volume, WithinRel(6, 1e-12));
  CHECK_THAT((g.centroid - Vec3(0.5, 1, 1.5)).norm(), WithinAbs(0, 1e-12));
}

TEST_CASE("mass_properties of a tetrahedron does not depend on the reference point", "[vertices]") {
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::vector<std::int64_t>> loops = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const Vec3& about : {Vec3(0.1, 0.2, 0.3), Vec3(-7, 3, 100)}) {
    const auto mp = slice::mass_properties(v, loops, about);
    CHECK_THAT(mp.volume, WithinRel(1.0 / 6, 1e-12));
    CHECK_THAT((mp.centroid - Vec3(0.25, 0.25, 0.25)).norm(), WithinAbs(0, 1e-12));
    CHECK_THAT(mp.inertia[0], WithinRel(1.0 / 80, 1e-9));
    CHECK_THAT(mp.inertia[3], WithinRel(1.0 / 480, 1e-9));
  }
}

TEST_CASE("four or more planes through one point give one vertex", "[vertices][degenerate]") {
  SECTION("a square pyramid: four faces meet at the apex") {
    // Base z >= 0, sides through the apex (0, 0, 1) and the base edges at +-1.
    const auto blk = block_of({{-Vec3::UnitZ(), 0},
                               {Vec3(1, 0, 1), 1},
                               {Vec3(-1, 0, 1), 1},
                               {Vec3(0, 1, 1), 1},
                               {Vec3(0, -1, 1), 1}},
                              Vec3(0, 0, 0.3));
    const auto g = slice::block_geometry(blk, kNoJoints, kTol);
    CHECK(g.vertices.size() == 5);
    check_consistent(blk, g, kTol);
    CHECK_THAT(g.volume, WithinRel(4.0 / 3, 1e-12));
    CHECK(g.loops[0].size() == 4);
    for (std::size_t f = 1; f < 5; ++f) CHECK(g.loops[f].size() == 3);
  }
  SECTION("an octahedron: four faces at each of six vertices") {
    std::vector<std::pair<Vec3, double>> p;
    for (double sx : {-1.0, 1.0})
      for (double sy : {-1.0, 1.0})
        for (double sz : {-1.0, 1.0}) p.push_back({Vec3(sx, sy, sz), 1});
    const auto blk = block_of(p, Vec3(0.01, -0.02, 0.03));
    const auto g = slice::block_geometry(blk, kNoJoints, kTol);
    CHECK(g.vertices.size() == 6);
    check_consistent(blk, g, kTol);
    CHECK_THAT(g.volume, WithinRel(4.0 / 3, 1e-12));
    for (const auto& loop : g.loops) CHECK(loop.size() == 3);
  }
  SECTION("a plane grazing an edge 1e-13 deep: its vertices merge, its face has no area") {
    auto p = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
    p.push_back({Vec3(1, 1, 0), 2 - 1e-13});
    const auto blk = block_of(p, Vec3(0.5, 0.5, 0.5));
    CHECK_THROWS_WITH(slice::block_geometry(blk, kNoJoints, kTol, 7),
                      Contains("block 7") && Contains("face 6") && Contains("no area"));
  }
}

TEST_CASE("faces without area are errors that name the block", "[vertices][degenerate]") {
  SECTION("a plane through an edge only (redundant)") {
    auto p = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
    p.push_back({Vec3(1, 1, 0), 2});
    const auto blk = block_of(p, Vec3(0.5, 0.5, 0.5));
    CHECK_THROWS_WITH(slice::block_geometry(blk, kNoJoints, kTol, 12),
                      Contains("block 12") && Contains("face 6") && Contains("does not touch"));
  }
  SECTION("a plane far outside (redundant)") {
    auto p = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
    p.push_back({Vec3(1, 1, 1), 5});
    const auto blk = block_of(p, Vec3(0.5, 0.5, 0.5));
    CHECK_THROWS_AS(slice::block_geometry(blk, kNoJoints, kTol, 3), slice::Error);
  }
  SECTION("a corner cut off 1e-12 deep: a triangle far below the tolerance") {
    auto p = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
    p.push_back({Vec3(1, 1, 1).normalized(), std::sqrt(3.0) - 1e-12});
    const auto blk = block_of(p, Vec3(0.5, 0.5, 0.5));
    CHECK_THROWS_WITH(slice::block_geometry(blk, kNoJoints, kTol, 4),
                      Contains("block 4") && Contains("face 6"));
  }
  SECTION("a corner cut off 1e-3 deep is a real face") {
    auto p = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
    p.push_back({Vec3(1, 1, 1).normalized(), std::sqrt(3.0) - 1e-3});
    const auto blk = block_of(p, Vec3(0.5, 0.5, 0.5));
    const auto g = slice::block_geometry(blk, kNoJoints, kTol);
    CHECK(g.vertices.size() == 10);
    check_consistent(blk, g, kTol);
    // The corner cut off is a tetrahedron with legs h sqrt(3) (h = 1e-3): volume (h sqrt 3)^3/6.
    const double leg = 1e-3 * std::sqrt(3.0);
    CHECK_THAT(g.volume, WithinRel(1 - leg * leg * leg / 6, 1e-12));
  }
  SECTION("an unbounded block") {
    const auto blk = block_of({{-Vec3::UnitX(), 0},
                               {Vec3::UnitX(), 1},
                               {-Vec3::UnitY(), 0},
                               {Vec3::UnitY(), 1},
                               {-Vec3::UnitZ(), 0}},
                              Vec3(0.5, 0.5, 0.5));
    CHECK_THROWS_AS(slice::block_geometry(blk, kNoJoints, kTol, 0), slice::Error);
  }
}

TEST_CASE("compute_geometry refuses blocks that are not pruned", "[vertices]") {
  slice::BlockSystem bs;
  bs.joints.length_scale = 1;
  bs.blocks.push_back(block_of(box(Vec3(0, 0, 0), Vec3(1, 1, 1)), Vec3(0.5, 0.5, 0.5)));
  bs.pruned = false;
  CHECK_THROWS_WITH(slice::compute_geometry(bs), Contains("pruned") && Contains("slice-prune"));
  bs.pruned = true;
  const auto st = slice::compute_geometry(bs);
  REQUIRE(bs.geometry);
  CHECK(st.blocks == 1);
  CHECK(bs.geometry->vertex_offset == std::vector<std::int64_t>{0, 8});
  CHECK(bs.geometry->face_vertex_offset.size() == 7);
  CHECK(bs.geometry->face_vertices.size() == 24);
}

TEST_CASE("clip_polygon keeps the inside of a half-space", "[vertices]") {
  const std::vector<Vec3> sq = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  CHECK_THAT(slice::newell_normal(slice::clip_polygon(sq, {Vec3::UnitX(), 0.5})).z(),
             WithinRel(2 * 0.5 * 2, 1e-15));
  CHECK(slice::clip_polygon(sq, {Vec3::UnitX(), -1}).empty());
  CHECK(slice::clip_polygon(sq, {Vec3::UnitX(), 3}) == sq);
}

namespace {

// A 10 m cube cut by one horizontal joint at z = 5 whose polygon is a square of side s
// centred at (cx, cy): the joint extends through the whole block (the method's rule), so each
// child has a face of 100 m2 of which only the polygon's part inside the cube is real joint.
slice::BlockSystem bridge(double s, double cx, double cy) {
  std::ostringstream t;
  t.precision(17);
  t << "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n"
    << "[[joints]]\ndip = 0\ndip_direction = 0\npoint = [" << cx << ", " << cy << ", 5]\n"
    << "polygon_uv = [[" << -s / 2 << ", " << -s / 2 << "], [" << s / 2 << ", " << -s / 2 << "], ["
    << s / 2 << ", " << s / 2 << "], [" << -s / 2 << ", " << s / 2 << "]]\n";
  const auto js = slice::generate_joints(slice::parse_scene(t.str(), "bridge.toml"));
  auto r = slice::cut_blocks(js, {});
  slice::prune_blocks(r.blocks, slice::LpBackend::native);
  slice::compute_geometry(r.blocks);
  return std::move(r.blocks);
}

// The joint face's (joint 0) fraction of each block.
std::vector<double> joint_fractions(const slice::BlockSystem& bs) {
  std::vector<double> out;
  std::size_t row = 0;
  for (const auto& b : bs.blocks)
    for (const auto& f : b.faces) {
      if (f.joint == 0) {
        CHECK_THAT(bs.geometry->face_area[row], WithinRel(100, 1e-12));
        out.push_back(bs.geometry->face_joint_fraction[row]);
      }
      ++row;
    }
  return out;
}

}  // namespace

TEST_CASE("rock bridge: a joint smaller than the block it cuts", "[vertices][bridge]") {
  SECTION("a 2 m square inside the 10 m face: 4 / 100") {
    const auto bs = bridge(2, 5, 5);
    REQUIRE(bs.blocks.size() == 2);
    for (const double fr : joint_fractions(bs)) CHECK_THAT(fr, WithinRel(0.04, 1e-12));
  }
  SECTION("a 4 m square centred on the domain's edge x = 10: 2 x 4 / 100") {
    const auto bs = bridge(4, 10, 3);
    REQUIRE(bs.blocks.size() == 2);
    for (const double fr : joint_fractions(bs)) CHECK_THAT(fr, WithinRel(0.08, 1e-12));
  }
  SECTION("a square larger than the domain: the whole face is joint") {
    const auto bs = bridge(30, 5, 5);
    REQUIRE(bs.blocks.size() == 2);
    for (const double fr : joint_fractions(bs)) CHECK(fr == 1);
  }
}

#include "slice/polytope.hpp"

#include <catch2/catch.hpp>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Plane;
using slice::Vec3;

TEST_CASE("a box is bounded, has an interior and the right volume", "[polytope]") {
  for (const Vec3& shift : {Vec3(0, 0, 0), Vec3(5e5, 5e6, 300)}) {
    CAPTURE(shift.transpose());
    const auto planes = slice::box_planes(shift + Vec3(0, 0, 0), shift + Vec3(2, 3, 4));
    const auto info = slice::analyse_polytope(planes, 1e-9 * 5);
    CHECK(info.bounded);
    CHECK(info.has_interior);
    CHECK(info.vertices.size() == 8);
    CHECK_THAT(info.volume, WithinRel(24.0, 1e-9));
    CHECK_THAT((info.max - info.min - Vec3(2, 3, 4)).norm(), WithinAbs(0, 1e-9));
  }
}

TEST_CASE("a tetrahedron has volume 1/6", "[polytope]") {
  std::vector<Plane> p = {{-Vec3::UnitX(), 0},
                          {-Vec3::UnitY(), 0},
                          {-Vec3::UnitZ(), 0},
                          {Vec3(1, 1, 1).normalized(), 1 / std::sqrt(3.0)}};
  const auto info = slice::analyse_polytope(p, 1e-12);
  CHECK(info.bounded);
  CHECK(info.has_interior);
  CHECK(info.vertices.size() == 4);
  CHECK_THAT(info.volume, WithinRel(1.0 / 6.0, 1e-12));
}

TEST_CASE("an octahedron's vertices are found once although four planes meet there", "[polytope]") {
  std::vector<Plane> p;
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0})
        p.push_back({Vec3(sx, sy, sz).normalized(), 1 / std::sqrt(3.0)});
  const auto info = slice::analyse_polytope(p, 1e-12);
  CHECK(info.vertices.size() == 6);
  CHECK_THAT(info.volume, WithinRel(4.0 / 3.0, 1e-12));
}

TEST_CASE("unbounded, empty and flat regions are recognised", "[polytope]") {
  auto box = slice::box_planes({0, 0, 0}, {1, 1, 1});
  SECTION("a box without its top is unbounded") {
    box.pop_back();
    CHECK_FALSE(slice::analyse_polytope(box, 1e-12).bounded);
  }
  SECTION("a slab is unbounded") {
    std::vector<Plane> slab = {box[4], box[5]};
    CHECK_FALSE(slice::analyse_polytope(slab, 1e-12).bounded);
  }
  SECTION("a prism open along an oblique axis is unbounded") {
    const Vec3 axis = Vec3(1, 2, 3).normalized();
    std::vector<Plane> prism;
    for (const Vec3& n : {Vec3(3, 0, -1), Vec3(-3, 0, 1), Vec3(0, 3, -2), Vec3(0, -3, 2)})
      prism.push_back({n.normalized(), 1});
    for (const auto& q : prism) REQUIRE(std::abs(q.normal.dot(axis)) < 1e-15);
    CHECK_FALSE(slice::analyse_polytope(prism, 1e-12).bounded);
  }
  SECTION("x <= 0 and x >= 1 is empty") {
    box[1] = {Vec3::UnitX(), 0};
    box[0] = {-Vec3::UnitX(), -1};
    const auto info = slice::analyse_polytope(box, 1e-12);
    CHECK_FALSE(info.has_interior);
    CHECK(info.volume == 0.0);
  }
  SECTION("x <= 0 and x >= 0 is flat") {
    box[1] = {Vec3::UnitX(), 0};
    box[0] = {-Vec3::UnitX(), 0};
    CHECK_FALSE(slice::analyse_polytope(box, 1e-12).has_interior);
  }
}

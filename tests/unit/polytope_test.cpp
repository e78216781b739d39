#include "slice/polytope.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

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

namespace {

// The vertex search analyse_polytope made before it skipped lines that miss the region: every
// triple of planes solved, every solution tested against every plane. The reference for the
// test below.
std::vector<Vec3> vertices_by_every_triple(const std::vector<Plane>& planes, double tol) {
  std::vector<Vec3> out;
  const std::size_t n = planes.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        Eigen::Matrix3d a;
        a.row(0) = planes[i].normal;
        a.row(1) = planes[j].normal;
        a.row(2) = planes[k].normal;
        if (std::abs(a.determinant()) < 1e-12) continue;
        const Vec3 x = a.partialPivLu().solve(Vec3(planes[i].d, planes[j].d, planes[k].d));
        if (!std::all_of(planes.begin(), planes.end(),
                         [&](const Plane& p) { return p.distance(x) <= tol; }))
          continue;
        if (std::none_of(out.begin(), out.end(),
                         [&](const Vec3& v) { return (v - x).norm() <= tol; }))
          out.push_back(x);
      }
  return out;
}

}  // namespace

// Random regions: tangent planes of a sphere, planes through shared vertices and edges (several
// planes meeting at a point), duplicated planes and redundant planes, at the origin and 1e6 m
// away. The skip of lines that miss the region must not lose or move a single vertex.
TEST_CASE("skipping lines that miss the region finds exactly the vertices of every triple",
          "[polytope]") {
  std::mt19937_64 rng(20261123);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(0, 1);
  auto direction = [&] { return Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized(); };
  for (int c = 0; c < 300; ++c) {
    CAPTURE(c);
    const double r = std::pow(10.0, unit(rng) * 6 - 3);  // 1 mm to 1 km
    const Vec3 centre = c % 3 == 0 ? Vec3(1e6, -2e6, 3e5) : Vec3::Zero();
    std::vector<Plane> planes =
        slice::box_planes(centre - Vec3::Constant(r), centre + Vec3::Constant(r));
    const int extra = 1 + int(unit(rng) * 60);
    for (int k = 0; k < extra; ++k) {
      const Vec3 n = direction();
      switch (k % 4) {
        case 0:  // tangent to the inscribed sphere: cuts corners
          planes.push_back({n, n.dot(centre) + r * (0.9 + 0.2 * unit(rng))});
          break;
        case 1: {  // through a corner of the box (a vertex where four or more planes meet)
          const Vec3 corner = centre + r * Vec3(unit(rng) < 0.5 ? -1 : 1, unit(rng) < 0.5 ? -1 : 1,
                                                unit(rng) < 0.5 ? -1 : 1);
          const Vec3 out = (corner - centre).normalized();
          const Vec3 m = (out + 0.5 * direction()).normalized();
          planes.push_back({m, m.dot(corner)});
          break;
        }
        case 2:  // a copy of an earlier plane
          planes.push_back(planes[std::size_t(unit(rng) * double(planes.size()))]);
          break;
        default:  // far outside: redundant
          planes.push_back({n, n.dot(centre) + 3 * r});
      }
    }
    std::shuffle(planes.begin(), planes.end(), rng);
    const double tol = 1e-9 * r * std::sqrt(3.0);
    const auto info = slice::analyse_polytope(planes, tol);
    REQUIRE(info.bounded);
    CHECK(info.vertices == vertices_by_every_triple(planes, tol));
  }
}

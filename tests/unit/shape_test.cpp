// slice/shape.hpp: alpha and beta on shapes whose chords are known by hand (a cube, boxes that
// are plates and rods, a regular tetrahedron and octahedron), the same shapes rotated, moved
// 1e6 m and rescaled, the classes, and refusals.
#include "slice/shape.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "slice/error.hpp"
#include "slice/vertices.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::ShapeClass;
using slice::Vec3;

namespace {

struct Solid {
  std::vector<Vec3> vertices;
  double area = 0, volume = 0;
};

Solid box(double a, double b, double c) {
  Solid s;
  for (int i = 0; i < 8; ++i) s.vertices.emplace_back(i & 1 ? a : 0, i & 2 ? b : 0, i & 4 ? c : 0);
  s.area = 2 * (a * b + b * c + c * a);
  s.volume = a * b * c;
  return s;
}

// A box's 28 chords by hand: 4 edges of each length a, b, c; 4 diagonals on each pair of
// opposite faces; 4 space diagonals. alpha = A * mean chord / (7.7 V).
double box_alpha(double a, double b, double c) {
  const double sum = 4 * (a + b + c) +
                     4 * (std::hypot(a, b) + std::hypot(b, c) + std::hypot(a, c)) +
                     4 * std::sqrt(a * a + b * b + c * c);
  return 2 * (a * b + b * c + c * a) * (sum / 28) / (7.7 * a * b * c);
}

// The same solid turned by `q`, scaled by `k` and moved by `t`, its vertices shuffled.
Solid moved(const Solid& s, const Eigen::Quaterniond& q, double k, const Vec3& t,
            std::mt19937& rng) {
  Solid m{{}, s.area * k * k, s.volume * k * k * k};
  for (const Vec3& v : s.vertices) m.vertices.push_back(q * (k * v) + t);
  std::shuffle(m.vertices.begin(), m.vertices.end(), rng);
  return m;
}

slice::BlockShape shape_of(const Solid& s) {
  return slice::block_shape(s.vertices, s.area, s.volume);
}

}  // namespace

TEST_CASE("a cube: alpha 0.99904, beta 1/4, class C", "[block-shape]") {
  // Chords: 12 edges 1, 12 face diagonals sqrt 2, 4 space diagonals sqrt 3; mean 1.28210, so
  // alpha = 6 * 1.28210 / 7.7. The median chord is sqrt 2: from a corner the long chords are the
  // 3 face diagonals (cos^2 between two: 1/4) and the space diagonal (cos^2 2/3): beta = 1/4.
  const auto s = shape_of(box(1, 1, 1));
  const double mean = (12 + 12 * std::sqrt(2.0) + 4 * std::sqrt(3.0)) / 28;
  CHECK_THAT(s.alpha, WithinRel(6 * mean / 7.7, 1e-14));
  CHECK_THAT(s.alpha, WithinAbs(0.99904, 1e-5));
  CHECK_THAT(s.beta, WithinAbs(0.25, 1e-14));
  CHECK(s.shape == ShapeClass::C);
  // Kalenchuk's beta (UnBlocks-gen's eq. 5): the chords longer than the median sqrt 2 are the 4
  // space diagonals (+-1, +-1, +-1); T = sum d d^T = 4 I, |T|_F^2 = 48, (tr T)^2 = 144:
  // beta_k = 10 (1/3)^2 = 10/9.
  CHECK_THAT(s.beta_k, WithinRel(10.0 / 9, 1e-14));
  CHECK(s.shape_k == ShapeClass::C);  // UnBlocks-gen's classes: alpha < 2, beta_k < 4
}

TEST_CASE("plates and a rod: alpha and beta by hand", "[block-shape]") {
  SECTION("a 10 x 10 x 1 plate: beta 1/10201, class PC") {
    // Median chord sqrt 101 (the 8 side-face diagonals). From a corner the long chords are
    // (10,10,0), (10,0,1), (0,10,1), (10,10,1); (10,0,1) and (0,10,1) have cos 1/101.
    const auto s = shape_of(box(10, 10, 1));
    CHECK_THAT(s.alpha, WithinRel(box_alpha(10, 10, 1), 1e-14));
    CHECK_THAT(s.alpha, WithinAbs(3.0910, 1e-4));
    CHECK_THAT(s.beta, WithinRel(1.0 / 10201, 1e-12));
    CHECK(s.shape == ShapeClass::PC);
    // Kalenchuk's beta: longer than sqrt 101 are the 4 top and bottom diagonals (10, +-10, 0)
    // and the 4 space diagonals (10, +-10, +-1): T = diag(800, 800, 4), |T|_F^2 = 1,280,016,
    // (tr T)^2 = 1604^2 = 2,572,816.
    const double r = 1280016.0 / 2572816;
    CHECK_THAT(s.beta_k, WithinRel(10 * r * r, 1e-13));
    CHECK_THAT(s.beta_k, WithinAbs(2.4752, 1e-4));
    CHECK(s.shape_k == ShapeClass::PC);  // 2 <= alpha < 5, beta_k < 4
  }
  SECTION("a 20 x 20 x 1 plate: class P") {
    const auto s = shape_of(box(20, 20, 1));
    CHECK_THAT(s.alpha, WithinRel(box_alpha(20, 20, 1), 1e-14));
    CHECK(s.alpha > 5);
    CHECK_THAT(s.beta, WithinRel(1.0 / (401.0 * 401.0), 1e-12));
    CHECK(s.shape == ShapeClass::P);
  }
  SECTION("a 1 x 1 x 10 rod: beta 10000/10201, class E") {
    // Median chord 10 (the long edges). From a corner the long chords are (0,0,10), (1,0,10),
    // (0,1,10), (1,1,10); the smallest cos^2 is between (1,0,10) and (0,1,10): (100/101)^2.
    const auto s = shape_of(box(1, 1, 10));
    CHECK_THAT(s.alpha, WithinRel(box_alpha(1, 1, 10), 1e-14));
    CHECK_THAT(s.alpha, WithinAbs(3.3985, 1e-4));
    CHECK_THAT(s.beta, WithinRel(10000.0 / 10201, 1e-14));
    CHECK(s.shape == ShapeClass::E);
    // Kalenchuk's beta: longer than 10 are the 8 side-face diagonals (+-1, 0, 10), (0, +-1, 10)
    // and the 4 space diagonals (+-1, +-1, 10): T = diag(8, 8, 1200), |T|_F^2 = 1,440,128,
    // (tr T)^2 = 1216^2 = 1,478,656.
    const double r = 1440128.0 / 1478656;
    CHECK_THAT(s.beta_k, WithinRel(10 * r * r, 1e-13));
    CHECK_THAT(s.beta_k, WithinAbs(9.4857, 1e-4));
    CHECK(s.shape_k == ShapeClass::E);  // beta_k >= 7
  }
  SECTION("a 1 x 2 x 4 brick lies between") {
    const auto s = shape_of(box(1, 2, 4));
    CHECK_THAT(s.alpha, WithinRel(box_alpha(1, 2, 4), 1e-14));
    CHECK(s.beta > 0.25);
    CHECK(s.beta < 10000.0 / 10201);
  }
}

TEST_CASE("non-orthogonal polyhedra: a regular tetrahedron and octahedron", "[block-shape]") {
  SECTION("tetrahedron: alpha 6 sqrt 6 / 7.7, beta 1/4 (every chord is the longest)") {
    // Edge s = 2 sqrt 2: A = sqrt 3 s^2, V = s^3 / (6 sqrt 2), all 6 chords s. At a corner the
    // three edges meet at 60 degrees: cos^2 1/4.
    const double e = 2 * std::sqrt(2.0);
    const Solid t{{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}},
                  std::sqrt(3.0) * e * e,
                  e * e * e / (6 * std::sqrt(2.0))};
    const auto s = shape_of(t);
    CHECK_THAT(s.alpha, WithinRel(6 * std::sqrt(6.0) / 7.7, 1e-14));
    CHECK_THAT(s.beta, WithinAbs(0.25, 1e-14));
    CHECK(s.shape == ShapeClass::C);
    CHECK(std::isnan(s.beta_k));  // no chord longer than the median: all are equal
    CHECK(s.shape_k == ShapeClass::none);
  }
  SECTION("octahedron: beta 0 (two chords from a corner at right angles)") {
    // Vertices +-e_i: 12 edges sqrt 2, 3 diagonals 2; A = 8 (sqrt 3 / 4) 2 = 4 sqrt 3, V = 4/3.
    const Solid o{{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
                  4 * std::sqrt(3.0),
                  4.0 / 3};
    const auto s = shape_of(o);
    const double mean = (12 * std::sqrt(2.0) + 3 * 2) / 15;
    CHECK_THAT(s.alpha, WithinRel(4 * std::sqrt(3.0) * mean / (7.7 * 4.0 / 3), 1e-14));
    CHECK_THAT(s.beta, WithinAbs(0, 1e-15));
    CHECK(s.shape == ShapeClass::C);
    // Longer than the median sqrt 2: the 3 diagonals 2 e_i, T = 4 I: beta_k = 10/9.
    CHECK_THAT(s.beta_k, WithinRel(10.0 / 9, 1e-14));
  }
  SECTION("a sheared block through slice-vertices' own geometry") {
    // x - z/2 in [0, 2], y in [0, 3], z in [0, 1]: its /geometry (vertices, face areas,
    // volume) gives the factors of the same solid given by hand.
    slice::Block b;
    const Vec3 n = Vec3(1, 0, -0.5).normalized();
    const double h = n.x();  // |(1, 0, -0.5)|^-1: the plane x - z/2 = 2 is n . x = 2 h
    b.origin = Vec3(1.25, 1.5, 0.5);
    for (const auto& [nn, d] : std::vector<std::pair<Vec3, double>>{{n, 2 * h},
                                                                    {-n, 0},
                                                                    {Vec3::UnitY(), 3},
                                                                    {-Vec3::UnitY(), 0},
                                                                    {Vec3::UnitZ(), 1},
                                                                    {-Vec3::UnitZ(), 0}})
      b.faces.push_back({nn, d - nn.dot(b.origin), -1});
    const auto g =
        slice::block_geometry(b, slice::JointSystem{}, slice::Tolerances::from_scale(4, 1e-9));
    double area = 0;
    for (const double a : g.face_area) area += a;
    const auto from_geometry = slice::block_shape(g.vertices, area, g.volume);
    Solid hand;
    for (int i = 0; i < 8; ++i) {
      const double z = i & 4 ? 1 : 0;
      hand.vertices.emplace_back((i & 1 ? 2 : 0) + z / 2, i & 2 ? 3 : 0, z);
    }
    hand.volume = 2 * 3 * 1;
    hand.area = 2 * (2 * 3) + 2 * (2 * 1) + 2 * (3 * std::hypot(1.0, 0.5));
    const auto by_hand = shape_of(hand);
    CHECK_THAT(g.volume, WithinRel(hand.volume, 1e-12));
    CHECK_THAT(area, WithinRel(hand.area, 1e-12));
    CHECK_THAT(from_geometry.alpha, WithinRel(by_hand.alpha, 1e-12));
    CHECK_THAT(from_geometry.beta, WithinAbs(by_hand.beta, 1e-12));
    CHECK(from_geometry.shape == by_hand.shape);
  }
}

TEST_CASE("rotated, moved 1e6 m, rescaled and reordered: the same factors", "[block-shape]") {
  // Fixed seed, 200 random turns per solid, offsets up to 1e6 m, scales from mm to km.
  std::mt19937 rng(20061212);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(-1, 1);
  const double e = 2 * std::sqrt(2.0);
  const std::vector<Solid> solids{box(1, 1, 1), box(10, 10, 1), box(1, 1, 10), box(1, 2, 4),
                                  Solid{{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}},
                                        std::sqrt(3.0) * e * e,
                                        e * e * e / (6 * std::sqrt(2.0))}};
  for (std::size_t k = 0; k < solids.size(); ++k) {
    CAPTURE(k);
    const auto ref = shape_of(solids[k]);
    for (int i = 0; i < 200; ++i) {
      const Eigen::Quaterniond q =
          Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
      const double scale = std::pow(10.0, 3 * unit(rng));
      const Vec3 t = 1e6 * Vec3(unit(rng), unit(rng), unit(rng));
      const auto s = shape_of(moved(solids[k], q, scale, t, rng));
      CAPTURE(i, scale, t.transpose());
      // 1e6 m from the origin a vertex carries ~1e-10 m of rounding: relative to a 1 mm block,
      // 1e-7.
      const double tol = 1e-9 + 1e-10 * t.norm() / scale;
      CHECK_THAT(s.alpha, WithinRel(ref.alpha, tol));
      CHECK_THAT(s.beta, WithinAbs(ref.beta, tol));
      CHECK(s.shape == ref.shape);
      if (std::isnan(ref.beta_k))
        CHECK(std::isnan(s.beta_k));
      else
        CHECK_THAT(s.beta_k, WithinRel(ref.beta_k, tol));
    }
  }
}

TEST_CASE("shape classes: the diagram's boundaries", "[block-shape]") {
  CHECK(slice::shape_class(1.0, 0.1) == ShapeClass::C);
  CHECK(slice::shape_class(2.0, 0.3) == ShapeClass::C);
  CHECK(slice::shape_class(2.01, 0.3) == ShapeClass::PC);
  CHECK(slice::shape_class(5.0, 0.0) == ShapeClass::PC);
  CHECK(slice::shape_class(5.01, 0.0) == ShapeClass::P);
  CHECK(slice::shape_class(3.0, 0.31) == ShapeClass::CE);
  CHECK(slice::shape_class(3.01, 0.75) == ShapeClass::EP);
  CHECK(slice::shape_class(1.0, 0.76) == ShapeClass::E);
  CHECK(slice::shape_class(9.0, 1.0) == ShapeClass::E);
  CHECK(slice::shape_class(1.0, std::nan("")) == ShapeClass::none);
  for (std::size_t c = 0; c < slice::kShapeClasses.size(); ++c)
    CHECK(std::size_t(slice::kShapeClasses[c]) == c);
  CHECK(std::string(slice::to_string(ShapeClass::EP)) == "EP");
  CHECK(std::string(slice::to_string(ShapeClass::none)) == "none");
}

TEST_CASE("UnBlocks-gen's classes on Kalenchuk's beta: plotTools.py's boundaries",
          "[block-shape]") {
  // plotTools.py, BlockShapeDistribution: C alpha < 2 and beta < 4; PC 2 <= alpha < 5; P alpha
  // >= 5; CE alpha < 3 and 4 <= beta < 7; EP alpha >= 3 there; E beta >= 7.
  using slice::kalenchuk_class;
  CHECK(kalenchuk_class(1.0, 10.0 / 9) == ShapeClass::C);
  CHECK(kalenchuk_class(1.99, 3.99) == ShapeClass::C);
  CHECK(kalenchuk_class(2.0, 3.99) == ShapeClass::PC);
  CHECK(kalenchuk_class(4.99, 1.0) == ShapeClass::PC);
  CHECK(kalenchuk_class(5.0, 1.0) == ShapeClass::P);
  CHECK(kalenchuk_class(1.0, 4.0) == ShapeClass::CE);
  CHECK(kalenchuk_class(2.99, 6.99) == ShapeClass::CE);
  CHECK(kalenchuk_class(3.0, 4.0) == ShapeClass::EP);
  CHECK(kalenchuk_class(9.0, 6.99) == ShapeClass::EP);
  CHECK(kalenchuk_class(1.0, 7.0) == ShapeClass::E);
  CHECK(kalenchuk_class(9.0, 10.0) == ShapeClass::E);
  CHECK(kalenchuk_class(1.0, std::nan("")) == ShapeClass::none);
  CHECK(kalenchuk_class(std::nan(""), 2.0) == ShapeClass::none);
  // A 1 x 2 x 4 brick: beta_k 4.97 (CE), a 20 x 20 x 1 plate: alpha 5.6 (P); a regular
  // tetrahedron has no beta_k (none).
  const auto brick = shape_of(box(1, 2, 4));
  CHECK_THAT(brick.beta_k, WithinAbs(4.9718, 1e-4));
  CHECK(brick.shape_k == ShapeClass::CE);
  CHECK(shape_of(box(20, 20, 1)).shape_k == ShapeClass::P);
}

TEST_CASE("block_shape and block_shapes refuse what has no shape", "[block-shape]") {
  const Solid c = box(1, 1, 1);
  const std::vector<Vec3> three(c.vertices.begin(), c.vertices.begin() + 3);
  CHECK_THROWS_WITH(slice::block_shape(three, 1, 1, "block 7"),
                    Contains("block 7") && Contains("at least 4 vertices"));
  CHECK_THROWS_AS(slice::block_shape(c.vertices, 6, 0), slice::Error);
  CHECK_THROWS_AS(slice::block_shape(c.vertices, -6, 1), slice::Error);
  CHECK_THROWS_AS(slice::block_shape(c.vertices, 6, std::nan("")), slice::Error);
  auto bad = c.vertices;
  bad[3].x() = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(slice::block_shape(bad, 6, 1), Contains("not finite"));
  // A 2-D section's polygons: refused, with the reason.
  slice::Geometry g;
  CHECK_THROWS_WITH(slice::block_shapes({}, g, 2), Contains("3-D blocks"));
}

TEST_CASE("summarise_shapes: counts and volumes by class, kept blocks only", "[block-shape]") {
  const std::vector<slice::BlockShape> shapes{{1, 0.25, ShapeClass::C},
                                              {3, 0.9, ShapeClass::E},
                                              {1, 0.25, ShapeClass::C},
                                              {6, 0.1, ShapeClass::P}};
  const std::vector<double> vol{1, 2, 3, 4};
  const auto all = slice::summarise_shapes(shapes, vol);
  CHECK(all.count[0] == 2);
  CHECK(all.volume[0] == 4);
  CHECK(all.count[5] == 1);
  CHECK(all.volume[2] == 4);
  const auto kept = slice::summarise_shapes(shapes, vol, {true, true, false, false});
  CHECK(kept.count[0] == 1);
  CHECK(kept.volume[0] == 1);
  CHECK(kept.count[2] == 0);
  // By UnBlocks-gen's classes on beta_k (shape_k) instead.
  auto k = shapes;
  k[0].shape_k = k[2].shape_k = ShapeClass::CE;
  k[1].shape_k = ShapeClass::E;
  k[3].shape_k = ShapeClass::PC;
  const auto byk = slice::summarise_shapes(k, vol, {}, true);
  CHECK(byk.count[0] == 0);
  CHECK(byk.count[3] == 2);
  CHECK(byk.volume[3] == 4);
  CHECK(byk.volume[1] == 4);
  CHECK(byk.volume[5] == 2);
}

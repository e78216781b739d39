// Hand-checkable cases of the LP layer (slice/lp.hpp), each run on every backend.
#include "slice/lp.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "slice/error.hpp"

namespace {

using Catch::Matchers::WithinAbs;
using slice::Face;
using slice::LpBackend;
using slice::LpStatus;
using slice::LpVec;
using slice::Plane;
using slice::Vec3;

// Exact backends get this absolute tolerance on O(1) answers; ipopt is an interior point method
// stopped at a tolerance (kIpoptTol = 1e-10 on the scaled problem), so it gets a wider one.
double answer_tol(LpBackend b) { return b == LpBackend::ipopt ? 1e-7 : 1e-12; }

/// The box [lo, hi] as faces relative to the origin.
std::vector<Face> box(const Vec3& lo, const Vec3& hi) {
  std::vector<Face> f;
  for (int k = 0; k < 3; ++k) {
    f.push_back({-Vec3::Unit(k), -lo[k]});
    f.push_back({Vec3::Unit(k), hi[k]});
  }
  return f;
}

std::vector<Face> unit_cube() { return box(Vec3::Zero(), Vec3::Ones()); }

/// The in-plane edges of the square of side `side` centred at `c` in a plane x = const.
std::vector<Plane> square_in_x_plane(const Vec3& c, double side) {
  const double h = side / 2;
  return {{Vec3::UnitY(), c.y() + h},
          {-Vec3::UnitY(), -(c.y() - h)},
          {Vec3::UnitZ(), c.z() + h},
          {-Vec3::UnitZ(), -(c.z() - h)}};
}

const slice::Tolerances kTol = slice::Tolerances::from_scale(1, 1e-9);

}  // namespace

TEST_CASE("backend names round-trip", "[lp]") {
  for (auto b : {LpBackend::native, LpBackend::ipopt, LpBackend::exact})
    CHECK(slice::parse_lp_backend(slice::to_string(b)) == b);
  CHECK(slice::parse_lp_backend("NATIVE") == LpBackend::native);
  CHECK_THROWS_AS(slice::parse_lp_backend("clp"), slice::Error);
  CHECK(slice::to_string(LpStatus::unbounded) == "unbounded");
}

TEST_CASE("cut test of the unit cube", "[lp][cut]") {
  const auto backend = GENERATE(LpBackend::native, LpBackend::exact, LpBackend::ipopt);
  CAPTURE(slice::to_string(backend));
  const auto solver = slice::make_solver(backend);
  const auto cube = unit_cube();
  const double tol = answer_tol(backend);

  SECTION("x = 0.5 cuts through the middle: s* = -0.5") {
    const auto r = slice::cut_test(*solver, cube, {Vec3::UnitX(), 0.5}, {}, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.s, WithinAbs(-0.5, tol));
    CHECK(r.cuts);
    CHECK_THAT(r.point.x(), WithinAbs(0.5, tol));
  }
  SECTION("x = 1 touches a face: s* = 0, no cut") {
    const auto r = slice::cut_test(*solver, cube, {Vec3::UnitX(), 1}, {}, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.s, WithinAbs(0, tol));
    CHECK_FALSE(r.cuts);
  }
  SECTION("x = 2 misses: s* = 1, no cut") {
    const auto r = slice::cut_test(*solver, cube, {Vec3::UnitX(), 2}, {}, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.s, WithinAbs(1, tol));
    CHECK_FALSE(r.cuts);
  }
  SECTION("a plane through one vertex only: s* = 0, no cut") {
    const Vec3 n = Vec3(1, 1, 1).normalized();
    const auto r = slice::cut_test(*solver, cube, {n, n.dot(Vec3::Ones())}, {}, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.s, WithinAbs(0, tol));
    CHECK_FALSE(r.cuts);
  }
  SECTION("x = -0.5 with the normal pointing inwards still cuts") {
    const auto r = slice::cut_test(*solver, cube, {-Vec3::UnitX(), -0.5}, {}, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.s, WithinAbs(-0.5, tol));
  }
  SECTION("a polygon in x = 0.5 that misses the cube: no cut") {
    const auto edges = square_in_x_plane({0.5, 3, 3}, 1);
    const auto r = slice::cut_test(*solver, cube, {Vec3::UnitX(), 0.5}, edges, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK(r.s > 0);
    CHECK_FALSE(r.cuts);
  }
  SECTION("a small polygon inside the cube: s* = -(half its side)") {
    const auto edges = square_in_x_plane({0.5, 0.5, 0.5}, 0.4);
    const auto r = slice::cut_test(*solver, cube, {Vec3::UnitX(), 0.5}, edges, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.s, WithinAbs(-0.2, tol));
    CHECK(r.cuts);
  }
  SECTION("a polygon overlapping one corner of the section") {
    // The square [0.9, 1.9]^2 in (y, z) overlaps the section [0, 1]^2 in [0.9, 1]^2: the best
    // point (0.95, 0.95) is 0.05 inside everything.
    const auto edges = square_in_x_plane({0.5, 1.4, 1.4}, 1);
    const auto r = slice::cut_test(*solver, cube, {Vec3::UnitX(), 0.5}, edges, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.s, WithinAbs(-0.05, tol));
  }
}

TEST_CASE("cut test at a 1e6 offset runs in the block frame", "[lp][cut]") {
  const auto backend = GENERATE(LpBackend::native, LpBackend::exact, LpBackend::ipopt);
  CAPTURE(slice::to_string(backend));
  const auto solver = slice::make_solver(backend);
  const Vec3 origin(5e5, 5e6, 300);
  const Plane global{Vec3(1, 2, 2).normalized(), 0};
  const Plane through_centre{global.normal, global.normal.dot(origin + Vec3(0.5, 0.5, 0.5))};
  const auto r =
      slice::cut_test(*solver, unit_cube(), slice::to_local(through_centre, origin), {}, kTol);
  REQUIRE(r.status == LpStatus::optimal);
  CHECK(r.cuts);
  // The plane through the centre with normal (1,2,2)/3 reaches 0.5 inside x... s* = -0.5 is the
  // bound of any plane through the centre of the unit cube (the inscribed ball).
  CHECK_THAT(r.s, WithinAbs(-0.5, 1e-9 + answer_tol(backend)));
}

TEST_CASE("Chebyshev centre and inradius", "[lp][chebyshev]") {
  const auto backend = GENERATE(LpBackend::native, LpBackend::exact, LpBackend::ipopt);
  CAPTURE(slice::to_string(backend));
  const auto solver = slice::make_solver(backend);
  const double tol = answer_tol(backend);

  SECTION("unit cube: radius 0.5 at its centre") {
    const auto r = slice::chebyshev_ball(*solver, unit_cube(), kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.radius, WithinAbs(0.5, tol));
    CHECK((r.centre - Vec3(0.5, 0.5, 0.5)).norm() < 1e3 * tol);
  }
  SECTION("a 4 x 2 x 1 box: radius 0.5, the centre free along x and y but inside") {
    const auto r = slice::chebyshev_ball(*solver, box(Vec3::Zero(), Vec3(4, 2, 1)), kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.radius, WithinAbs(0.5, tol));
    CHECK_THAT(r.centre.z(), WithinAbs(0.5, 1e3 * tol));
  }
  SECTION("a half-space has no finite inscribed ball: unbounded") {
    const std::vector<Face> half{{Vec3::UnitZ(), 0}};
    CHECK(slice::chebyshev_ball(*solver, half, kTol).status == LpStatus::unbounded);
  }
}

TEST_CASE("extents of a rotated cube", "[lp][extents]") {
  const auto backend = GENERATE(LpBackend::native, LpBackend::exact, LpBackend::ipopt);
  CAPTURE(slice::to_string(backend));
  const auto solver = slice::make_solver(backend);
  const double tol = answer_tol(backend);
  // A cube of half-size h centred at c, rotated by R: face normals +-R e_k at distance h.
  const Eigen::Matrix3d rot =
      (Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * Eigen::AngleAxisd(0.7, Vec3::UnitX()))
          .toRotationMatrix();
  const Vec3 c(0.2, -0.1, 0.4);
  const double h = 0.5;
  std::vector<Face> faces;
  for (int k = 0; k < 3; ++k)
    for (double sgn : {1.0, -1.0}) {
      const Vec3 n = sgn * rot.col(k);
      faces.push_back({n, h + n.dot(c)});
    }
  const auto r = slice::extents(*solver, faces, kTol);
  REQUIRE(r.status == LpStatus::optimal);
  // The extreme x_k of the cube is c_k +- h sum_j |R_kj|.
  const Vec3 half = h * rot.cwiseAbs().rowwise().sum();
  for (int k = 0; k < 3; ++k) {
    CHECK_THAT(r.max[k], WithinAbs(c[k] + half[k], tol));
    CHECK_THAT(r.min[k], WithinAbs(c[k] - half[k], tol));
    CHECK_THAT(r.centre[k], WithinAbs(c[k], tol));
  }
  CHECK_THAT(r.radius, WithinAbs(half.norm(), tol));
}

TEST_CASE("redundant faces", "[lp][prune]") {
  const auto backend = GENERATE(LpBackend::native, LpBackend::exact, LpBackend::ipopt);
  CAPTURE(slice::to_string(backend));
  const auto solver = slice::make_solver(backend);
  const double tol = answer_tol(backend);
  auto faces = unit_cube();
  const Vec3 n = Vec3(1, 1, 0).normalized();
  faces.push_back({n, 1.5 * n.x()});  // x + y <= 1.5: cuts an edge off
  faces.push_back({n, 2.5 * n.x()});  // x + y <= 2.5: misses the cube

  SECTION("a face that cuts a corner is not redundant") {
    const auto r = slice::face_redundancy(*solver, faces, 6, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.value, WithinAbs(2 * n.x(), tol));
    CHECK_FALSE(r.redundant);
  }
  SECTION("a face beyond the block is redundant") {
    const auto r = slice::face_redundancy(*solver, faces, 7, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.value, WithinAbs(1.5 * n.x(), tol));
    CHECK(r.redundant);
  }
  SECTION("x <= 1 is still a face: without it x reaches 1.5") {
    const auto r = slice::face_redundancy(*solver, faces, 1, kTol);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.value, WithinAbs(1.5, tol));
    CHECK_FALSE(r.redundant);
  }
  SECTION("without z <= 1 nothing bounds z: unbounded, not redundant") {
    const auto r = slice::face_redundancy(*solver, faces, 5, kTol);
    CHECK(r.status == LpStatus::unbounded);
    CHECK_FALSE(r.redundant);
  }
  SECTION("a face index past the block throws") {
    CHECK_THROWS_AS(slice::face_redundancy(*solver, faces, 8, kTol), slice::Error);
  }
}

TEST_CASE("generic LPs: infeasible, unbounded, degenerate, parallel", "[lp]") {
  const auto backend = GENERATE(LpBackend::native, LpBackend::exact, LpBackend::ipopt);
  CAPTURE(slice::to_string(backend));
  const auto solver = slice::make_solver(backend);
  const double tol = answer_tol(backend);
  slice::DenseLp lp;

  SECTION("x <= 0 and x >= 1: infeasible") {
    lp.reset(2);
    lp.c = LpVec(1, 1, 0, 0);
    lp.add_row(LpVec(1, 0, 0, 0), 0);
    lp.add_row(LpVec(-1, 0, 0, 0), -1);
    lp.add_row(LpVec(0, -1, 0, 0), 0);
    CHECK(solver->solve(lp).status == LpStatus::infeasible);
  }
  SECTION("an empty triangle: infeasible in 3 variables") {
    lp.reset(3);
    lp.c = LpVec(0, 0, 1, 0);
    lp.add_row(LpVec(1, 1, 0, 0), 1);
    lp.add_row(LpVec(-1, 0, 0, 0), -1);
    lp.add_row(LpVec(0, -1, 0, 0), -1);
    lp.add_row(LpVec(0, 0, -1, 0), 0);
    CHECK(solver->solve(lp).status == LpStatus::infeasible);
  }
  SECTION("maximise x with only x >= 0: unbounded") {
    lp.reset(2);
    lp.maximise = true;
    lp.c = LpVec(1, 0, 0, 0);
    lp.add_row(LpVec(-1, 0, 0, 0), 0);
    lp.add_row(LpVec(0, 1, 0, 0), 1);
    lp.add_row(LpVec(0, -1, 0, 0), 1);
    CHECK(solver->solve(lp).status == LpStatus::unbounded);
  }
  SECTION("bounds instead of rows, maximise x + y in [0,1] x [0,2]") {
    lp.reset(2);
    lp.maximise = true;
    lp.c = LpVec(1, 1, 0, 0);
    lp.lower = LpVec(0, 0, 0, 0);
    lp.upper = LpVec(1, 2, 0, 0);
    const auto r = solver->solve(lp);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.objective, WithinAbs(3, tol));
  }
  SECTION("degenerate: eight rows through the optimal vertex, duplicates and parallels") {
    // min x + y + z over the octant shifted to (1, 2, 3), with the same rows repeated, parallel
    // rows that do not bind, and several other rows through the vertex.
    lp.reset(3);
    lp.c = LpVec(1, 1, 1, 0);
    const Vec3 v(1, 2, 3);
    for (int rep = 0; rep < 3; ++rep)
      for (int k = 0; k < 3; ++k) lp.add_row(-LpVec::Unit(k), -v[k]);
    for (int k = 0; k < 3; ++k) lp.add_row(-LpVec::Unit(k), -v[k] + 5);  // parallel, slack
    for (const Vec3& n : {Vec3(-1, -1, 0), Vec3(-1, 0, -1), Vec3(0, -1, -1), Vec3(-1, -1, -1)}) {
      const Vec3 u = n.normalized();
      lp.add_row(LpVec(u.x(), u.y(), u.z(), 0), u.dot(v));
    }
    const auto r = solver->solve(lp);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.objective, WithinAbs(6, tol * 10));
  }
  SECTION("four variables") {
    // min t s.t. x_k - 1 <= t, -x_k <= t for k = 0..2: the centre of [0,1]^3, t = -0.5.
    lp.reset(4);
    lp.c = LpVec(0, 0, 0, 1);
    for (int k = 0; k < 3; ++k) {
      LpVec a = LpVec::Unit(k);
      a[3] = -1;
      lp.add_row(a, 1);
      a[k] = -1;
      lp.add_row(a, 0);
    }
    const auto r = solver->solve(lp);
    REQUIRE(r.status == LpStatus::optimal);
    CHECK_THAT(r.objective, WithinAbs(-0.5, tol));
  }
  SECTION("bad input throws") {
    lp.reset(5);
    CHECK_THROWS_AS(solver->solve(lp), slice::Error);
    lp.reset(2);
    lp.add_row(LpVec(std::nan(""), 0, 0, 0), 1);
    CHECK_THROWS_AS(solver->solve(lp), slice::Error);
  }
}

TEST_CASE("a non-unit face normal is bad input", "[lp]") {
  const auto solver = slice::make_solver(LpBackend::native);
  auto faces = unit_cube();
  faces[2].normal *= 2;
  CHECK_THROWS_AS(slice::chebyshev_ball(*solver, faces, kTol), slice::Error);
  CHECK_THROWS_AS(slice::cut_test(*solver, faces, {Vec3::UnitX(), 0.5}, {}, kTol), slice::Error);
}

TEST_CASE("a cut test names the bad face or edge wherever it is, on every backend", "[lp]") {
  // The native backend checks the rows four at a time (AVX2) and the rest one by one: a bad row
  // in every position of blocks of 4 to 9 faces, and of a 5-edge polygon, must throw and name it.
  const auto backend = GENERATE(LpBackend::native, LpBackend::exact, LpBackend::ipopt);
  CAPTURE(slice::to_string(backend));
  const auto solver = slice::make_solver(backend);
  const Plane plane{Vec3(1, 2, 2).normalized(), 0.1};
  std::vector<Plane> edges;
  for (int k = 0; k < 5; ++k) {
    const double phi = 2 * 3.141592653589793 * k / 5;
    const Vec3 e1 = plane.normal.unitOrthogonal(), e2 = plane.normal.cross(e1);
    const Vec3 e = std::cos(phi) * e1 + std::sin(phi) * e2;
    edges.push_back({e, e.dot(plane.d * plane.normal) + 0.3});
  }
  const auto message = [&](const std::vector<Face>& faces, const std::vector<Plane>& es) {
    try {
      slice::cut_test(*solver, faces, plane, es, kTol);
    } catch (const slice::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  for (int n = 4; n <= 9; ++n) {
    std::vector<Face> faces;
    for (int i = 0; i < n; ++i) {
      const double t = 2.399963 * i, z = 1 - (2 * i + 1.0) / n;  // spread over the sphere
      const double r = std::sqrt(1 - z * z);
      faces.push_back({Vec3(r * std::cos(t), r * std::sin(t), z), 1});
    }
    REQUIRE(message(faces, edges) == "no error");
    for (int i = 0; i < n; ++i) {
      for (const int kind : {0, 1, 2, 3}) {
        auto bad = faces;
        if (kind == 0) bad[i].normal *= 1 + 1e-6;
        if (kind == 1) bad[i].normal.x() = std::nan("");
        if (kind == 2) bad[i].d = std::numeric_limits<double>::infinity();
        if (kind == 3) bad[i].d = std::nan("");
        CAPTURE(n, i, kind);
        CHECK_THAT(message(bad, edges),
                   Catch::Matchers::Contains("face " + std::to_string(i) + " "));
      }
    }
    for (int k = 0; k < 5; ++k) {
      auto bad = edges;
      bad[k].normal *= 0.5;
      CAPTURE(n, k);
      CHECK_THAT(message(faces, bad),
                 Catch::Matchers::Contains("polygon edge " + std::to_string(k)));
    }
  }
}

TEST_CASE("batched solves give the single-solve answers", "[lp]") {
  const auto backend = GENERATE(LpBackend::native, LpBackend::exact, LpBackend::ipopt);
  CAPTURE(slice::to_string(backend));
  const auto solver = slice::make_solver(backend);
  std::vector<slice::DenseLp> lps(3);
  for (int k = 0; k < 3; ++k) {
    lps[k].reset(2);
    lps[k].c = LpVec(1, 1, 0, 0);
    lps[k].add_row(LpVec(-1, 0, 0, 0), k);
    lps[k].add_row(LpVec(0, -1, 0, 0), 1);
  }
  std::vector<slice::LpResult> out(3);
  solver->solve_batch(lps, out);
  for (int k = 0; k < 3; ++k) {
    REQUIRE(out[k].status == LpStatus::optimal);
    CHECK_THAT(out[k].objective, WithinAbs(-k - 1, answer_tol(backend)));
  }
  lps[1].add_row(LpVec(1, 0, 0, 0), -5);  // infeasible: the batch falls back to single solves
  solver->solve_batch(lps, out);
  CHECK(out[0].status == LpStatus::optimal);
  CHECK(out[1].status == LpStatus::infeasible);
  CHECK(out[2].status == LpStatus::optimal);
}

TEST_CASE("tolerances without a positive length scale are bad input", "[lp]") {
  const auto solver = slice::make_solver(LpBackend::native);
  slice::Tolerances tol = kTol;
  tol.length_scale = 0;
  CHECK_THROWS_AS(slice::chebyshev_ball(*solver, unit_cube(), tol), slice::Error);
  tol = kTol;
  tol.cut = std::nan("");
  CHECK_THROWS_AS(slice::cut_test(*solver, unit_cube(), {Vec3::UnitX(), 0.5}, {}, tol),
                  slice::Error);
}

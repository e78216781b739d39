// The orientation convention (docs/design.md, "The linear programs"): x East, y North, z Up; dip
// direction clockwise from North; upward normal n = (sin d sin a, sin d cos a, cos d).
#include "slice/orientation.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using Catch::Matchers::WithinAbs;
using slice::Vec3;

namespace {
void check_vec(const Vec3& got, const Vec3& want, double tol) {
  CAPTURE(got.transpose(), want.transpose());
  CHECK_THAT(got.x(), WithinAbs(want.x(), tol));
  CHECK_THAT(got.y(), WithinAbs(want.y(), tol));
  CHECK_THAT(got.z(), WithinAbs(want.z(), tol));
}
}  // namespace

TEST_CASE("sind and cosd are exact at multiples of 90 degrees", "[orientation]") {
  CHECK(slice::sind(0) == 0.0);
  CHECK(slice::sind(90) == 1.0);
  CHECK(slice::sind(180) == 0.0);
  CHECK(slice::sind(270) == -1.0);
  CHECK(slice::sind(-90) == -1.0);
  CHECK(slice::cosd(0) == 1.0);
  CHECK(slice::cosd(90) == 0.0);
  CHECK(slice::cosd(180) == -1.0);
  CHECK(slice::cosd(360) == 1.0);
  CHECK(slice::sind(450) == 1.0);
  CHECK_THAT(slice::sind(30), WithinAbs(0.5, 1e-16));
  CHECK_THAT(slice::cosd(60), WithinAbs(0.5, 1e-16));
}

TEST_CASE("sind and cosd keep the complement and half-turn identities bit for bit",
          "[orientation]") {
  for (int deg = -720; deg <= 720; ++deg) {
    CAPTURE(deg);
    REQUIRE(slice::sind(90.0 - deg) == slice::cosd(deg));
    REQUIRE(slice::cosd(90.0 - deg) == slice::sind(deg));
    REQUIRE(slice::sind(deg - 180.0) == -slice::sind(deg));
    REQUIRE(slice::cosd(deg - 180.0) == -slice::cosd(deg));
  }
}

TEST_CASE("upward normal of hand-computed orientations", "[orientation]") {
  SECTION("dip 0 is horizontal whatever the dip direction") {
    for (double a : {0.0, 90.0, 180.0, 270.0, 37.5}) {
      const Vec3 n = slice::normal_from_dip(0, a);
      CHECK(n.x() == 0.0);
      CHECK(n.y() == 0.0);
      CHECK(n.z() == 1.0);
    }
  }
  SECTION("dip 90: the normal is horizontal and points along the dip direction") {
    check_vec(slice::normal_from_dip(90, 0), {0, 1, 0}, 0);     // dips North
    check_vec(slice::normal_from_dip(90, 90), {1, 0, 0}, 0);    // dips East
    check_vec(slice::normal_from_dip(90, 180), {0, -1, 0}, 0);  // dips South
    check_vec(slice::normal_from_dip(90, 270), {-1, 0, 0}, 0);  // dips West
    CHECK(slice::normal_from_dip(90, 37).z() == 0.0);
  }
  SECTION("dip 45 towards East and towards South") {
    const double h = std::sqrt(0.5);
    check_vec(slice::normal_from_dip(45, 90), {h, 0, h}, 1e-15);
    check_vec(slice::normal_from_dip(45, 180), {0, -h, h}, 1e-15);
  }
  SECTION("the paper's Table 3 sets, dip direction / dip 122/8, 112/80, 9/85") {
    // sin d sin a, sin d cos a, cos d evaluated by hand (15 digits).
    check_vec(slice::normal_from_dip(8, 122),
              {0.118025483305370, -0.073750507261811, 0.990268068741570}, 1e-14);
    check_vec(slice::normal_from_dip(80, 112),
              {0.913097848445116, -0.368915477525482, 0.173648177666930}, 1e-14);
    check_vec(slice::normal_from_dip(85, 9),
              {0.155839184671897, 0.983929888267910, 0.087155742747658}, 1e-14);
  }
  SECTION("unit length") {
    for (double d = 0; d <= 90; d += 7.5)
      for (double a = 0; a < 360; a += 11.25)
        CHECK_THAT(slice::normal_from_dip(d, a).norm(), WithinAbs(1, 1e-15));
  }
}

TEST_CASE("the paper's Priest-frame pole is exactly -n after the frame change", "[orientation]") {
  // Priest: x North, y East, z Down; N = (cos b cos a, sin b cos a, sin a), a = 90 - dip,
  // b = dip direction - 180: the downward pole of the same plane.
  struct Case {
    double dip, dd;
  };
  for (const Case c :
       {Case{8, 122}, Case{80, 112}, Case{85, 9}, Case{0, 0}, Case{90, 0}, Case{90, 90},
        Case{90, 180}, Case{90, 270}, Case{45, 45}, Case{30, 300}, Case{60, 225}, Case{12, 359}}) {
    CAPTURE(c.dip, c.dd);
    const Vec3 n = slice::normal_from_dip(c.dip, c.dd);
    const Vec3 p = slice::priest_to_global(slice::priest_pole(c.dip, c.dd));
    CHECK(p.x() == -n.x());
    CHECK(p.y() == -n.y());
    CHECK(p.z() == -n.z());
  }
  // A non-integer orientation: equal to rounding.
  const Vec3 n = slice::normal_from_dip(33.3, 123.4);
  check_vec(slice::priest_to_global(slice::priest_pole(33.3, 123.4)), -n, 1e-15);
}

TEST_CASE("strike and dip vectors", "[orientation]") {
  // Dip direction East: strike is North (right-hand rule), the dip vector goes East and down.
  check_vec(slice::strike_vector(90), {0, 1, 0}, 0);
  check_vec(slice::strike_vector(0), {-1, 0, 0}, 0);    // dips North: strike West
  check_vec(slice::strike_vector(180), {1, 0, 0}, 0);   // dips South: strike East
  check_vec(slice::strike_vector(270), {0, -1, 0}, 0);  // dips West: strike South
  check_vec(slice::dip_vector(30, 90), {std::sqrt(3.0) / 2, 0, -0.5}, 1e-15);
  check_vec(slice::dip_vector(90, 180), {0, 0, -1}, 1e-15);
  for (double d : {0.0, 8.0, 45.0, 85.0, 90.0})
    for (double a : {0.0, 9.0, 112.0, 122.0, 270.0}) {
      CAPTURE(d, a);
      const Vec3 s = slice::strike_vector(a), v = slice::dip_vector(d, a);
      const Vec3 n = slice::normal_from_dip(d, a);
      CHECK_THAT(s.dot(n), WithinAbs(0, 1e-15));
      CHECK_THAT(v.dot(n), WithinAbs(0, 1e-15));
      CHECK_THAT(v.norm(), WithinAbs(1, 1e-15));
      CHECK(v.z() <= 0);  // down dip
    }
}

TEST_CASE("plane frame: u along strike, v = n x strike, right-handed", "[orientation]") {
  for (double d : {0.0, 8.0, 45.0, 80.0, 90.0})
    for (double a : {0.0, 9.0, 112.0, 122.0, 200.0}) {
      CAPTURE(d, a);
      const auto f = slice::plane_frame(d, a);
      check_vec(f.u, slice::strike_vector(a), 0);
      check_vec(f.u.cross(f.v), f.n, 1e-15);
      CHECK_THAT(f.u.dot(f.v), WithinAbs(0, 1e-15));
      check_vec(f.v, -slice::dip_vector(d, a), 1e-15);  // v runs up the dip line
      const Vec3 o(5e5, 5e6, 300);
      const Vec3 x = f.to_global(o, {2.5, -1.25});
      const auto uv = f.to_uv(o, x);
      CHECK_THAT(uv.x(), WithinAbs(2.5, 1e-9));
      CHECK_THAT(uv.y(), WithinAbs(-1.25, 1e-9));
      CHECK_THAT(f.n.dot(x - o), WithinAbs(0, 1e-9));
    }
}

TEST_CASE("normal to dip and dip direction inverts normal_from_dip", "[orientation]") {
  for (double d = 0.5; d <= 89.5; d += 4.5)
    for (double a = 0; a < 360; a += 7.5) {
      CAPTURE(d, a);
      const Vec3 n = slice::normal_from_dip(d, a);
      for (const Vec3& m : {n, Vec3(-n), Vec3(3.0 * n)}) {
        const auto r = slice::dip_from_normal(m);
        CHECK_THAT(r.dip_deg, WithinAbs(d, 1e-12));
        CHECK_THAT(r.dip_direction_deg, WithinAbs(a, 1e-11));
      }
    }
  const auto flat = slice::dip_from_normal({0, 0, -2});
  CHECK(flat.dip_deg == 0.0);
  CHECK(flat.dip_direction_deg == 0.0);
  const auto east = slice::dip_from_normal({1, 0, 0});
  CHECK_THAT(east.dip_deg, WithinAbs(90, 1e-12));
  CHECK_THAT(east.dip_direction_deg, WithinAbs(90, 1e-12));
}

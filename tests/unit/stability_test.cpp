// One body's stability (slice/stability.hpp, analyse_body): Goodman & Shi's removability and the
// mode of motion, with the factor of safety against the closed forms of limit equilibrium. Frame
// of docs/design.md, "The linear programs": x East, y North, z Up, gravity -z; a plane's upward
// normal is (sin dip sin dipdir, sin dip cos dipdir, cos dip). A ContactPlane's normal is the
// body's outward normal: a block resting on a plane has the plane's downward normal there.
#include "slice/stability.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::BodyStability;
using slice::ContactPlane;
using slice::FailureMode;
using slice::Vec3;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kW = 2.5e6;  // weight of the test blocks, N (about 100 m3 of rock)

double rad(double deg) { return deg * std::numbers::pi / 180; }

/// The upward unit normal of a plane dip / dip direction (degrees), computed here with std::sin
/// rather than slice::normal_from_dip so that the test does not lean on the library.
Vec3 upward(double dip_deg, double dip_direction_deg) {
  const double d = rad(dip_deg), a = rad(dip_direction_deg);
  return {std::sin(d) * std::sin(a), std::sin(d) * std::cos(a), std::cos(d)};
}

/// A contact plane of outward normal n, area A, friction angle phi (degrees), cohesion c and
/// tensile strength t (Pa): the sums the stage makes of its contacts.
ContactPlane plane(const Vec3& n, double A, double phi_deg, double c = 0, double t = 0) {
  ContactPlane p;
  p.normal = n;
  p.area = A;
  p.friction = A * std::tan(rad(phi_deg));
  p.cohesion = c * A;
  p.tension = t * A;
  return p;
}

BodyStability analyse(const std::vector<ContactPlane>& planes, const Vec3& r) {
  return slice::analyse_body(planes, r);
}

void check_vec(const Vec3& got, const Vec3& want, double tol) {
  CAPTURE(got.transpose(), want.transpose());
  CHECK_THAT(got.x(), WithinAbs(want.x(), tol));
  CHECK_THAT(got.y(), WithinAbs(want.y(), tol));
  CHECK_THAT(got.z(), WithinAbs(want.z(), tol));
}

/// Nothing the resultant drives: removable, mode stable, no direction, no planes.
void check_stable(const BodyStability& s) {
  CHECK(s.removable);
  CHECK(s.mode == FailureMode::stable);
  CHECK(s.fos == kInf);
  CHECK(s.direction == Vec3::Zero());
  CHECK(s.planes == std::array<int, 2>{-1, -1});
}

/// The block's outward normal on a plane dipping alpha towards +x (dip direction 90): the
/// plane's downward normal, -(sin a, 0, cos a).
Vec3 on_slope(double alpha_deg) { return -upward(alpha_deg, 90); }

}  // namespace

TEST_CASE("analyse_body: a block on one plane slides down dip, FoS tan(phi) / tan(alpha)",
          "[stability]") {
  const double alpha = GENERATE(10.0, 30.0, 45.0, 70.0);
  const double phi = GENERATE(0.0, 20.0, 35.0, 60.0);  // above and below the dip: the mode is the
                                                       // same, the FoS says which one fails
  CAPTURE(alpha, phi);
  const std::vector<ContactPlane> planes{plane(on_slope(alpha), 40, phi)};
  const BodyStability s = analyse(planes, {0, 0, -kW});
  CHECK(s.removable);
  CHECK(s.mode == FailureMode::slides_one);
  CHECK(s.planes == std::array<int, 2>{0, -1});
  // Down dip: towards +x, plunging alpha.
  check_vec(s.direction, {std::cos(rad(alpha)), 0, -std::sin(rad(alpha))}, 1e-12);
  const double want = std::tan(rad(phi)) / std::tan(rad(alpha));
  CHECK_THAT(s.fos, WithinRel(want, 1e-12) || WithinAbs(want, 1e-15));
}

TEST_CASE("analyse_body: cohesion adds c A to the resisting force of a sliding block",
          "[stability]") {
  const double alpha = 35, phi = 25, A = 12.5, c = 4e4;  // c A = 5e5 N
  const double a = rad(alpha);
  const std::vector<ContactPlane> planes{plane(on_slope(alpha), A, phi, c)};
  const BodyStability s = analyse(planes, {0, 0, -kW});
  REQUIRE(s.mode == FailureMode::slides_one);
  const double want = (c * A + kW * std::cos(a) * std::tan(rad(phi))) / (kW * std::sin(a));
  CHECK_THAT(s.fos, WithinRel(want, 1e-12));
  check_vec(s.direction, {std::cos(a), 0, -std::sin(a)}, 1e-12);
}

TEST_CASE("analyse_body: the tension of a face the sliding block leaves resists, resolved",
          "[stability]") {
  // A tension crack behind the block: its face there points up-slope (-x) and the block leaves
  // it at cos(alpha) per unit of motion; the tension of the base, which it slides along, and of
  // a side face it runs along does not count.
  const double alpha = 40, phi = 30, A = 20, c = 1e4, t = 5e3, A_back = 8, t_back = 2e4;
  const double a = rad(alpha);
  const std::vector<ContactPlane> planes{plane(on_slope(alpha), A, phi, c, t),
                                         plane({-1, 0, 0}, A_back, 30, 0, t_back),
                                         plane({0, 1, 0}, 5, 30, 0, 1e6)};
  const BodyStability s = analyse(planes, {0, 0, -kW});
  REQUIRE(s.mode == FailureMode::slides_one);
  CHECK(s.planes == std::array<int, 2>{0, -1});
  const double resisting =
      kW * std::cos(a) * std::tan(rad(phi)) + c * A + t_back * A_back * std::cos(a);
  CHECK_THAT(s.fos, WithinRel(resisting / (kW * std::sin(a)), 1e-12));
}

TEST_CASE("analyse_body: a release face parallel to the motion changes nothing", "[stability]") {
  const double alpha = 30, phi = 20;
  const ContactPlane base = plane(on_slope(alpha), 40, phi, 1e4);
  // A vertical side face: its normal (0, +-1, 0) is perpendicular to the motion down dip. The
  // block runs along it, so it neither blocks the slide nor resists it (its strength is moot).
  const ContactPlane side = plane({0, 1, 0}, 25, 45, 1e6, 1e6);
  const BodyStability alone = analyse({base}, {0, 0, -kW});
  REQUIRE(alone.mode == FailureMode::slides_one);

  SECTION("after the base") {
    const BodyStability s = analyse({base, side}, {0, 0, -kW});
    CHECK(s.mode == FailureMode::slides_one);
    CHECK(s.planes == std::array<int, 2>{0, -1});
    CHECK_THAT(s.fos, WithinRel(alone.fos, 1e-12));
    check_vec(s.direction, alone.direction, 1e-12);
  }
  SECTION("before the base, and a second one opposite: the index follows the span") {
    ContactPlane other = side;
    other.normal = {0, -1, 0};
    const BodyStability s = analyse({side, base, other}, {0, 0, -kW});
    CHECK(s.removable);
    CHECK(s.mode == FailureMode::slides_one);
    CHECK(s.planes == std::array<int, 2>{1, -1});
    CHECK_THAT(s.fos, WithinRel(alone.fos, 1e-12));
    check_vec(s.direction, alone.direction, 1e-12);
  }
}

TEST_CASE("analyse_body: a locked plane never slips", "[stability]") {
  ContactPlane base = plane(on_slope(30), 40, 10);
  base.locked = true;
  check_stable(analyse({base}, {0, 0, -kW}));
  // A wedge with one of its planes locked does not slide on the other alone either.
  ContactPlane a = plane(-upward(40, 130), 50, 30), b = plane(-upward(60, 220), 50, 30);
  b.locked = true;
  check_stable(analyse({a, b}, {0, 0, -kW}));
}

TEST_CASE("analyse_body: a block on a horizontal floor is removable and stable", "[stability]") {
  const std::vector<ContactPlane> floor{plane({0, 0, -1}, 10, 30)};
  check_stable(analyse(floor, {0, 0, -kW}));
  SECTION("also in an open box: floor and four walls, free above") {
    const std::vector<ContactPlane> box{floor[0], plane({1, 0, 0}, 5, 30), plane({-1, 0, 0}, 5, 30),
                                        plane({0, 1, 0}, 5, 30), plane({0, -1, 0}, 5, 30)};
    check_stable(analyse(box, {0, 0, -kW}));
    // Lifted out of it (a resultant upwards): it falls upwards, held by no tension here.
    const BodyStability s = analyse(box, {0, 0, 3e5});
    CHECK(s.mode == FailureMode::falls);
    CHECK(s.fos == 0.0);
    check_vec(s.direction, {0, 0, 1}, 0);
  }
  SECTION("no resultant drives nothing") { check_stable(analyse(floor, Vec3::Zero())); }
}

TEST_CASE("analyse_body: a block in a closed box of six faces is not removable", "[stability]") {
  std::vector<ContactPlane> box;
  for (int k = 0; k < 3; ++k)
    for (const double sign : {1.0, -1.0}) box.push_back(plane(sign * Vec3::Unit(k), 4, 30));
  for (const Vec3& r : {Vec3(0, 0, -kW), Vec3(1, 2, 3), Vec3(0, 0, 0)}) {
    CAPTURE(r.transpose());
    const BodyStability s = analyse(box, r);
    CHECK_FALSE(s.removable);
    CHECK(s.mode == FailureMode::not_removable);
    CHECK(s.fos == kInf);
    CHECK(s.direction == Vec3::Zero());
  }
  // A tetrahedron's four faces lock it as well (its normals positively span space).
  const std::vector<ContactPlane> tet{
      plane(Vec3(1, 1, 1).normalized(), 1, 30), plane(Vec3(1, -1, -1).normalized(), 1, 30),
      plane(Vec3(-1, 1, -1).normalized(), 1, 30), plane(Vec3(-1, -1, 1).normalized(), 1, 30)};
  CHECK(analyse(tet, {0, 0, -kW}).mode == FailureMode::not_removable);
  // Without one face it comes out.
  CHECK(analyse({tet.begin(), tet.end() - 1}, {0, 0, -kW}).removable);
}

TEST_CASE("analyse_body: a block hanging from a roof between vertical faces falls", "[stability]") {
  // The roof is above the block: its outward normal there is +z. The four sides are vertical
  // and the motion, straight down, runs along them.
  const double A_roof = 6, A_side = 9;
  const auto body = [&](double t_roof, double t_side, bool east_wall = true) {
    std::vector<ContactPlane> out{
        plane({0, 0, 1}, A_roof, 30, 1e5, t_roof), plane({-1, 0, 0}, A_side, 30, 1e5, t_side),
        plane({0, 1, 0}, A_side, 30, 1e5, t_side), plane({0, -1, 0}, A_side, 30, 1e5, t_side)};
    if (east_wall) out.push_back(plane({1, 0, 0}, A_side, 30, 1e5, t_side));
    return out;
  };
  SECTION("without tension: FoS 0 (cohesion holds nothing it leaves)") {
    const BodyStability s = analyse(body(0, 0), {0, 0, -kW});
    CHECK(s.removable);
    CHECK(s.mode == FailureMode::falls);
    CHECK(s.fos == 0.0);
    check_vec(s.direction, {0, 0, -1}, 0);
    CHECK(s.planes == std::array<int, 2>{-1, -1});
  }
  SECTION("with tension: the roof's t A over W; the sides it runs along do not count") {
    const double t_roof = 1.5e5;  // t A = 9e5 N
    const BodyStability s = analyse(body(t_roof, 1e7), {0, 0, -kW});
    CHECK(s.mode == FailureMode::falls);
    CHECK_THAT(s.fos, WithinRel(t_roof * A_roof / kW, 1e-12));
  }
  SECTION("an oblique resultant leaves roof and one side: each tension resolved against it") {
    // Without the east wall (+x): the resultant leaves the roof (+z) and the west wall (-x)
    // and runs along the north and south walls (+-y).
    const double t = 1e5;
    const Vec3 r(1e6, 0, -kW);
    CHECK(analyse(body(t, t), r).mode != FailureMode::falls);  // the east wall is in the way
    const BodyStability s = analyse(body(t, t, false), r);
    REQUIRE(s.mode == FailureMode::falls);
    const Vec3 d = r.normalized();
    check_vec(s.direction, d, 1e-15);
    CHECK_THAT(s.fos, WithinRel((t * A_roof * -d.z() + t * A_side * d.x()) / r.norm(), 1e-12));
  }
  SECTION("a body with no planes at all falls") {
    const BodyStability s = analyse({}, {0, 0, -kW});
    CHECK(s.removable);
    CHECK(s.mode == FailureMode::falls);
    CHECK(s.fos == 0.0);
  }
}

TEST_CASE("analyse_body: Hoek & Bray's wedge on planes 40/130 and 60/220 slides on both",
          "[stability]") {
  // The wedge rests on both planes: its outward normals there are their downward normals. The
  // limit equilibrium, solved here as a 3 x 3 system: weight + N_A n_A + N_B n_B - T e = 0 with
  // n the planes' upward normals (the reactions on the wedge), e the line of intersection
  // plunging, T the shear force along it that holds the wedge. T = W sin(psi) with psi the
  // plunge; FoS = (N_A tan(phi_A) + N_B tan(phi_B) + c_A A_A + c_B A_B) / T.
  const Vec3 nA = upward(40, 130), nB = upward(60, 220);
  Vec3 e = nA.cross(nB).normalized();
  if (e.z() > 0) e = -e;
  const double phiA = 30, phiB = 35, AA = 150, AB = 90;
  const double c = GENERATE(0.0, 2e3);
  CAPTURE(c);
  const Vec3 weight(0, 0, -kW);
  Eigen::Matrix3d M;
  M.col(0) = nA;
  M.col(1) = nB;
  M.col(2) = -e;
  const Vec3 x = M.fullPivLu().solve(-weight);
  const double NA = x[0], NB = x[1], T = x[2];
  REQUIRE(NA > 0);  // both planes carry the wedge: a two-plane slide
  REQUIRE(NB > 0);
  CHECK_THAT(T, WithinRel(kW * -e.z(), 1e-12));  // W sin(plunge)
  // The line of intersection plunges 37.06 degrees towards 155.8 degrees.
  CHECK_THAT(std::asin(-e.z()) * 180 / std::numbers::pi, WithinAbs(37.058, 1e-3));
  CHECK_THAT(std::atan2(e.x(), e.y()) * 180 / std::numbers::pi, WithinAbs(155.848, 1e-3));

  const std::vector<ContactPlane> planes{plane(-nA, AA, phiA, c), plane(-nB, AB, phiB, c)};
  const BodyStability s = analyse(planes, weight);
  CHECK(s.removable);
  CHECK(s.mode == FailureMode::slides_two);
  CHECK(s.planes == std::array<int, 2>{0, 1});
  check_vec(s.direction, e, 1e-12);
  const double want = (NA * std::tan(rad(phiA)) + NB * std::tan(rad(phiB)) + c * AA + c * AB) / T;
  CHECK_THAT(s.fos, WithinRel(want, 1e-12));
  if (c == 0) CHECK_THAT(s.fos, WithinAbs(0.92638, 1e-5));  // the same, rounded

  SECTION("a release face along the line of intersection, above the wedge, changes nothing") {
    // A face containing e whose outward normal lies between the planes' upward normals (the
    // wedge's upper face, or a joint above it): the wedge runs along it and the resultant pulls
    // away from it. (A face containing e that the wedge could lean on, such as a vertical wall
    // beside it, is no release face: three planes along one line share the load in a way
    // equilibrium does not decide.)
    const Vec3 z_perp = (Vec3::UnitZ() - e.z() * e).normalized();
    for (const Vec3& m : {z_perp, Vec3((nA + nB).normalized()), Vec3((2 * nA + nB).normalized()),
                          Vec3((nA + 3 * nB).normalized())}) {
      CAPTURE(m.transpose());
      const std::vector<ContactPlane> with{planes[0], planes[1], plane(m, 30, 0, 0, 1e6)};
      const BodyStability w = analyse(with, weight);
      CHECK(w.mode == FailureMode::slides_two);
      CHECK(w.planes == std::array<int, 2>{0, 1});
      CHECK_THAT(w.fos, WithinRel(s.fos, 1e-12));
      check_vec(w.direction, e, 1e-12);
    }
  }
  SECTION("a face across the line below the wedge stops it; up the line it is still free") {
    const std::vector<ContactPlane> with{planes[0], planes[1], plane(e, 30, 10)};
    check_stable(analyse(with, weight));
  }
}

// The dual hull's orientation predicate (slice::orientation_sign, vertices.cpp) against CGAL's
// exact one on the point sets where a filter cannot decide: dual points n / d of parallel face
// pairs (four from two pairs lie, but for rounding, in a plane through the origin), boxes (exact
// zeros), points rounded onto a facet's plane, exactly coplanar and collinear points, and all of
// them scaled by powers of two out to where products underflow. Any sign that differs would
// change a block's hull; none may.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "slice/vertices.hpp"
#include "support/support.hpp"

using slice::Vec3;

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

int cgal_sign(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
  const auto pt = [](const Vec3& v) { return Kernel::Point_3(v.x(), v.y(), v.z()); };
  return int(CGAL::orientation(pt(p), pt(q), pt(r), pt(s)));
}

Vec3 unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0, 1);
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

/// The same sign as CGAL for every order of the four points (each is a different determinant in
/// floating point). Counts the cases, those whose sign is 0 and the nearly coplanar ones.
struct Checker {
  std::size_t cases = 0, zeros = 0, near = 0, wrong = 0;
  void operator()(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
    std::array<Vec3, 4> v{p, q, r, s};
    std::array<int, 4> idx{0, 1, 2, 3};
    do {
      const Vec3 &a = v[std::size_t(idx[0])], &b = v[std::size_t(idx[1])],
                 &c = v[std::size_t(idx[2])], &d = v[std::size_t(idx[3])];
      const int want = cgal_sign(a, b, c, d), got = slice::orientation_sign(a, b, c, d);
      if (got != want) {  // named only when wrong: formatting every case would be the test's time
        CAPTURE(a.transpose(), b.transpose(), c.transpose(), d.transpose());
        CHECK(got == want);
        ++wrong;
      }
      ++cases;
      zeros += want == 0;
      // A naive determinant within 1e-12 of its scale: a case no plain filter decides.
      const Vec3 u = b - a, w = c - a, x = d - a;
      near += std::abs(x.dot(u.cross(w))) <= 1e-12 * u.norm() * w.norm() * x.norm();
    } while (std::next_permutation(idx.begin(), idx.end()));
  }
};

}  // namespace

TEST_CASE("orientation_sign is CGAL's sign on the dual points of parallel face pairs",
          "[vertices][hull]") {
  std::mt19937_64 rng(29);
  std::lognormal_distribution<double> dist(0, 2);  // face distances over many magnitudes
  std::uniform_real_distribution<double> u01(0, 1);
  Checker check;
  const int n = test::scaled_cases(5000);
  for (int i = 0; i < n; ++i) {
    CAPTURE(i);
    // Fixed set orientations (dip / dip direction as in table3-lognormal) or random ones.
    const bool fixed = i % 2 == 0;
    const Vec3 n1 = fixed ? Vec3(0.1176, -0.0735, 0.9903).normalized() : unit(rng);
    const Vec3 n2 = fixed ? Vec3(0.9131, -0.3689, 0.1736).normalized() : unit(rng);
    const Vec3 n3 = fixed ? Vec3(0.1558, 0.9839, 0.0872).normalized() : unit(rng);
    // About a centre that is not the origin now and then, as block_geometry computes them.
    const Vec3 c =
        i % 5 == 0 ? Vec3(Vec3(u01(rng), u01(rng), u01(rng)) * 0.01) : Vec3(Vec3::Zero());
    const auto dual = [&](const Vec3& m, double d) { return Vec3(m / (d - m.dot(c))); };
    const double d[6] = {dist(rng), dist(rng), dist(rng), dist(rng), dist(rng), dist(rng)};
    const Vec3 a = dual(n1, d[0]), a2 = dual(-n1, d[1]), b = dual(n2, d[2]), b2 = dual(-n2, d[3]),
               e = dual(n3, d[4]), e2 = dual(-n3, d[5]);
    check(a, a2, b, b2);  // two pairs: in a plane through the origin but for rounding
    check(a, a2, b, e);   // one pair and two others
    check(a, a2, e, e2);
    check(a, b, e, e2);
    check(a2, b2, e2, Vec3::Zero());  // the origin, as the bounded test uses it
    check(a, a2, b, Vec3::Zero());
    // Faces as far from the centre: exactly antipodal dual points (slice-cut puts a block's
    // origin midway between parallel faces), with pairs that are and are not.
    const Vec3 ma = dual(-n1, d[0]), mb = dual(-n2, d[2]);
    check(a, ma, b, b2);
    check(a, ma, b, mb);
    check(a, b2, ma, e);
    check(b, a, mb, ma);
    check(a, ma, Vec3::Zero(), b);
  }
  CHECK(check.wrong == 0);
  CHECK(check.near > check.cases / 4);
}

TEST_CASE("orientation_sign is CGAL's sign on boxes, coplanar and collinear points",
          "[vertices][hull]") {
  std::mt19937_64 rng(2029);
  std::uniform_real_distribution<double> u01(0, 1);
  std::uniform_int_distribution<int> small(-4, 4);
  Checker check;
  const int n = test::scaled_cases(5000);
  for (int i = 0; i < n; ++i) {
    CAPTURE(i);
    // A box's dual points: exact zeros, four of them in each coordinate plane.
    const double lo[3] = {-1 - u01(rng), -1 - u01(rng), -1 - u01(rng)};
    const double hi[3] = {1 + u01(rng), 1 + u01(rng), 1 + u01(rng)};
    const Vec3 px(1 / hi[0], 0, 0), mx(1 / lo[0], 0, 0), py(0, 1 / hi[1], 0), my(0, 1 / lo[1], 0),
        pz(0, 0, 1 / hi[2]);
    check(px, mx, py, my);
    check(px, py, pz, mx);
    check(px, -px, py, -py);  // a box about its centre
    check(px, -px, py, pz);
    // A point rounded onto the plane of three others, and the same exactly (small integers).
    const Vec3 a = unit(rng), b = unit(rng), c = unit(rng);
    const double s = u01(rng) * 2 - 0.5, t = u01(rng) * 2 - 0.5;
    check(a, b, c, a + s * (b - a) + t * (c - a));
    const Vec3 ia(small(rng), small(rng), small(rng)), ib(small(rng), small(rng), small(rng)),
        ic(small(rng), small(rng), small(rng));
    check(ia, ib, ic, ia + small(rng) * (ib - ia) + small(rng) * (ic - ia));
    // Collinear and repeated points.
    check(a, b, a + s * (b - a), c);
    check(a, a, b, c);
  }
  CHECK(check.wrong == 0);
  CHECK(check.zeros > check.cases / 10);
  CHECK(check.near > check.cases / 3);
}

TEST_CASE("orientation_sign stays exact at every scale, and beyond the expansions' range",
          "[vertices][hull]") {
  std::mt19937_64 rng(4711);
  std::lognormal_distribution<double> dist(0, 1);
  std::uniform_int_distribution<int> exponent(-1000, 1000);
  Checker check;
  const int n = test::scaled_cases(5000);
  for (int i = 0; i < n; ++i) {
    CAPTURE(i);
    // Powers of two keep the rounding: the same nearly degenerate sets, scaled.
    const int k = i < n / 2 ? exponent(rng) / 4 : exponent(rng);
    const double f = std::ldexp(1.0, k);
    const Vec3 n1 = unit(rng), n2 = unit(rng);
    const Vec3 a = n1 / dist(rng) * f, a2 = -n1 / dist(rng) * f, b = n2 / dist(rng) * f,
               b2 = -n2 / dist(rng) * f;
    CAPTURE(k);
    check(a, a2, b, b2);
    check(a, -a, b, b2);
    // Mixed magnitudes: one coordinate far smaller than the others.
    const Vec3 c(a.x(), a.y(), a.z() * std::ldexp(1.0, -exponent(rng) / 2 - 500));
    check(c, a2, b, b2);
  }
  CHECK(check.wrong == 0);
  CHECK(check.near > check.cases / 4);
}

#include "slice/orientation.hpp"

#include <cmath>
#include <numbers>

namespace slice {
namespace {

// Reduces x degrees to x = 90 q + r with r in [-45, 45] and q in {0, 1, 2, 3}. Exact for
// arguments that are exact in binary (all integers), so the identities in the header hold.
void reduce(double deg, int& q, double& r) {
  double x = std::fmod(deg, 360.0);
  if (x < 0) x += 360.0;
  const double k = std::round(x / 90.0);
  r = x - 90.0 * k;
  q = int(k) % 4;
}

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// sin and cos of r in [-45, 45] degrees; at +-45 both are sqrt(1/2), so that the quadrant
// chosen for an argument of 45 + 90 k does not change the last bit.
double sin_r(double r) {
  if (std::abs(r) == 45.0) return std::copysign(std::numbers::sqrt2 / 2, r);
  return std::sin(r * kRadPerDeg);
}
double cos_r(double r) {
  if (std::abs(r) == 45.0) return std::numbers::sqrt2 / 2;
  return std::cos(r * kRadPerDeg);
}

}  // namespace

double sind(double deg) {
  int q = 0;
  double r = 0;
  reduce(deg, q, r);
  switch (q) {
    case 0:
      return sin_r(r);
    case 1:
      return cos_r(r);
    case 2:
      return -sin_r(r);
    default:
      return -cos_r(r);
  }
}

double cosd(double deg) {
  int q = 0;
  double r = 0;
  reduce(deg, q, r);
  switch (q) {
    case 0:
      return cos_r(r);
    case 1:
      return -sin_r(r);
    case 2:
      return -cos_r(r);
    default:
      return sin_r(r);
  }
}

Vec3 normal_from_dip(double dip_deg, double dip_direction_deg) {
  const double sd = sind(dip_deg);
  return {sd * sind(dip_direction_deg), sd * cosd(dip_direction_deg), cosd(dip_deg)};
}

DipAndDirection dip_from_normal(const Vec3& n_in) {
  Vec3 n = n_in.normalized();
  if (n.z() < 0) n = -n;  // the upward normal; a vertical plane keeps the normal it was given
  DipAndDirection r;
  const double h = std::hypot(n.x(), n.y());
  r.dip_deg = std::atan2(h, n.z()) / kRadPerDeg;
  if (h == 0) return r;  // horizontal: dip direction undefined, 0 by convention
  double a = std::atan2(n.x(), n.y()) / kRadPerDeg;  // clockwise from North
  if (a < 0) a += 360.0;
  if (a >= 360.0) a -= 360.0;
  r.dip_direction_deg = a;
  return r;
}

Vec3 strike_vector(double dip_direction_deg) {
  const double s = dip_direction_deg - 90.0;
  return {sind(s), cosd(s), 0.0};
}

Vec3 dip_vector(double dip_deg, double dip_direction_deg) {
  return strike_vector(dip_direction_deg).cross(normal_from_dip(dip_deg, dip_direction_deg));
}

JointFrame plane_frame(double dip_deg, double dip_direction_deg) {
  JointFrame f;
  f.n = normal_from_dip(dip_deg, dip_direction_deg);
  f.u = strike_vector(dip_direction_deg);
  f.v = f.n.cross(f.u);
  return f;
}

Vec3 priest_pole(double dip_deg, double dip_direction_deg) {
  const double a = 90.0 - dip_deg;
  const double b = dip_direction_deg - 180.0;
  return {cosd(b) * cosd(a), sind(b) * cosd(a), sind(a)};
}

Vec3 priest_to_global(const Vec3& p) { return {p.y(), p.x(), -p.z()}; }

}  // namespace slice

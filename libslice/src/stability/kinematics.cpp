// One body: Goodman & Shi's removability, the mode of motion under the resultant and its factor
// of safety by limit equilibrium (docs/stability.md, "One body").
#include <cmath>
#include <limits>

#include "slice/stability.hpp"

namespace slice {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Does translation along unit d leave or run along every plane but `skip_a` and `skip_b`?
bool admissible(std::span<const ContactPlane> planes, const Vec3& d, double tol, int skip_a = -1,
                int skip_b = -1) {
  for (std::size_t k = 0; k < planes.size(); ++k)
    if (int(k) != skip_a && int(k) != skip_b && planes[k].normal.dot(d) > tol) return false;
  return true;
}

/// tan(phi) of a plane: its contacts' area-weighted mean (0 for a plane of no area).
double tan_phi(const ContactPlane& p) { return p.area > 0 ? p.friction / p.area : 0; }

/// The tension of the planes the motion d leaves, resolved against d (N).
double tension_against(std::span<const ContactPlane> planes, const Vec3& d, double tol) {
  double sum = 0;
  for (const ContactPlane& p : planes) {
    const double c = p.normal.dot(d);
    if (c < -tol) sum += p.tension * -c;
  }
  return sum;
}

/// Goodman & Shi: the cone of directions d with n . d <= 0 for every plane is more than {0}.
/// If it is, some extreme ray of it lies on two of its planes (n_i x n_j), or all the normals
/// are parallel (any direction along them), or they span a plane only (its normal).
bool removable(std::span<const ContactPlane> planes, double tol) {
  if (planes.empty()) return true;
  const Vec3& n0 = planes[0].normal;
  bool parallel = true;
  for (const ContactPlane& p : planes) parallel = parallel && p.normal.cross(n0).norm() <= tol;
  if (parallel) return true;
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (std::size_t j = i + 1; j < planes.size(); ++j) {
      const Vec3 c = planes[i].normal.cross(planes[j].normal);
      const double len = c.norm();
      if (len <= tol) continue;
      const Vec3 d = c / len;
      if (admissible(planes, d, tol) || admissible(planes, -d, tol)) return true;
    }
  return false;
}

}  // namespace

const char* to_string(FailureMode m) {
  switch (m) {
    case FailureMode::not_exposed:
      return "not exposed";
    case FailureMode::not_removable:
      return "not removable";
    case FailureMode::stable:
      return "stable";
    case FailureMode::falls:
      return "falls";
    case FailureMode::slides_one:
      return "slides on one plane";
    case FailureMode::slides_two:
      return "slides on two planes";
  }
  return "?";
}

BodyStability analyse_body(std::span<const ContactPlane> planes, const Vec3& resultant,
                           double angle_tol) {
  const double tol = angle_tol;
  BodyStability out;
  out.removable = removable(planes, tol);
  if (!out.removable) {
    out.mode = FailureMode::not_removable;
    return out;
  }
  const double R = resultant.norm();
  if (!(R > 0)) return out;      // nothing drives it: stable
  const Vec3 r = resultant / R;  // forces below in units of R
  // Falling or lifting: the resultant itself leaves every plane.
  if (admissible(planes, r, tol)) {
    out.mode = FailureMode::falls;
    out.direction = r;
    out.fos = tension_against(planes, r, tol) / R;
    return out;
  }
  // Sliding on one plane, or on two: the modes the resultant can drive that leave (or run
  // along) every other plane, each with its factor of safety. For planes in general position
  // one at most is admissible (Goodman & Shi). Where three or more planes are parallel to one
  // line, several can be, and equilibrium alone cannot share the load among them (statically
  // indeterminate): the smallest factor of safety is the answer, the safe side.
  BodyStability best = out;
  bool found = false;
  const auto consider = [&](FailureMode mode, const Vec3& d, double resisting, double driving,
                            bool locked, int a, int b) {
    const double fos = locked ? kInf : resisting / driving;
    if (found && !(fos < best.fos)) return;
    found = true;
    best.mode = mode;
    best.direction = d;
    best.fos = fos;
    best.planes = {a, b};
  };
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const ContactPlane& p = planes[i];
    const double N = r.dot(p.normal);  // presses on the plane
    if (N <= tol) continue;
    const Vec3 s = r - N * p.normal;
    const double S = s.norm();
    if (S <= tol) continue;  // straight into the plane: no shear
    const Vec3 d = s / S;
    if (!admissible(planes, d, tol, int(i))) continue;
    const double resisting = N * R * tan_phi(p) + p.cohesion + tension_against(planes, d, tol);
    consider(FailureMode::slides_one, d, resisting, S * R, p.locked, int(i), -1);
  }
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (std::size_t j = i + 1; j < planes.size(); ++j) {
      const ContactPlane &p = planes[i], &q = planes[j];
      const Vec3 c = p.normal.cross(q.normal);
      const double len = c.norm();
      if (len <= tol) continue;
      Vec3 d = c / len;
      double along = r.dot(d);
      if (std::abs(along) <= tol) continue;
      if (along < 0) d = -d, along = -along;
      // The rest of r presses on both planes: r - (r . d) d = N_p n_p + N_q n_q, N >= 0.
      const double cos_pq = p.normal.dot(q.normal), det = len * len;  // 1 - cos^2
      const double rp = r.dot(p.normal), rq = r.dot(q.normal);
      const double Np = (rp - cos_pq * rq) / det, Nq = (rq - cos_pq * rp) / det;
      if (Np <= tol || Nq <= tol) continue;
      if (!admissible(planes, d, tol, int(i), int(j))) continue;
      const double resisting = R * (Np * tan_phi(p) + Nq * tan_phi(q)) + p.cohesion + q.cohesion +
                               tension_against(planes, d, tol);
      consider(FailureMode::slides_two, d, resisting, along * R, p.locked || q.locked, int(i),
               int(j));
    }
  if (!found || std::isinf(best.fos)) return out;  // nothing can move (or only on locked planes)
  best.removable = true;
  return best;
}

}  // namespace slice

#include "slice/polytope.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace slice {
namespace {

// A direction counts as a ray of the region when no plane faces it by more than this
// (dimensionless: normals and directions are unit vectors).
constexpr double kRayCos = 1e-12;
// Three planes meet in one point when their normals' determinant exceeds this.
constexpr double kMinDet = 1e-12;

bool has_ray(std::span<const Plane> planes) {
  for (std::size_t i = 0; i < planes.size(); ++i) {
    for (std::size_t j = i + 1; j < planes.size(); ++j) {
      Vec3 r = planes[i].normal.cross(planes[j].normal);
      if (r.norm() < kMinDet) continue;
      r.normalize();
      for (const double sign : {1.0, -1.0}) {
        const bool ray = std::all_of(planes.begin(), planes.end(), [&](const Plane& p) {
          return sign * p.normal.dot(r) <= kRayCos;
        });
        if (ray) return true;
      }
    }
  }
  return false;
}

// Whether the line where planes a and b meet passes within a slack of every plane: if not, no
// vertex lies on it, and the triples (a, b, *) need not be solved. The slack, far above `tol`
// and the rounding of the line and of a vertex solved from three planes, keeps every vertex that
// the triple loop alone would find; the test makes analyse_polytope O(n^2) line clips plus
// O(n) triples per edge instead of O(n^3) triples (a domain of 400 planes: 4.8 s -> ms).
bool line_meets_region(const Plane& a, const Plane& b, std::span<const Plane> planes, double tol) {
  Vec3 dir = a.normal.cross(b.normal);
  const double len2 = dir.squaredNorm();
  if (len2 < kMinDet * kMinDet) return true;  // parallel: every triple is skipped anyway
  // The point of the line nearest the origin, then a unit direction.
  const Vec3 x0 = (a.d * b.normal.cross(dir) + b.d * dir.cross(a.normal)) / len2;
  dir /= std::sqrt(len2);
  const double slack = 1e3 * tol + 1e-10 * x0.norm();
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  for (const Plane& p : planes) {
    const double slope = p.normal.dot(dir);  // p.distance(x0 + t dir) = p.distance(x0) + slope t
    const double room = slack - p.distance(x0);  // slope * t <= room
    if (slope == 0) {
      if (room < 0) return false;
    } else if (slope > 0) {
      hi = std::min(hi, room / slope);
    } else {
      lo = std::max(lo, room / slope);
    }
    if (lo > hi) return false;
  }
  return true;
}

int normal_rank(std::span<const Plane> planes) {
  Eigen::Matrix<double, Eigen::Dynamic, 3> n(planes.size(), 3);
  for (std::size_t i = 0; i < planes.size(); ++i) n.row(Eigen::Index(i)) = planes[i].normal;
  Eigen::FullPivLU<Eigen::Matrix<double, Eigen::Dynamic, 3>> lu(n);
  lu.setThreshold(kMinDet);
  return int(lu.rank());
}

}  // namespace

std::vector<Plane> box_planes(const Vec3& min, const Vec3& max) {
  std::vector<Plane> p;
  for (int axis = 0; axis < 3; ++axis) {
    p.push_back({-Vec3::Unit(axis), -min[axis]});
    p.push_back({Vec3::Unit(axis), max[axis]});
  }
  return p;
}

PolytopeInfo analyse_polytope(std::span<const Plane> planes, double tol) {
  PolytopeInfo info;
  if (planes.size() < 4 || normal_rank(planes) < 3 || has_ray(planes)) return info;
  info.bounded = true;

  const std::size_t n = planes.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (!line_meets_region(planes[i], planes[j], planes, tol)) continue;
      for (std::size_t k = j + 1; k < n; ++k) {
        Eigen::Matrix3d a;
        a.row(0) = planes[i].normal;
        a.row(1) = planes[j].normal;
        a.row(2) = planes[k].normal;
        if (std::abs(a.determinant()) < kMinDet) continue;
        const Vec3 x = a.partialPivLu().solve(Vec3(planes[i].d, planes[j].d, planes[k].d));
        const bool inside = std::all_of(planes.begin(), planes.end(),
                                        [&](const Plane& p) { return p.distance(x) <= tol; });
        if (!inside) continue;
        const bool known = std::any_of(info.vertices.begin(), info.vertices.end(),
                                       [&](const Vec3& v) { return (v - x).norm() <= tol; });
        if (!known) info.vertices.push_back(x);
      }
    }
  }
  if (info.vertices.empty()) return info;

  info.min = info.max = info.vertices.front();
  Vec3 sum = Vec3::Zero();
  for (const Vec3& v : info.vertices) {
    info.min = info.min.cwiseMin(v);
    info.max = info.max.cwiseMax(v);
    sum += v;
  }
  const Vec3 c = sum / double(info.vertices.size());
  info.interior_point = c;
  info.has_interior = info.vertices.size() >= 4 &&
                      std::all_of(planes.begin(), planes.end(),
                                  [&](const Plane& p) { return p.distance(c) < -tol; });
  if (!info.has_interior) return info;

  // Volume: a pyramid from c over every face, V = sum A_f h_f / 3.
  for (const Plane& p : planes) {
    std::vector<Vec3> face;
    for (const Vec3& v : info.vertices)
      if (std::abs(p.distance(v)) <= tol) face.push_back(v);
    if (face.size() < 3) continue;
    Vec3 fc = Vec3::Zero();
    for (const Vec3& v : face) fc += v;
    fc /= double(face.size());
    const Vec3 u = (face.front() - fc).normalized();
    const Vec3 w = p.normal.cross(u);
    std::sort(face.begin(), face.end(), [&](const Vec3& a, const Vec3& b) {
      return std::atan2(w.dot(a - fc), u.dot(a - fc)) < std::atan2(w.dot(b - fc), u.dot(b - fc));
    });
    double area = 0;
    for (std::size_t i = 0; i < face.size(); ++i)
      area += p.normal.dot((face[i] - fc).cross(face[(i + 1) % face.size()] - fc)) / 2;
    info.volume += area * -p.distance(c) / 3;
  }
  return info;
}

std::string precision_problem(const Vec3& lo, const Vec3& hi, double tol, const std::string& what) {
  const double m = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
  const double step = m * std::numeric_limits<double>::epsilon();
  if (tol >= step) return {};
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "%s reaches %.3g from the origin, where doubles step by %.3g, coarser than "
                "the tolerance %.3g (tolerance x the domain's bounding radius)",
                what.c_str(), m, step, tol);
  return buf;
}

Vec3 newell_normal(const std::vector<Vec3>& polygon) {
  // About the first corner (the same sum for a closed loop): far from the origin the corners'
  // own cross products would swamp it with rounding.
  Vec3 s = Vec3::Zero();
  if (polygon.empty()) return s;
  const Vec3& o = polygon[0];
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
    s += (polygon[k] - o).cross(polygon[k + 1] - o);
  return s;
}

std::pair<double, Vec3> polygon_area_centroid(const std::vector<Vec3>& p) {
  if (p.size() < 3) return {0, p.empty() ? Vec3::Zero() : p[0]};
  // Relative to the first corner: at 1e6 m from the origin the cross products of the corners
  // themselves (1e12) would leave 1e-4 m2 of rounding in a face of a few m2.
  const Vec3 n = newell_normal(p);
  const double twice = n.norm();
  if (!(twice > 0)) return {0, p[0]};
  const Vec3 u = n / twice;
  Vec3 sum = Vec3::Zero();
  double w = 0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    const Vec3 a = p[i] - p[0], b = p[i + 1] - p[0];
    const double t = a.cross(b).dot(u);
    sum += t * (a + b) / 3;
    w += t;
  }
  return {twice / 2, w != 0 ? Vec3(p[0] + sum / w) : p[0]};
}

std::vector<Vec3> clip_polygon(const std::vector<Vec3>& polygon, const Plane& h) {
  std::vector<Vec3> out;
  clip_polygon(polygon, h, out);
  return out;
}

void clip_polygon(const std::vector<Vec3>& polygon, const Plane& h, std::vector<Vec3>& out) {
  out.clear();
  const std::size_t n = polygon.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& a = polygon[k];
    const Vec3& b = polygon[(k + 1) % n];
    const double da = h.distance(a), db = h.distance(b);
    if (da <= 0) out.push_back(a);
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
}

}  // namespace slice

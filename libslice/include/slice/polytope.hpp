#pragma once
// Small exact-enough polytope helpers for regions given by a few half-spaces (domains, zones):
// vertex enumeration by plane triples. O(n^4); meant for tens of planes, not for blocks. Also
// the two polygon helpers the vertices and the exports share (no LP or CGAL behind them).
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "slice/geometry.hpp"

namespace slice {

struct PolytopeInfo {
  bool bounded = false;       // the recession cone is {0}
  bool has_interior = false;  // positive volume
  std::vector<Vec3> vertices;
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();  // bounding box of the vertices
  Vec3 interior_point = Vec3::Zero();           // mean of the vertices
  double volume = 0;
};

/// Analyses the region normal . x <= d of `planes` (unit normals). `tol` is an absolute length:
/// a point within tol of a plane is on it.
PolytopeInfo analyse_polytope(std::span<const Plane> planes, double tol);

/// Why doubles cannot resolve a region spanning [lo, hi] at the absolute tolerance `tol`, or
/// "" if they can: at coordinates up to M from the origin a double steps by up to M * 2^-52, so a
/// tolerance below that step is meaningless (a 50 m box at 1e12 m steps by 2.4e-4 m, far above
/// its cut tolerance of 4.3e-8 m; joint planes closer than a step cannot even be told apart).
/// `what` names the region in the reason ("the domain", "the tunnel").
std::string precision_problem(const Vec3& lo, const Vec3& hi, double tol,
                              const std::string& what = "the domain");

/// Six planes of the box [min, max], outward normals, in the order -x +x -y +y -z +z.
std::vector<Plane> box_planes(const Vec3& min, const Vec3& max);

/// Newell's vector of a polygon: its normal times twice its area (right-handed about the loop).
Vec3 newell_normal(const std::vector<Vec3>& polygon);

/// Area and centroid of a planar polygon (a fan of triangles from its first corner); a polygon
/// of no area has area 0 and its first corner (or the origin) as centroid.
std::pair<double, Vec3> polygon_area_centroid(const std::vector<Vec3>& polygon);

/// The convex polygon `polygon` clipped by the half-space `h` (normal . x <= d); vertices in
/// order. Sutherland-Hodgman; points on the plane are kept.
std::vector<Vec3> clip_polygon(const std::vector<Vec3>& polygon, const Plane& h);
/// The same into `out` (cleared first; not `polygon` itself), reusing its memory.
void clip_polygon(const std::vector<Vec3>& polygon, const Plane& h, std::vector<Vec3>& out);

}  // namespace slice

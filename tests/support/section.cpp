#include "support/section.hpp"

#include <cmath>
#include <stdexcept>

#include "slice/orientation.hpp"

namespace test {

using slice::Vec3;

namespace {

// A face of a polygon being cut: the global half-plane and the joint that made it.
struct EdgeFace {
  slice::Plane plane;
  std::int64_t joint = -1;
};

// A convex polygon whose edge k starts at points[k] and lies on faces[k].
struct Piece {
  std::vector<Vec3> points;
  std::vector<EdgeFace> faces;
};

// Sutherland-Hodgman keeping each edge's face: the piece on the side n . x <= d of `cut`.
Piece clip(const Piece& p, const EdgeFace& cut) {
  Piece out;
  const std::size_t n = p.points.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& a = p.points[k];
    const Vec3& b = p.points[(k + 1) % n];
    const double da = cut.plane.distance(a), db = cut.plane.distance(b);
    if (da <= 0) {
      out.points.push_back(a);
      out.faces.push_back(p.faces[k]);
    }
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
      out.points.push_back(a + (b - a) * (da / (da - db)));
      // Leaving the half-plane, the new point starts the cut edge; entering, the rest of a b.
      out.faces.push_back(da < 0 ? cut : p.faces[k]);
    }
  }
  return out;
}

double shortest_edge(const Piece& p) {
  double m = INFINITY;
  for (std::size_t k = 0; k < p.points.size(); ++k)
    m = std::min(m, (p.points[(k + 1) % p.points.size()] - p.points[k]).norm());
  return m;
}

}  // namespace

double uniform(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return double(z >> 11) * 0x1.0p-53;
}

double twice_area_xz(const std::vector<Vec3>& polygon) {
  double a = 0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Vec3& p = polygon[k];
    const Vec3& q = polygon[(k + 1) % polygon.size()];
    a += p.x() * q.z() - q.x() * p.z();
  }
  return a;
}

slice::Joint section_joint(double angle_deg, const Vec3& point) {
  Vec3 n(slice::cosd(angle_deg), 0, slice::sind(angle_deg));
  if (n.z() < 0 || (n.z() == 0 && n.x() < 0)) n = -n;
  slice::Joint j;
  const auto dd = slice::dip_from_normal(n);
  j.dip_deg = dd.dip_deg;
  j.dip_direction_deg = dd.dip_direction_deg;
  j.plane = {n, n.dot(point)};
  j.centre = point;
  return j;
}

slice::Joint segment_joint(slice::Joint j, const Vec3& a, const Vec3& b) {
  const slice::JointFrame f = slice::plane_frame(j.dip_deg, j.dip_direction_deg);
  j.centre = (a + b) / 2;
  // In the plane's frame u runs along strike (y here) and v along the section's line.
  const double va = f.v.dot(a - j.centre), vb = f.v.dot(b - j.centre);
  const double lo = std::min(va, vb), hi = std::max(va, vb);
  j.polygon_uv = {{-0.5, lo}, {0.5, lo}, {0.5, hi}, {-0.5, hi}};
  return j;
}

slice::JointSystem section_system(const Vec3& lo, const Vec3& hi,
                                  const std::vector<slice::Joint>& joints) {
  slice::JointSystem js;
  js.name = "section";
  js.dimension = 2;
  js.domain.planes = {{-Vec3::UnitX(), -lo.x()},
                      {Vec3::UnitX(), hi.x()},
                      {-Vec3::UnitZ(), -lo.z()},
                      {Vec3::UnitZ(), hi.z()}};
  js.length_scale = Vec3(hi.x() - lo.x(), 0, hi.z() - lo.z()).norm() / 2;
  js.options.tolerance = 1e-9;
  js.joints = joints;
  return js;
}

Section cut_section(const slice::JointSystem& js, double min_edge) {
  // The domain: a square far larger than it, clipped by its planes.
  double big = 0;
  for (const auto& p : js.domain.planes) big = std::max(big, std::abs(p.d));
  big = 4 * big + 1;
  Piece dom;
  dom.points = {{-big, 0, -big}, {big, 0, -big}, {big, 0, big}, {-big, 0, big}};
  dom.faces.assign(4, {{Vec3::UnitZ(), 2 * big}, -2});  // placeholders, clipped away
  for (const auto& p : js.domain.planes) dom = clip(dom, {p, -1});
  for (const auto& f : dom.faces)
    if (f.joint == -2) throw std::logic_error("cut_section: the domain is unbounded");

  std::vector<Piece> pieces{dom};
  for (std::size_t j = 0; j < js.joints.size(); ++j) {
    const slice::Plane& pl = js.joints[j].plane;
    const EdgeFace below{pl, std::int64_t(j)};
    const EdgeFace above{{-pl.normal, -pl.d}, std::int64_t(j)};
    std::vector<Piece> next;
    for (const Piece& p : pieces) {
      bool neg = false, pos = false, near = false;
      for (const Vec3& x : p.points) {
        const double s = pl.distance(x);
        neg |= s < 0;
        pos |= s > 0;
        near |= std::abs(s) < min_edge;
      }
      if (neg && pos && !near) {
        Piece a = clip(p, below), b = clip(p, above);
        if (shortest_edge(a) >= min_edge && shortest_edge(b) >= min_edge) {
          next.push_back(std::move(a));
          next.push_back(std::move(b));
          continue;
        }
      }
      next.push_back(p);
    }
    pieces = std::move(next);
  }

  Section s;
  s.bs.joints = js;
  s.bs.pruned = true;
  for (const Piece& p : pieces) {
    slice::Block b;
    for (const Vec3& x : p.points) b.origin += x;
    b.origin /= double(p.points.size());
    for (const EdgeFace& f : p.faces) {
      const slice::Plane l = slice::to_local(f.plane, b.origin);
      b.faces.push_back({l.normal, l.d, f.joint});
    }
    s.bs.blocks.push_back(std::move(b));
    s.polygons.push_back(p.points);
  }
  return s;
}

}  // namespace test

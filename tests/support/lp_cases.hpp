#pragma once
// Random LP cases for the LP property tests and slice-bench-lp (header-only, so the benchmark
// tool can include it without linking the test support library). Deterministic: std::mt19937_64
// with fixed seeds and our own uniform/normal transforms (the standard distributions differ
// between standard libraries).
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/lp.hpp"

namespace test::lp {

using slice::Face;
using slice::Plane;
using slice::Vec3;

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}
  /// Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(g_() >> 11) * 0x1.0p-53; }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  /// 10^uniform(lo, hi).
  double log_uniform(double lo_exp, double hi_exp) {
    return std::pow(10.0, uniform(lo_exp, hi_exp));
  }
  int index(int n) { return static_cast<int>(g_() % static_cast<std::uint64_t>(n)); }
  bool chance(double p) { return uniform() < p; }
  /// A uniformly distributed unit vector (rejection from the cube).
  Vec3 unit_vector() {
    for (;;) {
      const Vec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      const double n2 = v.squaredNorm();
      if (n2 > 1e-4 && n2 <= 1) return v / std::sqrt(n2);
    }
  }
  /// A unit vector perpendicular to the unit vector n.
  Vec3 perpendicular(const Vec3& n) {
    for (;;) {
      const Vec3 v = unit_vector();
      const Vec3 p = v - v.dot(n) * n;
      if (p.squaredNorm() > 1e-4) return p.normalized();
    }
  }

 private:
  std::mt19937_64 g_;
};

/// A vertex of a block and the faces through it (at least 3).
struct Vertex {
  Vec3 x;
  std::vector<int> faces;
};

/// A random convex block: planes tangent to a sphere (centre, radius), relative to the block
/// origin 0. The first four normals are a jittered, randomly rotated regular tetrahedron's, so
/// the block is bounded; the rest are random. Some faces may be redundant.
struct RandomBlock {
  std::vector<Face> faces;
  Vec3 centre = Vec3::Zero();
  double radius = 1;
  std::vector<Vertex> vertices;  // empty unless enumerated
};

inline RandomBlock random_block(Rng& rng, int n_faces, double scale, bool degenerate = false) {
  RandomBlock b;
  b.centre = Vec3(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)) * scale;
  b.radius = scale * rng.uniform(0.2, 1.0);
  const Eigen::Quaterniond q(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1),
                             rng.uniform(-1, 1));
  const Eigen::Matrix3d rot = q.normalized().toRotationMatrix();
  const double s = 1 / std::sqrt(3.0);
  const std::array<Vec3, 4> tetra = {Vec3(s, s, s), Vec3(s, -s, -s), Vec3(-s, s, -s),
                                     Vec3(-s, -s, s)};
  auto add = [&](const Vec3& n) { b.faces.push_back({n, n.dot(b.centre) + b.radius}); };
  for (int i = 0; i < n_faces; ++i) {
    Vec3 n =
        i < 4 ? Vec3(rot * tetra[i] + 0.2 * rng.uniform() * rng.unit_vector()) : rng.unit_vector();
    add(n.normalized());
  }
  if (degenerate && n_faces >= 5) {
    // Rows the LP must survive: an exact duplicate and a parallel face barely outside another.
    const Face dup = b.faces[static_cast<std::size_t>(rng.index(n_faces))];
    b.faces.push_back(dup);
    const Face par = b.faces[static_cast<std::size_t>(rng.index(n_faces))];
    b.faces.push_back({par.normal, par.d + scale * rng.log_uniform(-13, -6)});
  }
  return b;
}

/// All vertices of the block by brute force over face triples (small blocks only).
inline void enumerate_vertices(RandomBlock& b, double scale) {
  const int n = static_cast<int>(b.faces.size());
  const double on = 1e-9 * scale;  // generator-side tolerance: vertices for picking planes only
  b.vertices.clear();
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        Eigen::Matrix3d m;
        m.row(0) = b.faces[i].normal.transpose();
        m.row(1) = b.faces[j].normal.transpose();
        m.row(2) = b.faces[k].normal.transpose();
        if (std::abs(m.determinant()) < 1e-6) continue;
        const Vec3 x = m.partialPivLu().solve(Vec3(b.faces[i].d, b.faces[j].d, b.faces[k].d));
        bool inside = true;
        for (const Face& f : b.faces) inside = inside && f.normal.dot(x) - f.d <= on;
        if (!inside) continue;
        bool known = false;
        for (const Vertex& v : b.vertices) known = known || (v.x - x).norm() <= on;
        if (known) continue;
        Vertex v{x, {}};
        for (int f = 0; f < n; ++f)
          if (std::abs(b.faces[f].normal.dot(x) - b.faces[f].d) <= on) v.faces.push_back(f);
        b.vertices.push_back(v);
      }
}

/// The same directions answered, by the same bits (the others' x is undefined).
inline bool same_bits(const slice::VertexExtremes& a, const slice::VertexExtremes& b) {
  if (a.found != b.found) return false;
  for (int dir = 0; dir < 6; ++dir)
    if ((a.found & (1u << dir)) &&
        std::memcmp(&a.x[std::size_t(dir)], &b.x[std::size_t(dir)], sizeof(Vec3)) != 0)
      return false;
  return true;
}

enum class PlaneKind { interior, vertex, edge, face, near_face, near_touch, miss };
inline const char* to_string(PlaneKind k) {
  constexpr const char* names[] = {"interior",  "vertex",     "edge", "face",
                                   "near_face", "near_touch", "miss"};
  return names[static_cast<int>(k)];
}

/// A plane of the given kind relative to the block (vertices enumerated, except for interior and
/// miss, which only use the tangent sphere).
inline Plane random_plane(Rng& rng, const RandomBlock& b, PlaneKind kind, double scale) {
  auto through = [](const Vec3& n, const Vec3& p) { return Plane{n, n.dot(p)}; };
  const auto& vs = b.vertices;
  switch (kind) {
    case PlaneKind::interior: {
      const Vec3 p = b.centre + b.radius * rng.uniform(0, 0.95) * rng.unit_vector();
      return through(rng.unit_vector(), p);
    }
    case PlaneKind::vertex:
      return through(rng.unit_vector(),
                     vs[static_cast<std::size_t>(rng.index(static_cast<int>(vs.size())))].x);
    case PlaneKind::edge: {
      // Two vertices sharing two faces span an edge; try a few random pairs, else a vertex.
      for (int attempt = 0; attempt < 50; ++attempt) {
        const auto& a = vs[static_cast<std::size_t>(rng.index(static_cast<int>(vs.size())))];
        const auto& c = vs[static_cast<std::size_t>(rng.index(static_cast<int>(vs.size())))];
        int shared = 0;
        for (int f : a.faces)
          for (int g : c.faces) shared += f == g;
        if (&a == &c || shared < 2) continue;
        const Vec3 dir = (c.x - a.x).normalized();
        return through(rng.perpendicular(dir), a.x);
      }
      return through(rng.unit_vector(), vs.front().x);
    }
    case PlaneKind::face:
    case PlaneKind::near_face: {
      const auto& v = vs[static_cast<std::size_t>(rng.index(static_cast<int>(vs.size())))];
      const Face& f = b.faces[static_cast<std::size_t>(
          v.faces[static_cast<std::size_t>(rng.index(static_cast<int>(v.faces.size())))])];
      const double sign = rng.chance(0.5) ? 1 : -1;
      if (kind == PlaneKind::face) return {sign * f.normal, sign * f.d};
      // Tilt the face's plane by a tiny angle about an in-plane axis through the vertex.
      const double angle = rng.log_uniform(-12, -3);
      const Vec3 axis = rng.perpendicular(f.normal);
      const Vec3 n = Eigen::AngleAxisd(angle, axis) * f.normal;
      return through(sign * n.normalized(), v.x);
    }
    case PlaneKind::near_touch: {
      // A supporting plane moved by +-delta, delta around the cut tolerance (1e-9 L) and beyond.
      const Vec3 n = rng.unit_vector();
      double h = -1e300;
      for (const Vertex& v : vs) h = std::max(h, n.dot(v.x));
      const double delta = scale * rng.log_uniform(-13, -5) * (rng.chance(0.5) ? 1 : -1);
      return {n, h - delta};
    }
    case PlaneKind::miss: {
      const Vec3 n = rng.unit_vector();
      return {n, n.dot(b.centre) + b.radius * rng.uniform(2, 20)};
    }
  }
  return {};
}

/// A convex polygon in `plane`, as unit in-plane edge half-planes n_k . x <= e_k: a regular
/// k-gon (3..8 sides) with random rotation, size and centre (near the block or off it).
inline std::vector<Plane> random_polygon(Rng& rng, const RandomBlock& b, const Plane& plane) {
  const Vec3& n = plane.normal;
  const Vec3 u = rng.perpendicular(n);
  const Vec3 v = n.cross(u);
  const Vec3 foot = b.centre - (n.dot(b.centre) - plane.d) * n;  // block centre on the plane
  const Vec3 c = foot + b.radius * rng.uniform(0, 2.5) * rng.perpendicular(n);
  const double r = b.radius * rng.log_uniform(-1.5, 0.5);
  const int k = 3 + rng.index(6);
  const double phase = rng.uniform(0, 2 * std::numbers::pi);
  std::vector<Plane> edges;
  for (int i = 0; i < k; ++i) {
    const double phi = phase + 2 * std::numbers::pi * i / k;
    const Vec3 e = (std::cos(phi) * u + std::sin(phi) * v).normalized();
    edges.push_back({e, e.dot(c) + r * std::cos(std::numbers::pi / k)});
  }
  return edges;
}

/// The ways a case is presented to the LP: as made, at a 1e6 m offset (plane and polygon go
/// through global coordinates and back to the block frame), scaled by 1e-3 and by 1e3.
enum class Variant { base, offset, small, large };
inline const char* to_string(Variant v) {
  constexpr const char* names[] = {"base", "offset 1e6", "scale 1e-3", "scale 1e3"};
  return names[static_cast<int>(v)];
}
inline double variant_scale(Variant v) {
  return v == Variant::small ? 1e-3 : v == Variant::large ? 1e3 : 1.0;
}

inline constexpr Variant kVariants[] = {Variant::base, Variant::offset, Variant::small,
                                        Variant::large};
inline constexpr PlaneKind kKinds[] = {
    PlaneKind::interior,  PlaneKind::vertex,     PlaneKind::edge, PlaneKind::face,
    PlaneKind::near_face, PlaneKind::near_touch, PlaneKind::miss};

/// A seed for case i of a run seeded with `seed` (the cases' streams do not overlap).
inline std::uint64_t mix(std::uint64_t seed, std::uint64_t i) {
  return seed ^ (i * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull);
}

/// The block origin used for the offset variant (UTM-like coordinates).
inline const Vec3 kOffsetOrigin(512345.678, 5123456.789, 312.5);

inline std::vector<Face> scaled(std::vector<Face> faces, double s) {
  for (Face& f : faces) f.d *= s;
  return faces;
}
inline Plane present(const Plane& p, Variant v) {
  if (v == Variant::offset)
    return slice::to_local(slice::to_global(p, kOffsetOrigin), kOffsetOrigin);
  return {p.normal, p.d * variant_scale(v)};
}
inline std::vector<Plane> present(std::vector<Plane> ps, Variant v) {
  for (Plane& p : ps) p = present(p, v);
  return ps;
}

}  // namespace test::lp

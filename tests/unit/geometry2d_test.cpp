// slice/vertices.hpp in 2-D mode (docs/2d.md): a section's blocks are convex polygons in (x, z).
// Hand-checkable polygons (rectangle, rotated rectangle, right triangle), random tilings of a box
// made by plain polygon clipping (tests/support/section.hpp), offsets and units, segment
// joints' fractions, and the faces that have no edge.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/vertices.hpp"
#include "support/section.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;

namespace {

// A block of half-planes n . x <= d (global, n = (nx, 0, nz), any length), origin `o`.
slice::Block block_of(const std::vector<std::pair<Vec3, double>>& planes, const Vec3& o,
                      std::int64_t joint = -1) {
  slice::Block b;
  b.origin = o;
  for (const auto& [n, d] : planes) {
    const slice::Plane l = slice::to_local({n / n.norm(), d / n.norm()}, o);
    b.faces.push_back({l.normal, l.d, joint});
  }
  return b;
}

// The half-planes of a convex polygon given counter-clockwise in (x, z): one per edge.
std::vector<std::pair<Vec3, double>> edges_of(const std::vector<Vec3>& p) {
  std::vector<std::pair<Vec3, double>> e;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Vec3 t = p[(k + 1) % p.size()] - p[k];
    const Vec3 n = Vec3(t.z(), 0, -t.x()).normalized();  // outward: right of the edge
    e.push_back({n, n.dot(p[k])});
  }
  return e;
}

std::vector<Vec3> rectangle(const Vec3& c, double w, double h, double angle_deg) {
  const Vec3 u(slice::cosd(angle_deg), 0, slice::sind(angle_deg));
  const Vec3 v(-u.z(), 0, u.x());  // u turned counter-clockwise in (x, z)
  return {c - w / 2 * u - h / 2 * v, c + w / 2 * u - h / 2 * v, c + w / 2 * u + h / 2 * v,
          c - w / 2 * u + h / 2 * v};
}

slice::JointSystem section_js(double L) {
  slice::JointSystem js;
  js.dimension = 2;
  js.length_scale = L;
  js.options.tolerance = 1e-9;
  return js;
}

slice::Tolerances tol_of(const slice::JointSystem& js) {
  return slice::Tolerances::from_scale(js.length_scale, js.options.tolerance, 2);
}

// Every invariant of a polygon's geometry that does not depend on its shape.
void check_polygon(const slice::Block& b, const slice::BlockGeometry& g,
                   const slice::Tolerances& tol) {
  const std::size_t nv = g.vertices.size();
  REQUIRE(nv == b.faces.size());  // one face per edge, none redundant
  REQUIRE(g.loops.size() == b.faces.size());
  for (const Vec3& x : g.vertices) CHECK(x.y() == 0);
  // Counter-clockwise with x to the right and z up, and the area is the polygon's.
  CHECK(test::twice_area_xz(g.vertices) > 0);
  CHECK_THAT(test::twice_area_xz(g.vertices) / 2, WithinRel(g.volume, 1e-9));
  std::vector<int> starts(nv, 0);
  for (std::size_t f = 0; f < b.faces.size(); ++f) {
    CAPTURE(f);
    REQUIRE(g.loops[f].size() == 2);
    const auto s = std::size_t(g.loops[f][0]), e = std::size_t(g.loops[f][1]);
    REQUIRE(s < nv);
    REQUIRE(e < nv);
    CHECK(e == (s + 1) % nv);  // the edge runs forward along the polygon
    ++starts[s];
    const Vec3 a = g.vertices[s] - b.origin, c = g.vertices[e] - b.origin;
    CHECK(std::abs(b.faces[f].normal.dot(a) - b.faces[f].d) <= tol.geometry);
    CHECK(std::abs(b.faces[f].normal.dot(c) - b.faces[f].d) <= tol.geometry);
    CHECK_THAT(g.face_area[f], WithinRel((c - a).norm(), 1e-12));
    // The outward normal is on the right of the edge's direction (counter-clockwise polygon).
    const Vec3 t = (c - a).normalized();
    CHECK_THAT(b.faces[f].normal.dot(Vec3(t.z(), 0, -t.x())), WithinAbs(1, 1e-9));
  }
  for (int s : starts) CHECK(s == 1);  // every vertex starts exactly one edge
  for (const Vec3& x : g.vertices)
    for (const auto& f : b.faces) CHECK(f.normal.dot(x - b.origin) - f.d <= tol.geometry);
}

// Second moments about the centroid of a polygon from its vertices (the spec's formulas).
struct Moments {
  double area, izz_x2, ixx_z2, ixz;
};
Moments moments(const std::vector<Vec3>& p, const Vec3& centroid) {
  Moments m{0, 0, 0, 0};
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Vec3 a = p[k] - centroid, b = p[(k + 1) % p.size()] - centroid;
    const double c = a.x() * b.z() - b.x() * a.z();
    m.area += c / 2;
    m.izz_x2 += (a.x() * a.x() + a.x() * b.x() + b.x() * b.x()) * c / 12;
    m.ixx_z2 += (a.z() * a.z() + a.z() * b.z() + b.z() * b.z()) * c / 12;
    m.ixz += (a.x() * b.z() + 2 * a.x() * a.z() + 2 * b.x() * b.z() + b.x() * a.z()) * c / 24;
  }
  return m;
}

}  // namespace

TEST_CASE("2-D: a rectangle's area, centroid and second moments by hand", "[vertices][2d]") {
  // w x h: A = w h, about the centroid integral z^2 = A h^2 / 12, x^2 = A w^2 / 12, J = their sum,
  // no product. Also far from the global origin and with the origin off the centre.
  const double w = 3, h = 2, area = w * h;
  const auto js = section_js(10);
  const auto tol = tol_of(js);
  for (const Vec3& c : {Vec3(0, 0, 0), Vec3(5e5, 0, 300), Vec3(-1e6, 0, 1e6)}) {
    CAPTURE(c.transpose());
    const auto blk = block_of(edges_of(rectangle(c, w, h, 0)), c + Vec3(0.3, 0, -0.2));
    const auto g = slice::block_geometry(blk, js, tol);
    REQUIRE(g.vertices.size() == 4);
    check_polygon(blk, g, tol);
    CHECK_THAT(g.volume, WithinRel(area, 1e-12));
    CHECK_THAT((g.centroid - c).norm(), WithinAbs(0, 1e-9));
    CHECK(g.centroid.y() == 0);
    CHECK_THAT(g.inertia[0], WithinRel(area * h * h / 12, 1e-9));            // xx: z^2
    CHECK_THAT(g.inertia[2], WithinRel(area * w * w / 12, 1e-9));            // zz: x^2
    CHECK_THAT(g.inertia[1], WithinRel(area * (w * w + h * h) / 12, 1e-9));  // yy: J
    CHECK(g.inertia[3] == 0);
    CHECK(g.inertia[4] == 0);
    CHECK_THAT(g.inertia[5], WithinAbs(0, 1e-9));
    for (std::size_t f = 0; f < 4; ++f) {
      CHECK_THAT(g.face_area[f], WithinRel(f % 2 == 0 ? w : h, 1e-12));
      CHECK(g.face_joint_fraction[f] == 1);
    }
  }
}

TEST_CASE("2-D: a rotated rectangle's product of inertia has the 3-D sign", "[vertices][2d]") {
  // Turned by t: integral x^2 = cos^2 t Iu + sin^2 t Iv, z^2 = sin^2 t Iu + cos^2 t Iv,
  // integral x z = sin t cos t (Iu - Iv), Iu = A w^2 / 12, Iv = A h^2 / 12; stored zx = -x z,
  // as 3-D's mass_properties stores -integral z x dV.
  const double w = 4, h = 1, area = w * h, iu = area * w * w / 12, iv = area * h * h / 12;
  const auto js = section_js(10);
  const auto tol = tol_of(js);
  for (const double t : {30.0, 135.0, -60.0}) {
    CAPTURE(t);
    const Vec3 c(2, 0, 7);
    const auto blk = block_of(edges_of(rectangle(c, w, h, t)), c);
    const auto g = slice::block_geometry(blk, js, tol);
    check_polygon(blk, g, tol);
    const double s = slice::sind(t), co = slice::cosd(t);
    CHECK_THAT(g.volume, WithinRel(area, 1e-12));
    CHECK_THAT(g.inertia[2], WithinRel(co * co * iu + s * s * iv, 1e-9));
    CHECK_THAT(g.inertia[0], WithinRel(s * s * iu + co * co * iv, 1e-9));
    CHECK_THAT(g.inertia[1], WithinRel(iu + iv, 1e-9));
    CHECK_THAT(g.inertia[5], WithinRel(-s * co * (iu - iv), 1e-9));
    // A 3-D prism of unit thickness has the same product: the stored sign is 3-D's.
    const double prism_zx = [&] {
      std::vector<Vec3> v;
      for (const Vec3& x : g.vertices) v.push_back(x + Vec3(0, -0.5, 0));
      for (const Vec3& x : g.vertices) v.push_back(x + Vec3(0, 0.5, 0));
      const std::size_t n = g.vertices.size();
      std::vector<std::vector<std::int64_t>> loops(2);
      // Seen from outside: the bottom (y = -0.5, normal -y) runs as the polygon runs in (x, z)
      // (x cross z = -y); the top the other way; sides (k, k+1, top k+1, top k).
      for (std::size_t k = 0; k < n; ++k) loops[0].push_back(std::int64_t(k));
      for (std::size_t k = n; k-- > 0;) loops[1].push_back(std::int64_t(n + k));
      for (std::size_t k = 0; k < n; ++k)
        loops.push_back({std::int64_t((k + 1) % n), std::int64_t(k), std::int64_t(n + k),
                         std::int64_t(n + (k + 1) % n)});
      const auto mp = slice::mass_properties(v, loops, g.centroid);
      REQUIRE_THAT(mp.volume, WithinRel(area, 1e-12));
      return mp.inertia[5];
    }();
    CHECK_THAT(g.inertia[5], WithinRel(prism_zx, 1e-9));
  }
}

TEST_CASE("2-D: a right triangle by hand", "[vertices][2d]") {
  // Legs a along x and b along z from p: A = a b / 2, centroid p + (a, b) / 3; about it
  // integral z^2 = a b^3 / 36, x^2 = b a^3 / 36, x z = -a^2 b^2 / 72, so zx = +a^2 b^2 / 72.
  const double a = 3, b = 2;
  const Vec3 p(-4, 0, 9);
  const auto js = section_js(10);
  const auto tol = tol_of(js);
  const std::vector<Vec3> tri = {p, p + Vec3(a, 0, 0), p + Vec3(0, 0, b)};
  const auto blk = block_of(edges_of(tri), p + Vec3(0.5, 0, 0.5));
  const auto g = slice::block_geometry(blk, js, tol);
  REQUIRE(g.vertices.size() == 3);
  check_polygon(blk, g, tol);
  CHECK_THAT(g.volume, WithinRel(a * b / 2, 1e-12));
  CHECK_THAT((g.centroid - p - Vec3(a / 3, 0, b / 3)).norm(), WithinAbs(0, 1e-12));
  CHECK_THAT(g.inertia[0], WithinRel(a * b * b * b / 36, 1e-12));
  CHECK_THAT(g.inertia[2], WithinRel(b * a * a * a / 36, 1e-12));
  CHECK_THAT(g.inertia[1], WithinRel(a * b * (a * a + b * b) / 36, 1e-12));
  CHECK_THAT(g.inertia[5], WithinRel(a * a * b * b / 72, 1e-12));
  CHECK_THAT(g.face_area[1], WithinRel(std::hypot(a, b), 1e-12));  // the hypotenuse
  // The vertices are the triangle's, in its (counter-clockwise) order up to rotation.
  const auto first = std::find_if(g.vertices.begin(), g.vertices.end(),
                                  [&](const Vec3& x) { return (x - p).norm() < 1e-12; });
  REQUIRE(first != g.vertices.end());
  const auto k0 = std::size_t(first - g.vertices.begin());
  for (std::size_t k = 0; k < 3; ++k)
    CHECK_THAT((g.vertices[(k0 + k) % 3] - tri[k]).norm(), WithinAbs(0, 1e-12));
}

TEST_CASE("2-D: a block whose origin is outside it still gets its polygon", "[vertices][2d]") {
  // The dual hull needs an interior point: the Chebyshev LP finds one (with two faces y = +-L
  // closing the section for the 3-D LP).
  const auto js = section_js(10);
  const auto tol = tol_of(js);
  const auto blk = block_of(edges_of(rectangle(Vec3(1, 0, 1), 2, 2, 0)), Vec3(8, 0, -3));
  REQUIRE(std::any_of(blk.faces.begin(), blk.faces.end(), [](const auto& f) { return f.d < 0; }));
  const auto g = slice::block_geometry(blk, js, tol);
  check_polygon(blk, g, tol);
  CHECK_THAT(g.volume, WithinRel(4, 1e-12));
  CHECK_THAT((g.centroid - Vec3(1, 0, 1)).norm(), WithinAbs(0, 1e-12));
}

TEST_CASE("2-D: random tilings give back their polygons and the domain's area", "[vertices][2d]") {
  const auto seed = GENERATE(range(1u, 21u));
  CAPTURE(seed);
  std::uint64_t state = seed;
  const double W = 20, H = 10;
  std::vector<slice::Joint> joints;
  for (int k = 0; k < 12; ++k)
    joints.push_back(test::section_joint(
        360 * test::uniform(state), Vec3(W * test::uniform(state), 0, H * test::uniform(state))));
  const auto js = test::section_system(Vec3(0, 0, 0), Vec3(W, 0, H), joints);
  auto sec = test::cut_section(js, 1e-3 * W);
  REQUIRE(sec.bs.blocks.size() > 12);
  const auto tol = tol_of(js);
  double total = 0;
  for (std::size_t b = 0; b < sec.bs.blocks.size(); ++b) {
    CAPTURE(b);
    const auto& blk = sec.bs.blocks[b];
    const auto g = slice::block_geometry(blk, js, tol, b);
    check_polygon(blk, g, tol);
    total += g.volume;
    // The polygon it was cut as: the same points, and face k's edge starts at point k.
    const auto& poly = sec.polygons[b];
    CHECK_THAT(g.volume, WithinRel(test::twice_area_xz(poly) / 2, 1e-9));
    for (std::size_t f = 0; f < poly.size(); ++f)
      CHECK((g.vertices[std::size_t(g.loops[f][0])] - poly[f]).norm() <= 1e-9 * W);
    // Second moments against the vertex formulas (the spec's definitions).
    const auto m = moments(poly, g.centroid);
    CHECK_THAT(g.inertia[0], WithinRel(m.ixx_z2, 1e-8));
    CHECK_THAT(g.inertia[2], WithinRel(m.izz_x2, 1e-8));
    CHECK_THAT(g.inertia[5], WithinAbs(-m.ixz, 1e-8 * (m.ixx_z2 + m.izz_x2)));
  }
  CHECK_THAT(total, WithinRel(W * H, 1e-12));

  // compute_geometry: the same per block, in the file's CSR layout, on any thread count.
  for (const int threads : {1, 2}) {
    auto bs = sec.bs;
    const auto st = slice::compute_geometry(bs, {}, threads);
    REQUIRE(bs.geometry);
    const auto& g = *bs.geometry;
    CHECK(st.blocks == bs.blocks.size());
    REQUIRE(g.volume.size() == bs.blocks.size());
    double sum = 0;
    for (const double v : g.volume) sum += v;
    CHECK_THAT(sum, WithinRel(W * H, 1e-12));
    std::size_t face = 0;
    for (std::size_t b = 0; b < bs.blocks.size(); ++b)
      for (std::size_t f = 0; f < bs.blocks[b].faces.size(); ++f, ++face)
        CHECK(g.face_vertex_offset[face + 1] - g.face_vertex_offset[face] == 2);
    CHECK(g.face_vertex_offset.back() == std::int64_t(2 * face));
  }
}

TEST_CASE("2-D: results do not depend on a far offset or on the unit", "[vertices][2d]") {
  const auto seed = GENERATE(range(1u, 6u));
  CAPTURE(seed);
  std::uint64_t state = 100 + seed;
  std::vector<slice::Joint> joints;
  std::vector<std::pair<double, Vec3>> lines;
  for (int k = 0; k < 8; ++k)
    lines.push_back({360 * test::uniform(state),
                     Vec3(20 * test::uniform(state), 0, 10 * test::uniform(state))});
  // The same section at the origin, shifted by 1e6 m, and in mm (x 1e3).
  const auto make = [&](const Vec3& shift, double scale) {
    std::vector<slice::Joint> js;
    for (const auto& [a, p] : lines) js.push_back(test::section_joint(a, shift + scale * p));
    return test::cut_section(test::section_system(shift, shift + scale * Vec3(20, 0, 10), js),
                             1e-3 * 20 * scale);
  };
  const Vec3 shift(1e6, 0, -1e6);
  for (const auto& [off, scale] : {std::pair{shift, 1.0}, std::pair{Vec3(0, 0, 0), 1e3}}) {
    CAPTURE(off.transpose(), scale);
    auto a = make(Vec3::Zero(), 1), b = make(off, scale);
    REQUIRE(a.bs.blocks.size() == b.bs.blocks.size());
    slice::compute_geometry(a.bs);
    slice::compute_geometry(b.bs);
    const auto &ga = *a.bs.geometry, &gb = *b.bs.geometry;
    REQUIRE(ga.vertices.size() == gb.vertices.size());
    for (std::size_t i = 0; i < ga.volume.size(); ++i) {
      CAPTURE(i);
      // At 1e6 m a coordinate is only known to 1.2e-10 m (half an ulp), in the test's own
      // cut as much as in the geometry: an area moves by that times the perimeter (< 60 m).
      CHECK_THAT(gb.volume[i], WithinAbs(scale * scale * ga.volume[i], 1e-8 * scale * scale));
      CHECK((gb.centroid[i] - off - scale * ga.centroid[i]).norm() <= 1e-9 * scale * 20);
      const double s4 = scale * scale * scale * scale;
      const double big = s4 * (ga.inertia[i][0] + ga.inertia[i][2]);
      for (const std::size_t k : {0u, 1u, 2u, 5u})
        CHECK_THAT(gb.inertia[i][k], WithinAbs(s4 * ga.inertia[i][k], 1e-7 * big));
    }
    for (std::size_t v = 0; v < ga.vertices.size(); ++v)
      CHECK((gb.vertices[v] - off - scale * ga.vertices[v]).norm() <= 1e-9 * scale * 20);
    CHECK(ga.face_vertices == gb.face_vertices);
  }
}

TEST_CASE("2-D: face_joint_fraction is the part of the edge between the segment's ends",
          "[vertices][2d]") {
  // [0, 2] x [0, 1] cut by x = 1: each half's edge on x = 1 runs z in [0, 1]. A segment of the
  // joint's line from z = 0.5 to z = 3 covers half of it; from -1 to 5 all; from 2 to 3 none.
  const auto vertical = test::section_joint(0, Vec3(1, 0, 0));
  for (const auto& [z0, z1, want] : {std::tuple{0.5, 3.0, 0.5}, std::tuple{-1.0, 5.0, 1.0},
                                     std::tuple{2.0, 3.0, 0.0}, std::tuple{0.2, 0.3, 0.1}}) {
    CAPTURE(z0, z1);
    const auto seg = test::segment_joint(vertical, Vec3(1, 0, z0), Vec3(1, 0, z1));
    // The stored rectangle spans y in [-0.5, 0.5] (docs/2d.md).
    for (const Vec3& x : slice::joint_polygon(seg))
      CHECK_THAT(std::abs(x.y()), WithinAbs(0.5, 1e-15));
    const auto js = test::section_system(Vec3(0, 0, 0), Vec3(2, 0, 1), {seg});
    auto sec = test::cut_section(js, 1e-3);
    REQUIRE(sec.bs.blocks.size() == 2);
    slice::compute_geometry(sec.bs);
    const auto& g = *sec.bs.geometry;
    std::size_t face = 0, seen = 0;
    for (const auto& blk : sec.bs.blocks)
      for (const auto& f : blk.faces) {
        if (f.joint == 0) {
          CHECK_THAT(g.face_joint_fraction[face], WithinAbs(want, 1e-12));
          ++seen;
        } else {
          CHECK(g.face_joint_fraction[face] == 1);
        }
        ++face;
      }
    CHECK(seen == 2);
  }
}

TEST_CASE("2-D: faces without an edge are refused, naming the block and the face",
          "[vertices][2d]") {
  const auto js = section_js(10);
  const auto tol = tol_of(js);
  auto sq = edges_of(rectangle(Vec3(0, 0, 0), 2, 2, 0));
  SECTION("a redundant face (outside the polygon)") {
    sq.push_back({Vec3(1, 0, 1), 5});
    const auto msg =
        test::error_of([&] { slice::block_geometry(block_of(sq, Vec3::Zero()), js, tol, 7); });
    CHECK_THAT(msg, Contains("block 7") && Contains("face 4") && Contains("redundant"));
  }
  SECTION("a face through a corner (touches in a point)") {
    sq.push_back({Vec3(1, 0, 1), 2});  // x + z = 2 passes through (1, 1)
    const auto msg =
        test::error_of([&] { slice::block_geometry(block_of(sq, Vec3::Zero()), js, tol); });
    CHECK_THAT(msg, Contains("face 4") && (Contains("redundant") || Contains("no length")));
  }
  SECTION("a face cutting a corner off by less than the tolerance") {
    sq.push_back({Vec3(1, 0, 1), 2 - 1e-12});
    const auto msg =
        test::error_of([&] { slice::block_geometry(block_of(sq, Vec3::Zero()), js, tol); });
    CHECK_THAT(msg, Contains("face 4") && Contains("no length"));
  }
  SECTION("a face normal to y") {
    auto b = block_of(sq, Vec3::Zero());
    b.faces.push_back({Vec3::UnitY(), 1, -1});
    const auto msg = test::error_of([&] { slice::block_geometry(b, js, tol); });
    CHECK_THAT(msg, Contains("face 4") && Contains("y component"));
  }
  SECTION("two faces") {
    sq.resize(2);
    const auto msg =
        test::error_of([&] { slice::block_geometry(block_of(sq, Vec3::Zero()), js, tol); });
    CHECK_THAT(msg, Contains("2 faces"));
  }
  SECTION("an unbounded block") {
    sq.erase(sq.begin());  // the face -z gone: a strip open downwards
    const auto msg =
        test::error_of([&] { slice::block_geometry(block_of(sq, Vec3::Zero()), js, tol); });
    CHECK_THAT(msg, Contains("unbounded") || Contains("no interior") || Contains("do not bound"));
  }
}

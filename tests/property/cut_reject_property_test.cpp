// The cut's geometric shortcuts (slice/cut_reject.hpp) against the exact cut LP, on random
// blocks and joints, degenerate ones included, and on whole random and degenerate scenes cut
// with and without them. Fixed seeds; SLICE_PROPERTY_SCALE (support.hpp) runs a share.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "slice/cut.hpp"
#include "slice/cut_reject.hpp"
#include "slice/lp.hpp"
#include "slice/scene.hpp"
#include "support/compare.hpp"
#include "support/lp_cases.hpp"
#include "support/support.hpp"

namespace {

using namespace test::lp;
using slice::CutReject;
using slice::LpBackend;
using slice::LpStatus;

constexpr std::uint64_t kSeed = 29029;  // issue 29, nothing more
constexpr double kRelTol = 1e-9;        // Tolerances::from_scale(L, 1e-9), as the scenes

// How a joint meets its block. The last four are the degenerate ones: a polygon with a corner
// at a vertex of the block, with an edge on the plane of a face, lying in a face's plane, and in
// a plane a hair (1e-13 to 1e-5 L) inside or outside a face.
enum class Shape { persistent, polygon, through_vertex, edge_on_face, on_face, near_face };
constexpr Shape kShapes[] = {Shape::persistent,   Shape::polygon, Shape::through_vertex,
                             Shape::edge_on_face, Shape::on_face, Shape::near_face};
constexpr int kShapeCount = 6;
const char* to_string(Shape s) {
  constexpr const char* names[] = {"persistent",   "polygon", "through vertex",
                                   "edge on face", "on face", "near face"};
  return names[static_cast<int>(s)];
}
/// A joint in the block's frame: its plane and its corners (counter-clockwise about the
/// normal; none: persistent).
struct JointCase {
  Plane plane;
  std::vector<Vec3> corners;
};

/// The regular k-gon in the plane of unit normal n with centre c and first corner `first`,
/// counter-clockwise about n.
std::vector<Vec3> regular_polygon(const Vec3& n, const Vec3& c, const Vec3& first, int k) {
  const Vec3 a = first - c, b = n.cross(a);
  std::vector<Vec3> out;
  for (int i = 0; i < k; ++i) {
    const double phi = 2 * std::numbers::pi * i / k;
    out.push_back(i == 0 ? first : Vec3(c + std::cos(phi) * a + std::sin(phi) * b));
  }
  return out;
}

/// A face through vertex v, and v (the block's vertices are enumerated).
std::pair<const Face*, const Vertex*> face_at_vertex(Rng& rng, const RandomBlock& b) {
  const Vertex& v = b.vertices[static_cast<std::size_t>(rng.index(int(b.vertices.size())))];
  const int f = v.faces[static_cast<std::size_t>(rng.index(int(v.faces.size())))];
  return {&b.faces[static_cast<std::size_t>(f)], &v};
}

JointCase make_joint(Rng& rng, const RandomBlock& b, Shape shape, PlaneKind kind) {
  JointCase j;
  const double size = b.radius * rng.log_uniform(-1.5, 0.5);
  const int k = 3 + rng.index(6);
  switch (shape) {
    case Shape::persistent:
      j.plane = random_plane(rng, b, kind, 1.0);
      break;
    case Shape::polygon: {
      j.plane = random_plane(rng, b, kind, 1.0);
      const Vec3& n = j.plane.normal;
      const Vec3 foot = b.centre - j.plane.distance(b.centre) * n;
      const Vec3 c = foot + b.radius * rng.uniform(0, 2.5) * rng.perpendicular(n);
      j.corners = regular_polygon(n, c, c + size * rng.perpendicular(n), k);
      break;
    }
    case Shape::through_vertex: {
      const Vec3& v = b.vertices[static_cast<std::size_t>(rng.index(int(b.vertices.size())))].x;
      const Vec3 n = rng.unit_vector();
      j.plane = {n, n.dot(v)};
      j.corners = regular_polygon(n, v + size * rng.perpendicular(n), v, k);
      break;
    }
    case Shape::edge_on_face: {
      // A rectangle whose first edge lies on a line of the face's plane through a vertex, in a
      // plane turned about that line; the sign of the normal puts it on either side.
      const auto [f, v] = face_at_vertex(rng, b);
      const Vec3 t = rng.perpendicular(f->normal);
      const Vec3 n = rng.perpendicular(t) * (rng.chance(0.5) ? 1 : -1);
      const Vec3 w = n.cross(t);
      const double lo = -size * rng.uniform(), hi = size * rng.uniform(0.1, 1);
      const double h = size * rng.uniform(0.1, 1);
      j.plane = {n, n.dot(v->x)};
      j.corners = {v->x + lo * t, v->x + hi * t, v->x + hi * t + h * w, v->x + lo * t + h * w};
      break;
    }
    case Shape::on_face:
    case Shape::near_face: {
      const auto [f, v] = face_at_vertex(rng, b);
      const double sign = rng.chance(0.5) ? 1 : -1;
      const double shift =
          shape == Shape::on_face ? 0 : rng.log_uniform(-13, -5) * (rng.chance(0.5) ? 1 : -1);
      const Vec3 n = sign * f->normal;
      j.plane = {n, sign * (f->d + shift)};
      const Vec3 foot = v->x + shift * f->normal;
      const Vec3 c = foot + size * rng.uniform(0, 1.5) * rng.perpendicular(n);
      j.corners = regular_polygon(n, c, c + size * rng.perpendicular(n), k);
      break;
    }
  }
  return j;
}

/// What cut.cpp hands the shortcuts and the LP: the joint moved to the global frame (at the
/// offset, or scaled) and back to the block's, its edges made from its global corners as
/// cut.cpp's prepare makes them, and the margin for the coordinates' size.
struct Presented {
  Plane plane;
  std::vector<Vec3> corners;
  std::vector<Plane> edges;
  double magnitude = 0;
};

Presented present_joint(const JointCase& j, Variant v) {
  const Vec3 origin = v == Variant::offset ? kOffsetOrigin : Vec3::Zero();
  const double s = variant_scale(v);
  const Plane global = slice::to_global({j.plane.normal, s * j.plane.d}, origin);
  Presented p;
  p.plane = slice::to_local(global, origin);
  p.magnitude = std::max(origin.cwiseAbs().maxCoeff(), std::abs(global.d));
  std::vector<Vec3> corners;
  for (const Vec3& c : j.corners) corners.push_back(origin + s * c);
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const Vec3& a = corners[k];
    const Vec3& b = corners[(k + 1) % corners.size()];
    const Vec3 m = (b - a).cross(global.normal).normalized();
    p.edges.push_back(slice::to_local(Plane{m, m.dot(a)}, origin));
    p.corners.push_back(a - origin);
    p.magnitude = std::max(p.magnitude, a.cwiseAbs().maxCoeff());
  }
  return p;
}

struct Tally {
  long cases = 0, no_cut = 0, failures = 0, splits = 0, proved = 0;
  long rejected[4] = {0, 0, 0, 0};  // by plane_misses_box, polygon_misses_box, faces, reject_cut
  std::vector<std::string> messages;
  void fail(const std::string& m) {
    ++failures;
    if (messages.size() < 8) messages.push_back(m);
  }
};

}  // namespace

TEST_CASE("no shortcut rejects a pair the exact cut LP cuts nor proves a cut it does not make",
          "[property][cut][reject]") {
  // 200 blocks of 5 to 20 faces (1 in 4 with a duplicate and a near-parallel face); on each,
  // 4 joints of every shape, each presented in 4 variants (as made, at a 1e6 m offset, scaled
  // by 1e-3 and 1e3): 19,200 pairs. Every test alone, and all in order, against the exact LP
  // (and the native one: the cut must not see a shortcut's "no" where native says "cut").
  // The faces test must also be complete: it rejects every pair whose exact s* exceeds twice
  // the margin (the polygon then misses the block grown by it).
  const long blocks = test::scaled_cases(200);
  auto exact = slice::make_solver(LpBackend::exact);
  auto native = slice::make_solver(LpBackend::native);
  slice::ClipScratch scratch;
  Tally by_shape[kShapeCount];
  for (long bi = 0; bi < blocks; ++bi) {
    Rng rng(mix(kSeed, static_cast<std::uint64_t>(bi)));
    RandomBlock block = random_block(rng, 5 + rng.index(16), 1.0, rng.chance(0.25));
    enumerate_vertices(block, 1.0);
    const auto base_tol = slice::Tolerances::from_scale(1, kRelTol);
    const slice::Extents box = slice::extents(*exact, block.faces, base_tol);
    REQUIRE(box.status == LpStatus::optimal);
    for (int si = 0; si < kShapeCount; ++si) {
      const Shape shape = kShapes[si];
      Tally& t = by_shape[si];
      for (int rep = 0; rep < 4; ++rep) {
        const PlaneKind kind = kKinds[static_cast<std::size_t>(bi + rep) % 7];
        const JointCase joint = make_joint(rng, block, shape, kind);
        for (const Variant v : kVariants) {
          const double s = variant_scale(v);
          const auto tol = slice::Tolerances::from_scale(s, kRelTol);
          std::vector<Face> faces = block.faces;
          for (Face& f : faces) f.d *= s;
          const Vec3 lo = s * box.min, hi = s * box.max;
          std::vector<Vec3> inside;  // points of the block, as its extremes in cut.cpp
          for (std::size_t k = 0; k < block.vertices.size() && k < 6; ++k)
            inside.push_back(s * block.vertices[k].x);
          const Presented p = present_joint(joint, v);
          const double margin =
              slice::reject_margin(tol, p.magnitude + (hi - lo).cwiseAbs().maxCoeff());
          const slice::CutTest ex = slice::cut_test(*exact, faces, p.plane, p.edges, tol);
          const slice::CutTest nat = slice::cut_test(*native, faces, p.plane, p.edges, tol);
          ++t.cases;
          std::ostringstream what;
          what.precision(17);
          what << to_string(shape) << " " << to_string(kind) << " " << to_string(v) << " block "
               << bi << " rep " << rep << ": exact s* " << ex.s << ", native s* " << nat.s;
          if (ex.status != LpStatus::optimal || nat.status != LpStatus::optimal) {
            t.fail(what.str() + ": LP not optimal");
            continue;
          }
          t.no_cut += ex.cuts ? 0 : 1;
          const bool said[4] = {
              slice::plane_misses_box(p.plane, lo, hi, margin),
              slice::polygon_misses_box(p.corners, lo, hi, margin),
              slice::faces_miss_polygon(faces, p.plane, p.corners, lo, hi, margin, scratch),
              slice::reject_cut(faces, p.plane, p.corners, lo, hi, inside, margin, scratch) !=
                  CutReject::none};
          // A plane that splits points of the block meets it: the faces test cannot settle a
          // persistent joint then (reject_cut does not try).
          if (p.corners.empty() && slice::plane_splits_points(p.plane, inside, margin)) {
            ++t.splits;
            if (said[2]) t.fail(what.str() + ": the plane splits the block, yet faces rejected");
          }
          constexpr const char* names[] = {"plane/box", "polygon box", "faces", "reject_cut"};
          for (int k = 0; k < 4; ++k) {
            if (!said[k]) continue;
            ++t.rejected[k];
            if (ex.cuts || nat.cuts) t.fail(what.str() + ": " + names[k] + " rejected a cut");
          }
          if (ex.s > 2 * margin && !said[2]) t.fail(what.str() + ": faces test missed it");
          // The converse: a pair proved cut is one both LPs cut. As the cut asks, after
          // reject_cut (whose faces test may leave its clipped region), and from scratch.
          slice::ClipScratch fresh;
          const bool proved = slice::surely_cuts(faces, p.plane, p.corners, p.edges, lo, hi,
                                                 tol.cut, margin, scratch);
          if (proved != slice::surely_cuts(faces, p.plane, p.corners, p.edges, lo, hi, tol.cut,
                                           margin, fresh))
            t.fail(what.str() + ": surely_cuts answers otherwise from scratch");
          if (proved) {
            ++t.proved;
            if (!ex.cuts || !nat.cuts) t.fail(what.str() + ": surely_cuts proved a cut");
          }
        }
      }
    }
  }
  long rejected_total[4] = {0, 0, 0, 0}, splits_total = 0;
  for (int si = 0; si < kShapeCount; ++si) {
    const Tally& t = by_shape[si];
    std::ostringstream summary;
    summary << to_string(kShapes[si]) << ": " << t.cases << " pairs, " << t.no_cut
            << " not cut (exact), rejected by plane/box " << t.rejected[0] << ", polygon box "
            << t.rejected[1] << ", faces " << t.rejected[2] << ", in order " << t.rejected[3]
            << "; splitting the block's points " << t.splits << "; proved cut " << t.proved;
    SUCCEED(summary.str());  // shown with -s
    for (const auto& m : t.messages) summary << "\n  " << m;
    INFO(summary.str());
    CHECK(t.cases == blocks * 16);
    CHECK(t.failures == 0);
    // Every shape has pairs not cut. A polygon with a corner at a vertex or an edge on a face
    // touches the block: within the margin, so never settled; the tests in order settle some
    // pairs of every other shape.
    CHECK(t.no_cut > 0);
    const Shape shape = kShapes[si];
    if (shape == Shape::through_vertex || shape == Shape::edge_on_face)
      CHECK(t.rejected[3] == 0);
    else
      CHECK(t.rejected[3] > 0);
    // Polygons through the block's inside and planes across it are proved cut; one with a
    // corner at a vertex or an edge on a face often reaches in far enough too.
    if (shape != Shape::on_face && shape != Shape::near_face) CHECK(t.proved > 0);
    for (int k = 0; k < 4; ++k) rejected_total[k] += t.rejected[k];
    splits_total += t.splits;
  }
  CHECK(splits_total > 0);
  // Each test rejects pairs of its own (none is dead code here).
  for (int k = 0; k < 4; ++k) CHECK(rejected_total[k] > 0);
}

namespace {

/// Random polygon joints in a 4 x 3 x 2 box, dense enough that most pairs past the index are
/// not cut: squares, 16-gons (discs) and triangles of random orientation, and a few persistent
/// planes.
std::string random_polygon_scene(std::uint64_t seed) {
  Rng rng(mix(kSeed + 1, seed));
  std::ostringstream s;
  s.precision(17);
  s << "[domain]\nbox = { min = [0, 0, 0], max = [4, 3, 2] }\n";
  const int joints = 30 + rng.index(30);
  for (int j = 0; j < joints; ++j) {
    const Vec3 p(4 * rng.uniform(), 3 * rng.uniform(), 2 * rng.uniform());
    s << "[[joints]]\ndip = " << 90 * rng.uniform() << "\ndip_direction = " << 359.9 * rng.uniform()
      << "\npoint = [" << p.x() << ", " << p.y() << ", " << p.z() << "]\n";
    const int shape = rng.index(8);
    if (shape == 0) continue;  // persistent
    const double r = rng.uniform(0.2, 1.2), phase = rng.uniform(0, 2 * std::numbers::pi);
    const int sides = shape <= 3 ? 4 : shape <= 6 ? 16 : 3;
    s << "polygon_uv = [";
    for (int k = 0; k < sides; ++k) {
      const double phi = phase + 2 * std::numbers::pi * k / sides;
      s << (k ? ", " : "") << "[" << r * std::cos(phi) << ", " << r * std::sin(phi) << "]";
    }
    s << "]\n";
  }
  return s.str();
}

/// Joints on a lattice of step 0.5 in a 4 m cube: axis-aligned rectangles and persistent planes,
/// some in the domain's faces, and triangles across the lattice's diagonals. Their corners are
/// other joints' block vertices, their edges lie on other joints' faces and many are coplanar
/// with a face (of the domain or of an earlier joint): every degenerate case at once.
std::string lattice_scene(std::uint64_t seed) {
  Rng rng(mix(kSeed + 2, seed));
  std::ostringstream s;
  s.precision(17);
  s << "[domain]\nbox = { min = [0, 0, 0], max = [4, 4, 4] }\n";
  const auto step = [&](int lo, int hi) { return 0.5 * (lo + rng.index(hi - lo + 1)); };
  const auto corner = [](const Vec3& x) {
    std::ostringstream o;
    o << "[" << x.x() << ", " << x.y() << ", " << x.z() << "]";
    return o.str();
  };
  const int joints = 12 + rng.index(12);
  for (int j = 0; j < joints; ++j) {
    const int axis = rng.index(3);  // the normal's axis
    // dip, dip direction of the normals +x, +y, +z (orientation.hpp)
    constexpr const char* angles[] = {"dip = 90\ndip_direction = 90\n",
                                      "dip = 90\ndip_direction = 0\n",
                                      "dip = 0\ndip_direction = 0\n"};
    const int kind = rng.index(6);
    if (kind == 5) {  // a triangle x + y + z = c through three lattice points (normal (1,1,1))
      const double c = step(2, 12);
      const double a = std::min(c, 4.0);
      s << "[[joints]]\ndip = 54.735610317245346\ndip_direction = 45\npolygon = ["
        << corner({a, c - a, 0}) << ", " << corner({0, a, c - a}) << ", " << corner({c - a, 0, a})
        << "]\n";
      continue;
    }
    Vec3 p(step(0, 8), step(0, 8), step(0, 8));
    s << "[[joints]]\n" << angles[axis];
    if (kind == 0) {  // persistent
      s << "point = " << corner(p) << "\n";
      continue;
    }
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double u0 = step(0, 6), v0 = step(0, 6);
    const double u1 = u0 + step(1, 8 - int(2 * u0)), v1 = v0 + step(1, 8 - int(2 * v0));
    Vec3 a = p, b = p, c = p, d = p;
    a[u] = u0, a[v] = v0, b[u] = u1, b[v] = v0, c[u] = u1, c[v] = v1, d[u] = u0, d[v] = v1;
    s << "polygon = [" << corner(a) << ", " << corner(b) << ", " << corner(c) << ", " << corner(d)
      << "]\n";
  }
  return s.str();
}

/// Cuts with and without the shortcuts: the same blocks, bit for bit, and fewer cut LPs.
void check_same_blocks(const std::string& scene, std::size_t& lps_with, std::size_t& lps_without,
                       std::size_t& settled, std::size_t* by_limit = nullptr,
                       std::array<std::size_t, 2>* chebyshev = nullptr) {
  const auto js = slice::generate_joints(slice::parse_scene(scene, "scene.toml"));
  slice::CutOptions with, without;
  without.use_shortcuts = false;
  const auto a = slice::cut_blocks(js, with), b = slice::cut_blocks(js, without);
  test::check_same(a.blocks, b.blocks);
  CHECK(a.stats.splits == b.stats.splits);
  // A pair the size limit settles before the LP (settled_by_limit) is a split undone without
  // the shortcuts if the plane cuts the block, and no split if it does not.
  CHECK(a.stats.splits_undone <= b.stats.splits_undone);
  CHECK(b.stats.splits_undone <= a.stats.splits_undone + a.stats.settled_by_limit);
  CHECK(a.stats.pairs_skipped == b.stats.pairs_skipped);
  CHECK(b.stats.rejected_plane + b.stats.rejected_box + b.stats.rejected_faces +
            b.stats.settled_by_limit + b.stats.cut_without_lp ==
        0);
  const std::size_t s = a.stats.rejected_plane + a.stats.rejected_box + a.stats.rejected_faces +
                        a.stats.settled_by_limit + a.stats.cut_without_lp;
  CHECK(a.stats.lps.cut_test + s == b.stats.lps.cut_test);
  lps_with += a.stats.lps.cut_test;
  lps_without += b.stats.lps.cut_test;
  settled += s;
  if (by_limit) *by_limit += a.stats.settled_by_limit;
  if (chebyshev) {
    (*chebyshev)[0] += a.stats.lps.chebyshev;
    (*chebyshev)[1] += b.stats.lps.chebyshev;
  }
}

}  // namespace

TEST_CASE("the shortcuts change no block of random polygon scenes", "[property][cut][reject]") {
  const long n = test::scaled_cases(20);
  std::size_t with = 0, without = 0, settled = 0;
  for (long seed = 1; seed <= n; ++seed) {
    CAPTURE(seed);
    check_same_blocks(random_polygon_scene(std::uint64_t(seed)), with, without, settled);
  }
  std::ostringstream summary;
  summary << without << " cut LPs without the shortcuts, " << with << " with";
  SUCCEED(summary.str());  // shown with -s
  CHECK(settled > 0);
  CHECK(2 * with < without);  // most pairs past the index are settled by geometry
}

TEST_CASE("the shortcuts change no block of degenerate lattice scenes", "[property][cut][reject]") {
  const long n = test::scaled_cases(40);
  std::size_t with = 0, without = 0, settled = 0;
  for (long seed = 1; seed <= n; ++seed) {
    const std::string scene = lattice_scene(std::uint64_t(seed));
    CAPTURE(seed, scene);
    check_same_blocks(scene, with, without, settled);
  }
  std::ostringstream summary;
  summary << without << " cut LPs without the shortcuts, " << with << " with";
  SUCCEED(summary.str());  // shown with -s
  CHECK(settled > 0);
}

// A pair whose split the size limit would undo, a piece between the plane and a parallel face
// thinner than min_inscribed_diameter by the margin, skips the cut LP (settled_by_limit), and a
// child whose ball about its centre is clear of the limit skips its Chebyshev LP: the blocks
// must be those every pair and every child to the LP gives. The lattice scenes put planes 0.5
// apart, on the domain's faces and on each other's (limits 0.3, 0.5 = the step itself, 0.6,
// 1.1); the random ones tilt them.
TEST_CASE("pairs the size limit settles before the cut LP change no block",
          "[property][cut][reject]") {
  const long n = test::scaled_cases(40);
  std::size_t with = 0, without = 0, settled = 0, by_limit = 0;
  std::array<std::size_t, 2> chebyshev{0, 0};
  for (long seed = 1; seed <= n; ++seed)
    for (const char* min_d : {"0.3", "0.5", "0.6", "1.1"}) {
      const std::string scene = "[options]\nmin_inscribed_diameter = " + std::string(min_d) + "\n" +
                                (seed % 2 ? lattice_scene(std::uint64_t(seed))
                                          : random_polygon_scene(std::uint64_t(seed)));
      CAPTURE(seed, scene);
      check_same_blocks(scene, with, without, settled, &by_limit, &chebyshev);
    }
  std::ostringstream summary;
  summary << without << " cut LPs without the shortcuts, " << with << " with, " << by_limit
          << " pairs settled by the size limit; Chebyshev LPs " << chebyshev[1] << " without, "
          << chebyshev[0] << " with";
  SUCCEED(summary.str());  // shown with -s
  CHECK(by_limit > 0);
  CHECK(chebyshev[0] < chebyshev[1]);
}

// parallel_slab_width (slice-cut's early size limit, issue 29): a block split by a plane
// parallel to one of its faces (the same normal, or its reverse, bit for bit) has a piece no
// thicker than the slab between them. Random blocks (some with a duplicate face and a face a
// hair outside another), the plane from 1e-7 to twice the block's radius inside one of its
// faces; also planes through a vertex of the block, and on the face itself. The
// exact Chebyshev LP of each piece must never find a piece thinner than the shortcut says it
// might be thick: 2 r_exact <= width. And wherever slice-cut would decide early (the width below
// a limit by the margin and the geometry tolerance), the native LP, the one slice-cut would
// otherwise run, finds the piece under the limit too.
TEST_CASE("a split's parallel slab bounds its pieces' inscribed diameter",
          "[property][cut][reject]") {
  const long n = test::scaled_cases(20'000, 4);
  auto exact = slice::make_solver(LpBackend::exact);
  auto native = slice::make_solver(LpBackend::native);
  const auto tol = slice::Tolerances::from_scale(1.0, kRelTol);
  long bounded = 0, decided = 0, wrong = 0;
  std::string first_wrong;
  for (long i = 0; i < n; ++i) {
    Rng rng(mix(kSeed + 31, static_cast<std::uint64_t>(i)));
    RandomBlock block = random_block(rng, 4 + rng.index(8), 1.0, rng.chance(0.3));
    enumerate_vertices(block, 1.0);
    if (block.vertices.empty()) continue;
    const Face& f = block.faces[static_cast<std::size_t>(rng.index(int(block.faces.size())))];
    double w = block.radius * rng.log_uniform(-7, 0.3);
    const int where = static_cast<int>(i % 4);  // 0, 1: a slab; 2: a vertex; 3: on the face
    if (where == 2) {
      const Vertex& v =
          block.vertices[static_cast<std::size_t>(rng.index(int(block.vertices.size())))];
      w = f.d - f.normal.dot(v.x);
    } else if (where == 3) {
      w = 0;
    }
    // The plane n . x = f.d - w, written with normal +-f.normal (a reversal is exact).
    const bool reversed = rng.chance(0.5);
    const Plane plane = reversed ? Plane{-f.normal, -(f.d - w)} : Plane{f.normal, f.d - w};
    const double width = slice::parallel_slab_width(block.faces, plane);
    REQUIRE(std::isfinite(width));
    std::vector<Face> below = block.faces, above = block.faces;
    below.push_back({plane.normal, plane.d, -1});
    above.push_back({-plane.normal, -plane.d, -1});
    double thinnest = INFINITY, thinnest_native = INFINITY;
    bool split = true;
    for (const auto* piece : {&below, &above}) {
      const slice::ChebyshevBall e = slice::chebyshev_ball(*exact, *piece, tol);
      const slice::ChebyshevBall c = slice::chebyshev_ball(*native, *piece, tol);
      // A piece with no interior (the plane misses the block, or lies on a face): no split.
      split = split && e.status == LpStatus::optimal && e.radius > 0;
      thinnest = std::min(thinnest, 2 * e.radius);
      if (c.status == LpStatus::optimal) thinnest_native = std::min(thinnest_native, 2 * c.radius);
    }
    if (!split) continue;
    ++bounded;
    bool ok = thinnest <= width + 1e-12;
    // slice-cut's rule: a limit min_d with width < min_d - margin - tol.geometry is decided
    // early; the LP must find that piece under min_d - margin. Limits just past that point.
    const double margin = 1e-7 * 0.4,
                 min_d = width + margin + tol.geometry + rng.log_uniform(-12, -1);
    if (width < min_d - margin - tol.geometry) {
      ++decided;
      ok = ok && thinnest_native < min_d - margin;
    }
    if (!ok && ++wrong <= 8) {
      std::ostringstream m;
      m << "case " << i << " where " << where << " width " << width << " exact 2r " << thinnest
        << " native 2r " << thinnest_native << "; ";
      first_wrong += m.str();
    }
  }
  INFO(bounded << " splits bounded, " << decided << " decided early");
  INFO(first_wrong);
  CHECK(wrong == 0);
  CHECK(bounded >= n / 4);
}

// ball_in_half_space (slice-cut's other early size limit, issue 29): a block's inscribed ball,
// cut by the planes that split the block again and again, keeps a ball inside each piece, so a
// piece whose ball is thicker than the limit passes it without an LP. Random blocks (some with
// duplicate and near-duplicate faces), their exact Chebyshev ball, then three splits in a row by
// planes through the inside, a vertex, an edge, on a face, tilted off a face, near touching,
// missing, each keeping a random side. Every ball kept must lie inside its piece (every face),
// and the piece's exact and native Chebyshev radii must be at least its radius.
TEST_CASE("a ball kept through splits lies inside every piece", "[property][cut][reject]") {
  const long n = test::scaled_cases(10'000, 4);
  auto exact = slice::make_solver(LpBackend::exact);
  auto native = slice::make_solver(LpBackend::native);
  const auto tol = slice::Tolerances::from_scale(1.0, kRelTol);
  long kept = 0, wrong = 0;
  std::string first_wrong;
  for (long i = 0; i < n; ++i) {
    Rng rng(mix(kSeed + 37, static_cast<std::uint64_t>(i)));
    RandomBlock block = random_block(rng, 4 + rng.index(8), 1.0, rng.chance(0.3));
    enumerate_vertices(block, 1.0);
    if (block.vertices.empty()) continue;
    std::vector<Face> piece = block.faces;
    const slice::ChebyshevBall b0 = slice::chebyshev_ball(*exact, piece, tol);
    REQUIRE(b0.status == LpStatus::optimal);
    slice::Ball ball{b0.centre, b0.radius - tol.geometry};
    for (int cut = 0; cut < 3 && ball.radius > 0; ++cut) {
      const auto kind = static_cast<PlaneKind>(rng.index(7));
      Plane half = random_plane(rng, block, kind, 1.0);
      if (rng.chance(0.5)) half = {-half.normal, -half.d};
      piece.push_back({half.normal, half.d, -1});
      ball = slice::ball_in_half_space(ball, half, tol.geometry);
      if (!(ball.radius > 0)) break;
      ++kept;
      double outside = -INFINITY;  // how far the ball pokes out of the piece (<= 0: inside)
      for (const Face& f : piece)
        outside = std::max(outside, f.normal.dot(ball.centre) + ball.radius - f.d);
      const slice::ChebyshevBall e = slice::chebyshev_ball(*exact, piece, tol);
      const slice::ChebyshevBall c = slice::chebyshev_ball(*native, piece, tol);
      const bool ok = outside <= 1e-15 && e.status == LpStatus::optimal &&
                      e.radius >= ball.radius && c.status == LpStatus::optimal &&
                      c.radius >= ball.radius;
      if (!ok && ++wrong <= 8) {
        std::ostringstream m;
        m << "case " << i << " cut " << cut << " " << to_string(kind) << ": ball " << ball.radius
          << " pokes out " << outside << ", exact r " << e.radius << ", native r " << c.radius
          << "; ";
        first_wrong += m.str();
      }
    }
  }
  INFO(kept << " balls kept");
  INFO(first_wrong);
  CHECK(wrong == 0);
  CHECK(kept >= n);
}

// surely_irredundant (the prune's shortcut): a face it keeps must be one the exact redundancy LP
// keeps, whatever point of the face's plane its search ends at. Random blocks (some with a
// duplicate face and a face a hair outside another), each with a few more faces from planes
// through the inside, a vertex, an edge, on a face, tilted off a face, near touching, missing,
// and its origin moved off the middle (so that the first point, the foot of the origin, is often
// cut off and the search has to move).
TEST_CASE("a face the prune keeps without an LP is one the exact LP keeps",
          "[property][cut][prune]") {
  const long n = test::scaled_cases(4'000, 4);
  auto exact = slice::make_solver(LpBackend::exact);
  const auto tol = slice::Tolerances::from_scale(1.0, kRelTol);
  long faces_tested = 0, certified = 0, moved = 0, wrong = 0;
  std::string first_wrong;
  for (long i = 0; i < n; ++i) {
    Rng rng(mix(kSeed + 41, static_cast<std::uint64_t>(i)));
    RandomBlock block = random_block(rng, 4 + rng.index(8), 1.0, rng.chance(0.3));
    enumerate_vertices(block, 1.0);
    if (block.vertices.empty()) continue;
    std::vector<Face> faces = block.faces;
    for (int extra = rng.index(4); extra > 0; --extra) {
      const Plane p = random_plane(rng, block, static_cast<PlaneKind>(rng.index(7)), 1.0);
      faces.push_back({p.normal, p.d, -1});
    }
    // The origin moved by up to the block's radius.
    const Vec3 shift = block.radius * rng.uniform(0, 1) * rng.unit_vector();
    for (Face& f : faces) f.d -= f.normal.dot(shift);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const slice::FaceRedundancy r = slice::face_redundancy(*exact, faces, f, tol);
      if (r.status == LpStatus::infeasible) break;  // the planes left no block
      ++faces_tested;
      if (!slice::surely_irredundant(faces, f, tol)) continue;
      ++certified;
      // Would the foot of the origin alone have done (the search's first point)?
      bool foot = true;
      for (std::size_t j = 0; j < faces.size(); ++j)
        foot = foot && (j == f || faces[j].d - faces[j].normal.dot(faces[f].d * faces[f].normal) >=
                                      tol.prune);
      moved += foot ? 0 : 1;
      if (r.redundant && ++wrong <= 8)
        first_wrong += "case " + std::to_string(i) + " face " + std::to_string(f) + "; ";
    }
  }
  INFO(certified << " of " << faces_tested << " faces kept without an LP, " << moved
                 << " of them after the search moved");
  INFO(first_wrong);
  CHECK(wrong == 0);
  CHECK(certified >= faces_tested / 4);
  CHECK(moved >= certified / 20);
}

// Closed triangle meshes (mesh.hpp): OBJ and STL reading, the solid check, inside tests.
#include "slice/mesh.hpp"

#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "slice/error.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using slice::Vec3;

namespace {

// The unit cube [0, 1]^3 as 6 quads, counter-clockwise seen from outside.
const char* kCubeObj = R"(# unit cube
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)";

slice::TriangleMesh cube() {
  test::TempDir tmp;
  test::write_text(tmp / "cube.obj", kCubeObj);
  return slice::read_mesh(tmp / "cube.obj");
}

/// A binary STL of the mesh's triangles.
std::string binary_stl(const slice::TriangleMesh& m) {
  std::string out(80, ' ');
  const auto count = std::uint32_t(m.triangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : m.triangles) {
    float rec[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        rec[3 + 3 * k + c] = float(m.vertices[std::size_t(t[std::size_t(k)])][c]);
    out.append(reinterpret_cast<const char*>(rec), sizeof rec);
    out.append(2, '\0');
  }
  return out;
}

}  // namespace

TEST_CASE("a cube reads from OBJ and both STL forms as the same solid", "[mesh]") {
  const auto m = cube();
  REQUIRE(m.vertices.size() == 8);
  REQUIRE(m.triangles.size() == 12);
  CHECK_THAT(slice::check_solid_mesh(m, "cube.obj"), WithinRel(1.0, 1e-15));
  test::TempDir tmp;
  test::write_text(tmp / "a.stl", test::ascii_stl(m));
  test::write_text(tmp / "b.STL", binary_stl(m));
  for (const char* name : {"a.stl", "b.STL"}) {
    CAPTURE(name);
    const auto s = slice::read_mesh(tmp / name);
    CHECK(s.vertices.size() == 8);  // welded
    CHECK(s.triangles.size() == 12);
    CHECK_THAT(slice::check_solid_mesh(s, name), WithinRel(1.0, 1e-15));
  }
}

TEST_CASE("points inside a mesh: strictly inside only, exact on the surface", "[mesh]") {
  const slice::MeshInside inside(cube());
  CHECK(inside(Vec3(0.5, 0.5, 0.5)));
  CHECK(inside(Vec3(1e-12, 0.5, 0.999999)));
  CHECK_FALSE(inside(Vec3(1.5, 0.5, 0.5)));
  CHECK_FALSE(inside(Vec3(1.0, 0.5, 0.5)));  // on a face
  CHECK_FALSE(inside(Vec3(0, 0, 0)));        // on a corner
  CHECK_FALSE(inside(Vec3(-1e-12, 0.5, 0.5)));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 x(u(rng), u(rng), u(rng));
    const bool want = (x.array() > 0).all() && (x.array() < 1).all();
    CHECK(inside(x) == want);
  }
}

TEST_CASE("meshes that bound no solid are refused with the reason", "[mesh]") {
  auto m = cube();
  SECTION("open") {
    m.triangles.pop_back();
    CHECK_THAT(test::error_of([&] { slice::check_solid_mesh(m, "x.obj"); }),
               Contains("x.obj") && Contains("open"));
  }
  SECTION("inside out") {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
    CHECK_THAT(test::error_of([&] { slice::check_solid_mesh(m, "x.obj"); }),
               Contains("inside out"));
  }
  SECTION("one triangle turned the wrong way") {
    std::swap(m.triangles[3][1], m.triangles[3][2]);
    CHECK_THAT(test::error_of([&] { slice::check_solid_mesh(m, "x.obj"); }),
               Contains("consistently oriented"));
  }
  SECTION("self-intersecting: two overlapping cubes in one mesh") {
    const auto n = std::int64_t(m.vertices.size());
    const auto first = m;
    for (const Vec3& x : first.vertices) m.vertices.push_back(x + Vec3(0.5, 0.5, 0.5));
    for (auto t : first.triangles) m.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
    CHECK_THAT(test::error_of([&] { slice::check_solid_mesh(m, "x.obj"); }),
               Contains("intersects itself"));
  }
  SECTION("a triangle without area") {
    m.vertices[6] = m.vertices[2];  // (1,1,1) onto (1,1,0): faces collapse
    CHECK_FALSE(test::error_of([&] { slice::check_solid_mesh(m, "x.obj"); }).empty());
  }
}

TEST_CASE("bad mesh files are refused with the file and line", "[mesh]") {
  test::TempDir tmp;
  test::write_text(tmp / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  CHECK_THAT(test::error_of([&] { slice::read_mesh(tmp / "bad.obj"); }),
             Contains("bad.obj:4") && Contains("vertex 9"));
  test::write_text(tmp / "nan.obj", "v 0 nan 0\n");
  CHECK_THAT(test::error_of([&] { slice::read_mesh(tmp / "nan.obj"); }), Contains("nan.obj:1"));
  test::write_text(tmp / "empty.stl", "solid x\nendsolid x\n");
  CHECK_THAT(test::error_of([&] { slice::read_mesh(tmp / "empty.stl"); }),
             Contains("no triangles"));
  test::write_text(tmp / "cave.ply", "ply\n");
  CHECK_THAT(test::error_of([&] { slice::read_mesh(tmp / "cave.ply"); }),
             Contains(".obj nor .stl"));
  CHECK_THAT(test::error_of([&] { slice::read_mesh(tmp / "missing.obj"); }),
             Contains("cannot be read"));
}

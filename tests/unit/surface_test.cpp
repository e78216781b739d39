// Topography surfaces (surface.hpp): the ESRI ASCII grid reader, the height-field checks, the
// closed solid of the rock above, on inputs known by hand.
#include "slice/surface.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "slice/error.hpp"
#include "slice/scene.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using slice::Vec2;
using slice::Vec3;

namespace {

slice::HeightGrid grid_of(const std::string& text) {
  test::TempDir tmp;
  test::write_text(tmp / "g.asc", text);
  return slice::read_ascii_grid(tmp / "g.asc");
}

std::string grid_error(const std::string& text) {
  return test::error_of([&] { grid_of(text); });
}

// The square [0, 1]^2 as two triangles at heights z(x, y) = 1 + x + 2 y, the second listed
// clockwise from above.
slice::TriangleMesh square() {
  slice::TriangleMesh m;
  m.vertices = {{0, 0, 1}, {1, 0, 2}, {1, 1, 4}, {0, 1, 3}};
  m.triangles = {{0, 1, 2}, {0, 3, 2}};
  return m;
}

const std::vector<Vec2> kUnit = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};

}  // namespace

TEST_CASE("an ESRI ASCII grid: keys in any case, centre or center, dx and dy, free line breaks",
          "[unit][surface]") {
  const slice::HeightGrid g = grid_of(
      "NCOLS 3\nnrows 2\nxllcentre 10\nYLLCENTER 20\ndx 2\ndy 0.5\n"
      "1 2 3\n4\n5 +6\n");
  CHECK(g.ncols == 3);
  CHECK(g.nrows == 2);
  CHECK(g.x0 == 10);
  CHECK(g.y0 == 20);
  CHECK(g.dx == 2);
  CHECK(g.dy == 0.5);
  CHECK_FALSE(g.nodata);
  CHECK(g.z == std::vector<double>{1, 2, 3, 4, 5, 6});
  CHECK(g.row_line == std::vector<std::int64_t>{7, 8});
  // Row 0 is the north row: y = y0 + (nrows - 1) dy.
  CHECK(g.x(2) == 14);
  CHECK(g.y(0) == 20.5);
  CHECK(g.at(1, 2) == 6);
  // A corner is half a cell from the centre.
  const slice::HeightGrid c = grid_of(
      "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 100\ncellsize 4\nnodata_value -1\n"
      "1 2\n3 -1\n");
  CHECK(c.x0 == 2);
  CHECK(c.y0 == 102);
  CHECK(c.nodata == -1);
}

TEST_CASE("malformed ESRI ASCII grids are refused with the line and the reason",
          "[unit][surface]") {
  const std::string head = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";
  CHECK_THAT(grid_error(head + "1 2\n3 nan\n"), Contains("g.asc:7") && Contains("not finite"));
  CHECK_THAT(grid_error(head + "1 2\n3 inf\n"), Contains("g.asc:7") && Contains("not finite"));
  CHECK_THAT(grid_error("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 0\n1 2\n3 4\n"),
             Contains("g.asc:5") && Contains("> 0"));
  CHECK_THAT(grid_error("ncols 2\nncols 2\n"), Contains("g.asc:2") && Contains("twice"));
  CHECK_THAT(grid_error("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\nfoo 3\n1 2\n"),
             Contains("g.asc:6") && Contains("unknown header key \"foo\""));
  CHECK_THAT(grid_error("ncols\nnrows 2\n"), Contains("g.asc:1") && Contains("no value"));
  CHECK_THAT(grid_error("ncols 1\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n2\n"),
             Contains("g.asc:1") && Contains("at least 2"));
  CHECK_THAT(grid_error("ncols 2.5\nnrows 2\n"),
             Contains("g.asc:1") && Contains("not a whole number"));
  CHECK_THAT(grid_error("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ndx 1\n1 2\n3 4\n"),
             Contains("no dy"));
  CHECK_THAT(grid_error(head + "1 2\n3 4\n" + std::string(1, '\0')), Contains("not text"));
  CHECK_THAT(grid_error(""), Contains("no ncols"));
}

TEST_CASE("a grid's surface: the cells over the domain, split south-west to north-east",
          "[unit][surface]") {
  // 4 x 3 centres at x = 0..3, y = 0..2; heights 10 r + c, the north row first.
  const slice::HeightGrid g = grid_of(
      "ncols 4\nnrows 3\nxllcenter 0\nyllcenter 0\ncellsize 1\nNODATA_value -9\n"
      "-9 1 2 3\n10 11 12 13\n20 21 22 23\n");
  // [1.5, 2.5] x [0.5, 1]: cells of columns 1 and 2, row 1 (from y = 0 to 1): no no-data.
  const slice::TriangleMesh m = slice::grid_surface(g, {1.5, 0.5}, {2.5, 1}, 1e-9, "g");
  CHECK(m.vertices.size() == 6);
  REQUIRE(m.triangles.size() == 4);
  // The first cell's triangles: (SW, SE, NE) and (SW, NE, NW).
  const auto at = [&](std::size_t t, std::size_t k) {
    return m.vertices[std::size_t(m.triangles[t][k])];
  };
  CHECK(at(0, 0) == Vec3(1, 0, 21));
  CHECK(at(0, 1) == Vec3(2, 0, 22));
  CHECK(at(0, 2) == Vec3(2, 1, 12));
  CHECK(at(1, 2) == Vec3(1, 1, 11));
  // Reaching the north-west corner takes its no-data value: refused with its row and line.
  CHECK_THAT(test::error_of([&] {
               slice::grid_surface(g, {0.5, 1.5}, {1, 2}, 1e-9, "g");
             }),
             Contains("g:7") && Contains("row 1, column 1") && Contains("no-data"));
  // Beyond the centres: refused with both extents.
  CHECK_THAT(test::error_of([&] {
               slice::grid_surface(g, {0, 0}, {3.5, 2}, 1e-9, "g");
             }),
             Contains("x [0, 3]") && Contains("x [0, 3.5]"));
}

TEST_CASE("height fields: orientation, overlaps, cover, and the solid above", "[unit][surface]") {
  const slice::TriangleMesh up = slice::check_height_field(square(), kUnit, 1e-9, "s");
  CHECK(up.triangles[1] == std::array<std::int64_t, 3>{0, 2, 3});  // turned counter-clockwise
  // The solid above up to z = 10: volume = 10 - mean height (2.5) over the unit square.
  const slice::TriangleMesh solid = slice::solid_above(up, 10);
  CHECK(solid.triangles.size() == 2 + 4 + 2 * 4);  // the lid: a fan of the 4 border edges
  CHECK_THAT(slice::check_solid_mesh(solid, "solid"), WithinRel(7.5, 1e-12));
  const slice::MeshInside inside(solid);
  CHECK(inside({0.6, 0.3, 2.3}));  // h(0.6, 0.3) = 2.2
  CHECK_FALSE(inside({0.6, 0.3, 2.1}));

  // A U (3 x 3 unit squares but the top middle one) at z = 1: its border is not star-shaped
  // about its centre, so the lid is the surface lifted; the solid up to z = 3 holds 8 x 2.
  slice::TriangleMesh u;
  for (int k = 0; k < 16; ++k) u.vertices.emplace_back(k % 4, k / 4, 1);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      if (!(i == 1 && j == 2)) {
        const std::int64_t sw = 4 * j + i;
        u.triangles.push_back({sw, sw + 1, sw + 5});
        u.triangles.push_back({sw, sw + 5, sw + 4});
      }
  const std::vector<Vec2> u_plan = {{0, 0}, {3, 0}, {3, 2}, {0, 2}};  // the U's bottom part
  const slice::TriangleMesh u_solid =
      slice::solid_above(slice::check_height_field(u, u_plan, 1e-9, "u"), 3);
  CHECK(u_solid.triangles.size() == 16 + 16 + 2 * 14);
  CHECK_THAT(slice::check_solid_mesh(u_solid, "u"), WithinRel(16.0, 1e-12));

  // A second sheet over part of the square, not joined to it: z is not a function there.
  slice::TriangleMesh two = square();
  two.vertices.push_back({0.2, 0.1, 9});
  two.vertices.push_back({0.9, 0.1, 9});
  two.vertices.push_back({0.9, 0.8, 9});
  two.triangles.push_back({4, 5, 6});
  CHECK_THAT(test::error_of([&] { slice::check_height_field(two, kUnit, 1e-9, "s"); }),
             Contains("triangles") && Contains("overlap in plan"));
  // A domain a little wider than the surface: refused with the border edge inside it.
  const std::vector<Vec2> wide = {{0, 0}, {1.001, 0}, {1.001, 1}, {0, 1}};
  CHECK_THAT(test::error_of([&] { slice::check_height_field(square(), wide, 1e-9, "s"); }),
             Contains("does not cover") && Contains("(1, 0) to (1, 1)"));
  // Wider by less than the tolerance: accepted.
  const std::vector<Vec2> within = {{0, 0}, {1 + 1e-10, 0}, {1 + 1e-10, 1}, {0, 1}};
  CHECK_NOTHROW(slice::check_height_field(square(), within, 1e-9, "s"));
  // A surface beside the domain.
  const std::vector<Vec2> beside = {{5, 5}, {6, 5}, {6, 6}, {5, 6}};
  CHECK_THAT(test::error_of([&] { slice::check_height_field(square(), beside, 1e-9, "s"); }),
             Contains("misses the domain's centre"));
}

TEST_CASE("crop_surface: the triangles over the plan, one sheet edge to edge", "[unit][surface]") {
  // A fan about v = (3, 0.5), outside the plan [0, 1] x [0, 1]: t1 and t3 reach into it, t2
  // between them does not. Kept alone, t1 and t3 would meet at v only: t2 comes back.
  slice::TriangleMesh fan;
  fan.vertices = {{3, 0.5, 1}, {0.5, 0.2, 1}, {2, 0.4, 1}, {2, 0.6, 1}, {0.5, 0.8, 1}};
  fan.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}};
  const slice::CroppedSurface all = slice::crop_surface(fan, {0, 0}, {1, 1});
  CHECK(all.numbers == std::vector<std::int64_t>{1, 2, 3});
  // Without t3, t2 is dropped, and the vertex only it used (3) with it.
  slice::TriangleMesh two = fan;
  two.triangles.pop_back();
  const slice::CroppedSurface one = slice::crop_surface(two, {0, 0}, {1, 1});
  CHECK(one.numbers == std::vector<std::int64_t>{1});
  CHECK(one.mesh.vertices.size() == 3);
  CHECK(one.mesh.triangles[0] == std::array<std::int64_t, 3>{0, 1, 2});
  // A fold far from the plan is cropped away; messages name the file's triangle numbers.
  slice::TriangleMesh far = square();
  far.vertices.push_back({5.2, 0.1, 9});
  far.vertices.push_back({5.9, 0.1, 9});
  far.vertices.push_back({5.9, 0.8, 9});
  far.vertices.push_back({5.1, 0.2, 8});
  far.vertices.push_back({5.9, 0.3, 8});
  far.vertices.push_back({5.5, 0.9, 8});
  far.triangles.insert(far.triangles.begin(), {{4, 5, 6}, {7, 8, 9}});  // two sheets at x ~ 5.5
  CHECK_THAT(test::error_of([&] { slice::check_height_field(far, kUnit, 1e-9, "s"); }),
             Contains("triangles 1 and 2 overlap in plan"));
  const slice::CroppedSurface near = slice::crop_surface(far, {-0.1, -0.1}, {1.1, 1.1});
  CHECK(near.numbers == std::vector<std::int64_t>{3, 4});
  CHECK_NOTHROW(slice::check_height_field(near.mesh, kUnit, 1e-9, "s", near.numbers));
  // Within the plan the fold is still refused, by the file's numbers.
  const slice::CroppedSurface wide = slice::crop_surface(far, {-0.1, -0.1}, {6, 1.1});
  CHECK_THAT(
      test::error_of([&] { slice::check_height_field(wide.mesh, kUnit, 1e-9, "s", wide.numbers); }),
      Contains("triangles 1 and 2 overlap in plan"));
}

TEST_CASE("plan_hull: a box's plan, counter-clockwise", "[unit][surface]") {
  std::vector<Vec3> box;
  for (int k = 0; k < 8; ++k) box.emplace_back(k & 1 ? 4 : 1, k & 2 ? 3 : 2, k & 4 ? 7 : 0);
  box.emplace_back(2, 2.5, 3);  // inside
  const std::vector<Vec2> h = slice::plan_hull(box);
  REQUIRE(h.size() == 4);
  double area = 0;
  for (std::size_t k = 0; k < h.size(); ++k) {
    const Vec2 &a = h[k], &b = h[(k + 1) % h.size()];
    area += (a.x() * b.y() - b.x() * a.y()) / 2;
  }
  CHECK(area == 3);
}

TEST_CASE("surface zones in scenes: 3-D only, one shape a zone", "[unit][surface]") {
  const auto error = [](const std::string& domain, const std::string& zone) {
    return test::error_of([&] { slice::parse_scene(domain + "[[zones]]\n" + zone, "s.toml"); });
  };
  const std::string d3 = "[domain]\nbox = { min = [0, 0, 0], max = [1, 1, 1] }\n";
  const std::string d2 = "[scene]\ndimension = 2\n[domain]\nbox = { min = [0, 0], max = [1, 1] }\n";
  CHECK_THAT(error(d2, "surface = \"t.asc\"\n"), Contains("surface zone is 3-D"));
  CHECK_THAT(error(d3, "surface = \"t.asc\"\nmesh = \"m.obj\"\n"),
             Contains("both 'mesh' and 'surface'"));
  CHECK_THAT(error(d3, "surface = \"t.asc\"\nbox = { min = [0, 0, 0], max = [1, 1, 1] }\n"),
             Contains("both 'surface' and 'box'"));
  CHECK_THAT(error(d3, "surface = \"nowhere.asc\"\n"),
             Contains("nowhere.asc") && Contains("not a file"));
}

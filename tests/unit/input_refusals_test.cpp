// Issue 42 items 8-10: inputs that passed unchecked and gave an empty or wrong result, or ran for
// minutes before any refusal. Each is now refused with one line naming the option or the scene
// line; a value just inside the limit still works.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/export_3dec.hpp"
#include "slice/export_yade.hpp"
#include "slice/extract.hpp"
#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "slice/vertices.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using slice::Vec3;

namespace {

// [0, 4] x [0, 1] x [0, 1] cut by x = 1, 2, 3 into four unit cubes, with geometry; all of it
// scaled by `s` (their contacts are s^2 m2).
slice::BlockSystem four_cubes(int s = 1) {
  const std::string S = std::to_string(s);
  std::string scene = "[domain]\nbox = { min = [0, 0, 0], max = [" + std::to_string(4 * s) + ", " +
                      S + ", " + S + "] }\n";
  for (int x = 1; x <= 3; ++x)
    scene +=
        "[[joints]]\ndip = 90\ndip_direction = 90\npoint = [" + std::to_string(x * s) + ", 0, 0]\n";
  auto r = slice::cut_blocks(slice::generate_joints(slice::parse_scene(scene, "row.toml")), {});
  slice::prune_blocks(r.blocks, slice::LpBackend::native);
  slice::compute_geometry(r.blocks);
  return std::move(r.blocks);
}

// An ESRI ASCII grid of cell size 1 whose centres run from -1.5 to n - 2.5 in x and y (so it
// covers a domain [0, n - 4]^2 with half a cell to spare), heights z(x, y).
template <class Height>
std::string grid(int n, const Height& z) {
  std::ostringstream s;
  s.precision(17);
  s << "ncols " << n << "\nnrows " << n << "\nxllcorner -2\nyllcorner -2\ncellsize 1\n";
  for (int row = 0; row < n; ++row) {  // north first
    const double y = n - 2.5 - row;
    for (int col = 0; col < n; ++col) s << (col ? " " : "") << z(-1.5 + col, y);
    s << "\n";
  }
  return s.str();
}

// The error of loading tmp/s.toml (domain [0, 10]^2 x [0, 10], the surface t.asc), or "".
std::string surface_error(const test::TempDir& tmp, const std::string& asc,
                          const std::string& zone_extra, const std::string& options = "") {
  test::write_text(tmp / "t.asc", asc);
  test::write_text(tmp / "s.toml", "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n" +
                                       options + "[[zones]]\nsurface = \"t.asc\"\n" + zone_extra);
  return test::error_of([&] { (void)slice::load_scene(tmp / "s.toml"); });
}

}  // namespace

TEST_CASE("a surface on or below the whole domain is refused, as one above it is",
          "[unit][surface][refusals]") {
  test::TempDir tmp;
  const auto flat = [](double h) { return [h](double, double) { return h; }; };
  for (const std::string cut : {"cut = false\n", "cut = true\n"}) {
    CAPTURE(cut);
    // Below everywhere, and on the domain's base: it would remove all of the rock.
    for (const double h : {-5.0, 0.0}) {
      CAPTURE(h);
      const std::string e = surface_error(tmp, grid(14, flat(h)), cut);
      CHECK_THAT(e, Contains("s.toml:") && Contains("below the domain everywhere") &&
                        Contains("remove all of it") && Contains("check the surface's heights"));
      CHECK(e.find('\n') == std::string::npos);
    }
    // Above everywhere (refused before), and through the domain (kept).
    CHECK_THAT(surface_error(tmp, grid(14, flat(12)), cut), Contains("remove nothing"));
    CHECK(surface_error(tmp, grid(14, flat(5)), cut).empty());
    // Below the domain but for one corner that rises into it: kept.
    CHECK(surface_error(tmp, grid(14, [](double x, double y) { return x + y > 18 ? 3.0 : -4.0; }),
                        cut)
              .empty());
  }
}

TEST_CASE("a cut surface with more triangles in the domain than max_blocks is refused",
          "[unit][surface][refusals]") {
  test::TempDir tmp;
  // A 64 x 64 grid over a 60 m square: its cells centre on -1.5 .. 61.5, so the domain meets
  // 61 x 61 of them, 7,442 triangles, none coplanar with its neighbours.
  const auto wavy = [](double x, double y) {
    return 5 + 0.3 * std::sin(x) + 0.2 * std::cos(1.3 * y);
  };
  const std::string asc = grid(64, wavy);
  const auto error = [&](const std::string& cut, const std::string& options) {
    test::write_text(tmp / "t.asc", asc);
    test::write_text(tmp / "s.toml", "[domain]\nbox = { min = [0, 0, 0], max = [60, 60, 10] }\n" +
                                         options + "[[zones]]\nsurface = \"t.asc\"\n" + cut);
    return test::error_of([&] { (void)slice::load_scene(tmp / "s.toml"); });
  };
  const std::string e = error("cut = true\n", "[options]\nmax_blocks = 7000\n");
  CHECK_THAT(e, Contains("s.toml:") && Contains("makes 7442 construction joints") &&
                    Contains("more blocks than max_blocks = 7000") &&
                    Contains("resample the surface coarser") &&
                    Contains("raise [options] max_blocks"));
  CHECK(e.find('\n') == std::string::npos);
  // At the limit (7,442 joints, 7,443 blocks at the least), without cut, or the default limit.
  CHECK(error("cut = true\n", "[options]\nmax_blocks = 7443\n").empty());
  CHECK(error("cut = false\n", "[options]\nmax_blocks = 7000\n").empty());
  CHECK(error("cut = true\n", "").empty());
}

TEST_CASE("a --yade-steps past the integers, or a time step of 0 or inf, is refused",
          "[unit][export][refusals]") {
  slice::YadeOptions o;
  o.steps = std::numeric_limits<long>::max();  // what CLI11 makes of 1e20
  CHECK_THAT(test::error_of([&] { o.validate(); }),
             Contains("--yade-steps: is 9223372036854775807, more than 1000000000000000") &&
                 Contains("give a whole number of steps from 0 to 1000000000000000"));
  o.steps = slice::kYadeMaxSteps;
  CHECK_NOTHROW(o.validate());

  const slice::BlockSystem bs = four_cubes();
  test::TempDir tmp;
  o.steps = 0;
  o.young = 1e-308;  // O.dt = 0.2 sqrt(2650 / 1e-308) = inf
  const std::string e = test::error_of([&] { slice::write_yade_script(tmp / "m.py", bs, o); });
  CHECK_THAT(e, Contains("--yade-young 1e-308") && Contains("would be inf s"));
  CHECK_FALSE(test::fs::exists(tmp / "m.py"));
  o.young = 1e9;
  CHECK(slice::write_yade_script(tmp / "m.py", bs, o).timestep > 0);
}

TEST_CASE("a --3dec-jkn so large that the time step is 0 s is refused",
          "[unit][export][refusals]") {
  const slice::BlockSystem bs = four_cubes(2);
  test::TempDir tmp;
  slice::ThreeDecOptions o;
  o.jkn = 1e308;  // times a contact of 4 m2: inf
  const std::string e =
      test::error_of([&] { slice::write_3dec(tmp / "m.3dgrid", tmp / "m.dat", bs, o); });
  CHECK_THAT(e, Contains("--3dec-jkn 1e+308") && Contains("the time step 0 s") &&
                    Contains("give a stiffness and density of the model's order"));
  CHECK(e.find('\n') == std::string::npos);
  CHECK_FALSE(test::fs::exists(tmp / "m.3dgrid"));
  CHECK_FALSE(test::fs::exists(tmp / "m.dat"));
  o.jkn = 1e10;
  CHECK(slice::write_3dec(tmp / "m.3dgrid", tmp / "m.dat", bs, o).critical_timestep > 0);
}

TEST_CASE("a sphere's centre or a cylinder's ends too far for doubles are refused",
          "[unit][extract][refusals]") {
  const slice::BlockSystem bs = four_cubes();
  slice::ExtractOptions o;
  o.region.shape = slice::RegionShape::cylinder;
  o.region.radius = 5;
  // Ends at 1e155, meant as "through everything": the squares of its distances overflowed, and
  // it kept nothing.
  o.region.a = Vec3(-1e155, 0.5, 0.5);
  o.region.b = Vec3(1e155, 0.5, 0.5);
  const std::string e = test::error_of([&] { slice::extract_blocks(bs, o, "row.h5"); });
  CHECK_THAT(e, Contains("--cylinder: the cylinder's axis reaches 1e+155 from the origin, where "
                         "doubles step by") &&
                    Contains("give axis ends a little beyond the blocks"));
  CHECK(e.find('\n') == std::string::npos);
  // Ends a little beyond the blocks take them all.
  o.region.a = Vec3(-10, 0.5, 0.5);
  o.region.b = Vec3(14, 0.5, 0.5);
  CHECK(slice::extract_blocks(bs, o, "row.h5").stats.kept == 4);
  // A sphere: its centre far out is refused; a huge radius about the model is exact, and kept.
  o.region.shape = slice::RegionShape::sphere;
  o.region.a = Vec3(1e200, 0.5, 0.5);
  o.region.radius = 1e200;
  CHECK_THAT(test::error_of([&] { slice::extract_blocks(bs, o, "row.h5"); }),
             Contains("--sphere: the sphere's centre reaches 1e+200"));
  o.region.a = Vec3(2, 0.5, 0.5);
  CHECK(slice::extract_blocks(bs, o, "row.h5").stats.kept == 4);
}

TEST_CASE("a tessellated fracture whose triangles overlap is refused, though the areas add up",
          "[unit][dfn][refusals]") {
  const auto fab = [](const std::string& second_triangle) {
    return "BEGIN FORMAT\n    Format = Ascii\n    XAxis = East\n    Scale = 100.0\n"
           "    No_Fractures = 0\n    No_TessFractures = 1\n    No_Nodes = 4\n"
           "    No_Properties = 1\nEND FORMAT\n\n"
           "BEGIN PROPERTIES\n    Prop1 = (Real*4) \"Transmissivity\"\nEND PROPERTIES\n\n"
           "BEGIN SETS\n    Set1 = \"A\"\nEND SETS\n\n"
           "BEGIN FRACTURE\nEND FRACTURE\n\n"
           "BEGIN TESSFRACTURE\n1 4 2 1\n1 1 1 5\n2 9 1 5\n3 9 9 5\n4 1 9 5\n"
           "1 1 2 3 0 1e-6\n" +
           second_triangle + "\nEND TESSFRACTURE\n";
  };
  test::TempDir tmp;
  const auto error = [&](const std::string& second_triangle) {
    test::write_text(tmp / "t.fab", fab(second_triangle));
    test::write_text(tmp / "s.toml",
                     "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n"
                     "[[dfn]]\nfile = \"t.fab\"\n");
    return test::error_of([&] { (void)slice::load_scene(tmp / "s.toml"); });
  };
  // The square 1-2-3-4 as two triangles: it tiles.
  CHECK(error("2 1 3 4 0 1e-6").empty());
  // The same triangle twice: the areas add up to the square's, half of it is bare.
  const std::string e = error("2 1 2 3 0 1e-6");
  CHECK_THAT(e,
             Contains("t.fab") && Contains("tessellated fracture 1") &&
                 Contains("not one convex polygon") &&
                 Contains("two triangles lie on the same side of the edge from node 1 to node 2"));
  CHECK(e.find('\n') == std::string::npos);
  // The same, turned the other way round: triangles of both orientations (refused before too).
  CHECK_THAT(error("2 3 2 1 0 1e-6"), Contains("not one convex polygon"));
}

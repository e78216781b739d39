// [[zones]] surface: topography (an open TIN as OBJ or STL, an ESRI ASCII grid) removes the
// rock above it, through the real tools (docs/topography.md). With cut = true the kept rock is
// exactly the rock below the piecewise-linear surface: its volume, computed here triangle by
// triangle from the test's own triangles, matches the blocks' to 1e-9.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "slice/h5io.hpp"
#include "slice/mesh.hpp"
#include "slice/surface.hpp"
#include "slice/vertices.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"
#include "support/surface_volume.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using slice::Vec2;
using slice::Vec3;
using test::column_volume;
using test::run_tool;

namespace {

using Tri = std::array<Vec3, 3>;

// The surface's height at (x, y), from the triangle that holds it in plan; NAN if none does.
double height_at(const std::vector<Tri>& surface, const Vec2& p) {
  for (const Tri& t : surface) {
    const auto cross = [](const Vec3& a, const Vec3& b, const Vec2& c) {
      return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    };
    const double area = cross(t[0], t[1], Vec2(t[2].x(), t[2].y()));
    const double l0 = cross(t[1], t[2], p) / area, l1 = cross(t[2], t[0], p) / area,
                 l2 = cross(t[0], t[1], p) / area;
    if (l0 >= 0 && l1 >= 0 && l2 >= 0) return l0 * t[0].z() + l1 * t[1].z() + l2 * t[2].z();
  }
  return NAN;
}

std::string scene(const std::string& box, const std::string& zone) {
  return test::surface_scene("topo", box, zone);
}

struct Result {
  double kept = 0, removed = 0;
  std::size_t blocks = 0, misplaced = 0;  // removed unless the centre is below the surface
};

// Scene -> joints -> cut -> vertices; the blocks' volumes, and whether each block's removal
// agrees with its centre's side of `surface`.
Result run(const test::TempDir& tmp, const std::string& text, const std::vector<Tri>& surface) {
  test::write_text(tmp / "s.toml", text);
  const auto j = (tmp / "j.h5").string(), b = (tmp / "b.h5").string(), g = (tmp / "g.h5").string();
  const auto r = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", j});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  REQUIRE(run_tool("slice-cut", {j, "-o", b, "--prune"}).exit_code == 0);
  REQUIRE(run_tool("slice-vertices", {b, "-o", g}).exit_code == 0);
  const auto bs = slice::read_blocks(g);
  Result out;
  out.blocks = bs.blocks.size();
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    const bool removed = bs.blocks[i].flags & slice::kRemoved;
    (removed ? out.removed : out.kept) += bs.geometry->volume[i];
    const Vec3& o = bs.blocks[i].origin;
    out.misplaced += removed != (o.z() > height_at(surface, {o.x(), o.y()})) ? 1 : 0;
  }
  return out;
}

std::string g17(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// A random TIN over [0, 20] x [0, 16] (the domain's plan): an nx x ny grid of nodes, the inner
// ones moved by up to a fifth of a cell, the border ones along the border, heights in
// [zlo, zhi], each quad split by a random diagonal, each triangle's corners in random order
// (some clockwise from above).
struct Tin {
  std::vector<Vec3> nodes;
  std::vector<std::array<int, 3>> faces;
  std::vector<Tri> triangles() const {
    std::vector<Tri> out;
    for (const auto& f : faces) out.push_back({nodes[f[0]], nodes[f[1]], nodes[f[2]]});
    return out;
  }
  std::string obj() const {
    std::string s = "# a random TIN\n";
    for (const Vec3& x : nodes) s += "v " + g17(x.x()) + " " + g17(x.y()) + " " + g17(x.z()) + "\n";
    for (const auto& f : faces)
      s += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
           std::to_string(f[2] + 1) + "\n";
    return s;
  }
};

Tin random_tin(std::mt19937_64& rng, int nx, int ny, double zlo, double zhi) {
  std::uniform_real_distribution<double> u(-1, 1), height(zlo, zhi);
  Tin t;
  const double cx = 20.0 / (nx - 1), cy = 16.0 / (ny - 1);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      double x = i * cx, y = j * cy;
      if (i > 0 && i < nx - 1) x += 0.2 * cx * u(rng);
      if (j > 0 && j < ny - 1) y += 0.2 * cy * u(rng);
      t.nodes.emplace_back(x, y, height(rng));
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int sw = j * nx + i, se = sw + 1, nw = sw + nx, ne = nw + 1;
      std::array<std::array<int, 3>, 2> two =
          u(rng) > 0 ? std::array<std::array<int, 3>, 2>{{{sw, se, ne}, {sw, ne, nw}}}
                     : std::array<std::array<int, 3>, 2>{{{sw, se, nw}, {se, ne, nw}}};
      for (auto f : two) {
        if (u(rng) > 0) std::swap(f[1], f[2]);
        t.faces.push_back(f);
      }
    }
  return t;
}

const char* kBox = "{ min = [0, 0, 0], max = [20, 16, 12] }";
constexpr double kBoxVolume = 20.0 * 16 * 12;

double volume_under(const std::vector<Tri>& surface, double z0, double z1) {
  double v = 0;
  for (const Tri& t : surface) v += column_volume(t, z0, z1);
  return v;
}

// An ESRI ASCII grid of 9 x 7 cells of 5 m, centres x = 0..40, y = 0..30, a no-data value in
// each corner, heights from the seed; `corner`: registered by xllcorner (-2.5), else xllcenter.
struct Grid {
  std::vector<std::vector<double>> z;  // [row from the north][column]
  std::string text(bool corner) const {
    std::ostringstream s;
    s << "ncols 9\nnrows 7\n"
      << (corner ? "xllcorner -2.5\nyllcorner -2.5\n" : "XLLCENTER 0\nYLLCENTER 0\n")
      << "cellsize 5\nNODATA_value -9999\n";
    for (const auto& row : z) {
      for (const double v : row) s << " " << g17(v);
      s << "\n";
    }
    return s.str();
  }
  // The triangles of the cells inside [5, 35] x [5, 25], split SW-NE.
  std::vector<Tri> triangles() const {
    const auto at = [&](int row, int col) { return Vec3(5.0 * col, 5.0 * (6 - row), z[row][col]); };
    std::vector<Tri> out;
    for (int row = 1; row < 5; ++row)
      for (int col = 1; col < 7; ++col) {
        const Vec3 sw = at(row + 1, col), se = at(row + 1, col + 1), ne = at(row, col + 1),
                   nw = at(row, col);
        out.push_back({sw, se, ne});
        out.push_back({sw, ne, nw});
      }
    return out;
  }
};

Grid random_grid(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> height(6, 24);
  Grid g;
  g.z.assign(7, std::vector<double>(9));
  for (auto& row : g.z)
    for (double& v : row) v = height(rng);
  g.z[0][0] = g.z[0][8] = g.z[6][0] = g.z[6][8] = -9999;  // outside the domain: no matter
  return g;
}

const char* kGridBox = "{ min = [5, 5, 0], max = [35, 25, 20] }";
constexpr double kGridBoxVolume = 30.0 * 20 * 20;

}  // namespace

TEST_CASE("a cut TIN surface keeps exactly the rock below it (random TINs, OBJ and STL)",
          "[tools][zones][surface]") {
  const long cases = test::scaled_cases(8);
  for (long c = 0; c < cases; ++c) {
    std::mt19937_64 rng(std::uint64_t(2026 + c));
    const int nx = 3 + int(c % 3), ny = 3 + int((c / 3) % 2);
    // Heights from 4 to 14: some of the surface above the domain's top (12).
    const Tin tin = random_tin(rng, nx, ny, 4, 14);
    const std::vector<Tri> tris = tin.triangles();
    CAPTURE(c, nx, ny);
    test::TempDir tmp;
    std::string zone;
    if (c % 2 == 0) {
      test::write_text(tmp / "topo.obj", tin.obj());
      zone = "surface = \"topo.obj\"\ncut = true";
    } else {
      slice::TriangleMesh m;
      m.vertices = tin.nodes;
      for (const auto& f : tin.faces) m.triangles.push_back({f[0], f[1], f[2]});
      test::write_text(tmp / "topo.stl", test::ascii_stl(m));
      zone = "surface = \"topo.stl\"\ncut = true";
    }
    const Result r = run(tmp, scene(kBox, zone), tris);
    const double exact = volume_under(tris, 0, 12);
    CHECK(r.blocks > 10);
    CHECK_THAT(r.kept, WithinRel(exact, 1e-9));
    CHECK_THAT(r.kept + r.removed, WithinRel(kBoxVolume, 1e-9));
    CHECK(r.misplaced == 0);
  }
}

TEST_CASE("a TIN that folds outside the domain's plan is cropped: the rock below it is kept",
          "[tools][zones][surface]") {
  // A TIN over [0, 20] x [0, 16]; the domain's plan is [0, 10] x [0, 8]. Node (i 4, j 2), near
  // (16, 8), pushed 6 m East past the border nodes: the triangles about it fold over, but lie
  // beyond x = 11.2, outside the domain's plan and its margin (5 % of its diagonal, 0.64 m).
  std::mt19937_64 rng(99);
  Tin tin = random_tin(rng, 6, 5, 4, 10);
  tin.nodes[2 * 6 + 4].x() += 6;
  test::TempDir tmp;
  test::write_text(tmp / "topo.obj", tin.obj());
  const std::string box = "{ min = [0, 0, 0], max = [10, 8, 12] }";
  // The whole surface is refused: slice-joints checks only what it keeps.
  const auto whole = slice::read_mesh(tmp / "topo.obj");
  CHECK_THAT(test::error_of([&] {
               slice::check_height_field(
                   whole, std::vector<Vec2>{{0, 0}, {20, 0}, {20, 16}, {0, 16}}, 1e-9, "topo.obj");
             }),
             Contains("overlap in plan"));
  // The triangles over the domain, clipped to its plan, give the exact volume under them.
  std::vector<Tri> inside;
  for (const Tri& t : tin.triangles()) {
    std::vector<Vec3> p(t.begin(), t.end());
    for (const slice::Plane& h : {slice::Plane{Vec3::UnitX(), 10}, slice::Plane{Vec3::UnitY(), 8}})
      if (p.size() >= 3) p = slice::clip_polygon(p, h);
    for (std::size_t k = 1; p.size() >= 3 && k + 1 < p.size(); ++k)
      inside.push_back({p[0], p[k], p[k + 1]});
  }
  const Result r = run(tmp, scene(box, "surface = \"topo.obj\"\ncut = true"), tin.triangles());
  CHECK(r.blocks > 5);
  CHECK_THAT(r.kept, WithinRel(volume_under(inside, 0, 12), 1e-9));
  CHECK_THAT(r.kept + r.removed, WithinRel(10.0 * 8 * 12, 1e-9));
  CHECK(r.misplaced == 0);
}

TEST_CASE("an ESRI ASCII grid surface: centres, the SW-NE diagonal, no-data outside the domain",
          "[tools][zones][surface]") {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    CAPTURE(seed);
    const Grid grid = random_grid(seed);
    const std::vector<Tri> tris = grid.triangles();
    const double exact = volume_under(tris, 0, 20);
    test::TempDir tmp;
    test::write_text(tmp / "corner.asc", grid.text(true));
    test::write_text(tmp / "centre.asc", grid.text(false));
    const Result a = run(tmp, scene(kGridBox, "surface = \"corner.asc\"\ncut = true"), tris);
    CHECK_THAT(a.kept, WithinRel(exact, 1e-9));
    CHECK_THAT(a.kept + a.removed, WithinRel(kGridBoxVolume, 1e-9));
    CHECK(a.misplaced == 0);
    // xllcenter = xllcorner + half a cell: the same surface, the same blocks.
    const Result b = run(tmp, scene(kGridBox, "surface = \"centre.asc\"\ncut = true"), tris);
    CHECK(a.blocks == b.blocks);
    CHECK(a.kept == b.kept);
    // Without the cut blocks straddle the surface; each is removed by its centre's side.
    const Result plain = run(tmp, scene(kGridBox, "surface = \"corner.asc\""), tris);
    CHECK(plain.misplaced == 0);
    CHECK(std::abs(plain.kept - exact) > 1.0);
  }
}

TEST_CASE("data/topo-slope.toml keeps exactly the rock below its bundled grid",
          "[tools][zones][surface]") {
  test::TempDir tmp;
  const std::string g = test::run_pipeline(tmp, "topo-slope.toml", test::Stage::geometry);
  const auto bs = slice::read_blocks(g);
  double kept = 0;
  for (std::size_t i = 0; i < bs.blocks.size(); ++i)
    if (!(bs.blocks[i].flags & slice::kRemoved)) kept += bs.geometry->volume[i];
  // The grid's triangles over the domain, from the file as the test reads it.
  std::istringstream in(test::read_bytes(test::data_path("topo-slope.asc")));
  std::string key;
  double ncols = 0, nrows = 0, x0 = 0, y0 = 0, cell = 0, nodata = 0;
  in >> key >> ncols >> key >> nrows >> key >> x0 >> key >> y0 >> key >> cell >> key >> nodata;
  std::vector<std::vector<double>> z(static_cast<std::size_t>(nrows),
                                     std::vector<double>(static_cast<std::size_t>(ncols)));
  for (auto& row : z)
    for (double& v : row) in >> v;
  REQUIRE(in);
  x0 += cell / 2, y0 += cell / 2;  // xllcorner, yllcorner: centres half a cell in
  const auto at = [&](std::size_t row, std::size_t col) {
    return Vec3(x0 + cell * double(col), y0 + cell * (nrows - 1 - double(row)), z[row][col]);
  };
  std::vector<Tri> tris;
  for (std::size_t row = 0; row + 1 < z.size(); ++row)
    for (std::size_t col = 0; col + 1 < z[row].size(); ++col) {
      const Vec3 sw = at(row + 1, col), se = at(row + 1, col + 1), ne = at(row, col + 1),
                 nw = at(row, col);
      // The domain is [0, 60] x [0, 40] in plan: the cells inside it.
      if (sw.x() < 0 || sw.y() < 0 || ne.x() > 60 || ne.y() > 40) continue;
      tris.push_back({sw, se, ne});
      tris.push_back({sw, ne, nw});
    }
  CHECK_THAT(kept, WithinRel(volume_under(tris, 0, 40), 1e-9));
}

TEST_CASE("bad surface zones are refused by slice-joints with one line, nothing written",
          "[tools][zones][surface]") {
  test::TempDir tmp;
  std::mt19937_64 rng(7);
  const Tin tin = random_tin(rng, 4, 4, 4, 10);
  Tin holed = tin;
  holed.faces.erase(holed.faces.begin() + 8);  // an inner triangle: a hole in the middle
  Tin folded = tin;
  folded.nodes[5].x() += 9;  // an inner node pushed past its neighbours: triangles fold over
  Tin cliff = tin;           // a vertical triangle on the border edge y = 0
  cliff.nodes.emplace_back(0, 0, 20);
  cliff.faces.push_back({0, 1, int(cliff.nodes.size()) - 1});
  Tin high = tin;
  for (Vec3& x : high.nodes) x.z() += 20;
  Grid grid = random_grid(1);
  Grid gap = grid;
  gap.z[3][4] = -9999;  // row 4, column 5: inside the domain
  const std::string ok = grid.text(true);
  const auto replace = [](std::string s, const std::string& a, const std::string& b) {
    return s.replace(s.find(a), a.size(), b);
  };
  struct Case {
    std::string file, text, box;
    std::vector<std::string> words;
  };
  const std::string big = "{ min = [-1, 0, 0], max = [20, 16, 12] }";
  const std::vector<Case> cases = {
      {"small.obj", tin.obj(), big, {"does not cover the domain", "(0, 0)"}},
      {"holed.obj", holed.obj(), kBox, {"does not cover the domain", "a hole"}},
      {"folded.obj", folded.obj(), kBox, {"overlap in plan", "overhang"}},
      {"cliff.obj", cliff.obj(), kBox, {"vertical"}},
      {"high.obj", high.obj(), kBox, {"remove nothing"}},
      {"gap.asc", gap.text(true), kGridBox, {"gap.asc:10", "row 4, column 5", "no-data"}},
      {"wide.asc", ok, "{ min = [-1, 5, 0], max = [35, 25, 20] }", {"cell centres span"}},
      {"noncols.asc", replace(ok, "ncols 9\n", ""), kGridBox, {"no ncols"}},
      {"both.asc",
       replace(ok, "cellsize 5\n", "cellsize 5\nxllcenter 0\n"),
       kGridBox,
       {"both xllcorner and xllcenter"}},
      {"short.asc", ok.substr(0, ok.rfind(' ')), kGridBox, {"short.asc:13", "ends after 62"}},
      {"long.asc", ok + "1\n", kGridBox, {"long.asc:14", "more than the 7 x 9"}},
      {"word.asc",
       replace(ok, "\n ", "\n 1.2.3 "),
       kGridBox,
       {"word.asc:7", "\"1.2.3\" is not a number"}},
      {"huge.asc",
       replace(ok, "ncols 9\nnrows 7", "ncols 300\nnrows 70"),
       kGridBox,
       {"huge.asc:2", "more than the file's"}},
      {"topo.txt", ok, kGridBox, {"not .stl, .obj, .asc, .tif or .tiff"}},
  };
  for (const auto& c : cases) {
    CAPTURE(c.file);
    test::write_text(tmp / c.file, c.text);
    test::write_text(tmp / "s.toml", scene(c.box, "surface = \"" + c.file + "\""));
    const auto out = (tmp / "j.h5").string();
    std::vector<std::string> words = c.words;
    words.push_back("s.toml:");
    test::check_refused(run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", out}),
                        "slice-joints", words);
    CHECK_FALSE(test::fs::exists(out));
  }
  // The surface is an input: -o onto it is refused, and it is left as it was.
  test::write_text(tmp / "topo.asc", ok);
  test::write_text(tmp / "s.toml", scene(kGridBox, "surface = \"topo.asc\""));
  const auto r =
      run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", (tmp / "topo.asc").string()});
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("surface"));
  CHECK(test::read_bytes(tmp / "topo.asc") == ok);
}

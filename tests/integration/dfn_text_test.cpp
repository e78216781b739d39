// The text inputs of a scene (FAB and CSV DFN files, ESRI ASCII grids, the scene's names) as
// issue 42 (items 5, 6, 11, 14) found them: text that is no UTF-8 or holds a NUL refused where
// it is read, tessellated fractures whose triangles overlap, DFN files too big, far or huge
// fractures and discs named by their file's line, byte-order marks and CR-only line ends.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using test::run_tool;

namespace {

const char* kHead = R"([scene]
name = "text"
[domain]
box = { min = [0, 0, 0], max = [10, 10, 10] }
)";

// Two fractures in the sets `a` and `b` (the names as given, in quotes).
std::string fab(const std::string& a = "A", const std::string& b = "B") {
  return "BEGIN FORMAT\n    Format = Ascii\n    XAxis = East\n    No_Fractures = 2\n"
         "    No_Nodes = 8\n    No_Properties = 0\nEND FORMAT\n"
         "BEGIN SETS\n    Set1 = \"" +
         a + "\"\n    Set2 = \"" + b +
         "\"\nEND SETS\n"
         "BEGIN FRACTURE\n"
         "1 4 1\n1 1 1 3\n2 8 1 3\n3 8 8 3\n4 1 8 3\n0 0 0 1\n"
         "2 4 2\n1 5 1 1\n2 5 9 1\n3 5 9 9\n4 5 1 9\n0 1 0 0\n"
         "END FRACTURE\n";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// Every CR LF and LF of `text` as one CR.
std::string cr_only(std::string text) {
  std::string out;
  for (const char c : text)
    if (c != '\r') out += c == '\n' ? '\r' : c;
  return out;
}

struct Run {
  int exit_code;
  std::string err;
};

// slice-joints on the scene `scene` (written to tmp / scene_name); nothing may be written when
// it fails, and a failure is one line.
Run joints(const test::TempDir& tmp, const std::string& scene,
           const std::string& scene_name = "s.toml") {
  test::write_text(tmp / scene_name, scene);
  const auto out = tmp / "j.h5";
  std::filesystem::remove(out);
  const auto r = run_tool("slice-joints", {(tmp / scene_name).string(), "-o", out.string()});
  if (r.exit_code != 0) {
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(std::filesystem::exists(out));
  }
  return {r.exit_code, r.err};
}

Run dfn_scene(const test::TempDir& tmp, const std::string& file) {
  return joints(tmp, std::string(kHead) + "[[dfn]]\nfile = \"" + file + "\"\n");
}

// A 3 x 3 grid of 10 m cells whose centres span [0, 20] in x and y at height `z`.
std::string grid(const std::string& z = "8") {
  std::string s = "ncols 3\nnrows 3\nxllcorner -5\nyllcorner -5\ncellsize 10\n";
  for (int r = 0; r < 3; ++r) s += z + " " + z + " " + z + "\n";
  return s;
}

Run grid_scene(const test::TempDir& tmp) {
  return joints(tmp, std::string(kHead) + "[[zones]]\nsurface = \"g.asc\"\n");
}

}  // namespace

TEST_CASE("names that are no UTF-8 text are refused where they are read", "[tools][dfn][text]") {
  test::TempDir tmp;
  SECTION("a Latin-1 set name in a FAB file") {
    test::write_text(tmp / "net.fab", fab("J\xe9"));
    const Run r = dfn_scene(tmp, "net.fab");
    CAPTURE(r.err);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("net.fab:9:") && Contains("not UTF-8") && Contains("iconv"));
  }
  SECTION("a Latin-1 set name in a CSV file") {
    test::write_text(tmp / "d.csv", "x,y,z,dip,dip_direction,radius,set\n5,5,5,0,0,2,n\xf6rd\n");
    const Run r = dfn_scene(tmp, "d.csv");
    CAPTURE(r.err);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("d.csv:2:") && Contains("not UTF-8"));
  }
  SECTION("a scene named after a Latin-1 file name") {
    const std::string body =
        "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n[[joints]]\ndip = 0\n"
        "dip_direction = 0\npoint = [5, 5, 5]\n";
    Run r = joints(tmp, body, "sc\xe8ne.toml");
    CAPTURE(r.err);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("not UTF-8") && Contains("[scene] name"));
    // Named in the scene, it is read, and slice-info reads what it wrote (its --json of the
    // provenance, which holds the file's name as typed, is the JSON writer's business).
    r = joints(tmp, "[scene]\nname = \"sc\xc3\xa8ne\"\n" + body, "sc\xe8ne.toml");
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const auto info = run_tool("slice-info", {(tmp / "j.h5").string()});
    CAPTURE(info.err);
    CHECK(info.exit_code == 0);
    CHECK_THAT(info.out, Contains("sc\xc3\xa8ne"));
  }
}

TEST_CASE("a NUL in a scene or set name is refused where it is read", "[tools][dfn][text]") {
  test::TempDir tmp;
  const std::string domain = "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n";
  const std::string joint = "[[joints]]\ndip = 0\ndip_direction = 0\npoint = [5, 5, 5]\n";
  struct Case {
    std::string name, scene, where;
  };
  test::write_text(tmp / "nul.fab", fab(std::string("a\0b", 3)));
  static const char kNulCsv[] = "x,y,z,dip,dip_direction,radius,set\n5,5,5,0,0,2,a\0b\n";
  test::write_text(tmp / "nul.csv", std::string(kNulCsv, sizeof kNulCsv - 1));
  const std::vector<Case> cases = {
      {"scene", "[scene]\nname = \"a\\u0000b\"\n" + domain + joint, "s.toml:2:"},
      {"sets", domain + "[[sets]]\nname = \"a\\u0000b\"\ndip = 0\ndip_direction = 0\nspacing = 5\n",
       "s.toml:4:"},
      {"joints set", domain + joint + "set = \"a\\u0000b\"\n", "s.toml:7:"},
      {"fab", domain + "[[dfn]]\nfile = \"nul.fab\"\n", "nul.fab:9:"},
      {"csv", domain + "[[dfn]]\nfile = \"nul.csv\"\n", "nul.csv:2:"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const Run r = joints(tmp, c.scene);
    CAPTURE(r.err);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains(c.where) && Contains("NUL"));
    CHECK_THAT(r.err, !Contains("disk") && !Contains("HDF5") && !Contains(".partial"));
  }
}

TEST_CASE("a tessellated fracture whose triangles overlap is refused", "[tools][dfn]") {
  test::TempDir tmp;
  // The square (0..2)^2 at z = 5 from five nodes, P = (1, 0) on its edge: A B C (area 2) and
  // P C D (area 2) add up to the square's 4 and run no edge twice, but they overlap (a third
  // of the square is covered twice) and leave as much bare by the edge D A.
  const auto tess = [](const std::string& faces, int n) {
    return "BEGIN FORMAT\nFormat = Ascii\nNo_Fractures = 0\nNo_TessFractures = 1\nEND FORMAT\n"
           "BEGIN FRACTURE\nEND FRACTURE\nBEGIN TESSFRACTURE\n1 5 " +
           std::to_string(n) + " 1\n1 3 3 5\n2 5 3 5\n3 5 5 5\n4 3 5 5\n5 4 3 5\n" + faces +
           "END TESSFRACTURE\n";
  };
  test::write_text(tmp / "over.fab", tess("1 1 2 3 0\n2 5 3 4 0\n", 2));
  Run r = dfn_scene(tmp, "over.fab");
  CAPTURE(r.err);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("over.fab:9:") && Contains("tessellated fracture 1") &&
                        Contains("face lines 1 and 2 overlap"));
  // The same square as two triangles that tile it, and as four about P: read.
  test::write_text(tmp / "tile.fab", tess("1 1 2 3 0\n2 1 3 4 0\n", 2));
  r = dfn_scene(tmp, "tile.fab");
  CAPTURE(r.err);
  CHECK(r.exit_code == 0);
  test::write_text(tmp / "fan.fab", tess("1 5 2 3 0\n2 5 3 4 0\n3 5 4 1 0\n", 3));
  r = dfn_scene(tmp, "fan.fab");
  CAPTURE(r.err);
  CHECK(r.exit_code == 0);

  // A mesh of 128 x 128 cells (32,768 triangles) on a tilted plane: every neighbour shares an
  // edge or a corner, none overlaps; read.
  const int n = 129;  // 128 x 128 cells of 1/16 m: every coordinate is exact in the file
  std::string nodes, faces;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = 1 + 0.0625 * i, y = 1 + 0.0625 * j;
      nodes += std::to_string(j * n + i + 1) + " " + std::to_string(x) + " " + std::to_string(y) +
               " " + std::to_string(2 + 0.25 * x) + "\n";
    }
  int f = 0;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i + 1, b = a + 1, c = a + n + 1, d = a + n;
      faces += std::to_string(++f) + " " + std::to_string(a) + " " + std::to_string(b) + " " +
               std::to_string(c) + " 0\n";
      faces += std::to_string(++f) + " " + std::to_string(a) + " " + std::to_string(c) + " " +
               std::to_string(d) + " 0\n";
    }
  const std::string head =
      "BEGIN FORMAT\nFormat = Ascii\nNo_Fractures = 0\nEND FORMAT\n"
      "BEGIN FRACTURE\nEND FRACTURE\nBEGIN TESSFRACTURE\n1 " +
      std::to_string(n * n) + " " + std::to_string(f) + " 1\n";
  test::write_text(tmp / "mesh.fab", head + nodes + faces + "END TESSFRACTURE\n");
  r = dfn_scene(tmp, "mesh.fab");
  CAPTURE(r.err);
  CHECK(r.exit_code == 0);
}

TEST_CASE("DFN files over 256 MiB are refused by their size, before they are read",
          "[tools][dfn]") {
  test::TempDir tmp;
  for (const std::string name : {"big.fab", "big.csv"}) {
    CAPTURE(name);
    test::write_text(tmp / name, name == "big.fab" ? fab() : "x,y,z,dip,dip_direction,radius\n");
    std::filesystem::resize_file(tmp / name, std::uintmax_t(300) << 20);  // sparse: no disk used
    const Run r = dfn_scene(tmp, name);
    CAPTURE(r.err);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains(name + ": is 300 MiB, more than the 256 MiB") &&
                          Contains("split the network"));
  }
}

TEST_CASE("a fracture of 1,000,000 nodes, most of them on its edges, is read", "[tools][dfn]") {
  // A square whose every edge carries 250,000 nodes (a clipped fracture's many collinear
  // corners): its joint is the square. The nodes used to be dropped one at a time, a vector
  // erase each (96 s for this file); now in one pass.
  test::TempDir tmp;
  const int per = 250000;
  std::string s;
  s.reserve(40u << 20);
  s = "BEGIN FORMAT\nFormat = Ascii\nEND FORMAT\nBEGIN FRACTURE\n1 " + std::to_string(4 * per) +
      " 1\n";
  int k = 0;
  const auto node = [&](double x, double y) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%d %.9g %.9g 5\n", ++k, x, y);
    s += buf;
  };
  for (int i = 0; i < per; ++i) node(1 + 8.0 * i / per, 1);
  for (int i = 0; i < per; ++i) node(9, 1 + 8.0 * i / per);
  for (int i = 0; i < per; ++i) node(9 - 8.0 * i / per, 9);
  for (int i = 0; i < per; ++i) node(1, 9 - 8.0 * i / per);
  s += "0 0 0 1\nEND FRACTURE\n";
  test::write_text(tmp / "many.fab", s);
  test::write_text(tmp / "s.toml", std::string(kHead) + "[[dfn]]\nfile = \"many.fab\"\n");
  const slice::Scene scene = slice::load_scene(tmp / "s.toml");
  REQUIRE(scene.joints.size() == 1);
  CHECK(scene.joints[0].polygon_uv.size() == 4);
}

TEST_CASE("far and huge fractures are refused naming their DFN file's line", "[tools][dfn]") {
  test::TempDir tmp;
  // Nodes at 1e155: the squares of their distances overflow; the normal was NaN and refused
  // only as the output's /joints/normal.
  test::write_text(tmp / "far.fab", replaced(fab(), "2 4 2\n1 5 1 1\n", "2 4 2\n1 5 1 1e155\n"));
  Run r = dfn_scene(tmp, "far.fab");
  CAPTURE(r.err);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("far.fab:19:") && Contains("fracture 2") && Contains("too far out"));
  CHECK_THAT(r.err, !Contains("/joints/normal"));
  // A disc of radius 1e160: finite, but its polygon's edges are not; slice-cut said "polygon
  // edge 0 has normal (0,0,0)".
  test::write_text(tmp / "huge.csv",
                   "x,y,z,dip,dip_direction,radius\n5,5,5,0,0,1\n5,5,5,0,0,1e160\n");
  r = dfn_scene(tmp, "huge.csv");
  CAPTURE(r.err);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("huge.csv:3:") && Contains("disc row 2") && Contains("radius"));
}

TEST_CASE("a UTF-8 byte-order mark starts a DFN file or a grid as nothing", "[tools][dfn][text]") {
  test::TempDir tmp;
  const std::string bom = "\xef\xbb\xbf";
  test::write_text(tmp / "net.fab", bom + fab());
  Run r = dfn_scene(tmp, "net.fab");
  CAPTURE(r.err);
  CHECK(r.exit_code == 0);
  test::write_text(tmp / "d.csv", bom + "x,y,z,dip,dip_direction,radius\n5,5,5,0,0,2\n");
  r = dfn_scene(tmp, "d.csv");
  CAPTURE(r.err);
  CHECK(r.exit_code == 0);
  test::write_text(tmp / "g.asc", bom + grid());
  r = grid_scene(tmp);
  CAPTURE(r.err);
  CHECK(r.exit_code == 0);
}

TEST_CASE("CR-only line ends are line ends, and no message echoes more than an excerpt",
          "[tools][dfn][text]") {
  test::TempDir tmp;
  // Many fractures, so that the file is long: with CR-only line ends it was one line of 1 MB,
  // and a mistake in it was echoed whole.
  std::string many = "BEGIN FORMAT\nFormat = Ascii\nEND FORMAT\nBEGIN FRACTURE\n";
  for (int f = 1; f <= 30000; ++f)
    many += std::to_string(f) + " 3 1\n1 1 1 3\n2 8 1 3\n3 8 8 3\n0 0 0 1\n";
  many += "END FRACTURE\n";
  REQUIRE(many.size() > (1u << 20));
  test::write_text(tmp / "cr.fab", cr_only(many));
  Run r = dfn_scene(tmp, "cr.fab");
  CAPTURE(r.err.substr(0, 300));
  CHECK(r.exit_code == 0);
  test::write_text(tmp / "bad.fab", cr_only(replaced(many, "END FRACTURE\n", "")));
  r = dfn_scene(tmp, "bad.fab");
  CAPTURE(r.err.substr(0, 300));
  CHECK(r.exit_code == 1);
  CHECK(r.err.size() < 400);
  CHECK_THAT(r.err, Contains("bad.fab:") && Contains("END FRACTURE is missing"));
  // A line of 1 MB without a line end in a key = value section: an excerpt of it.
  test::write_text(tmp / "long.fab", "BEGIN FORMAT\n" + std::string(1u << 20, 'x') + "\n");
  r = dfn_scene(tmp, "long.fab");
  CAPTURE(r.err.substr(0, 300));
  CHECK(r.exit_code == 1);
  CHECK(r.err.size() < 400);
  CHECK_THAT(r.err, Contains("long.fab:2:") && Contains("xxx...\""));
  // CSV and grid: their lines counted at each CR.
  test::write_text(tmp / "d.csv",
                   cr_only("x,y,z,dip,dip_direction,radius\n5,5,5,0,0,2\n5,5,5,95,0,2\n"));
  r = dfn_scene(tmp, "d.csv");
  CAPTURE(r.err);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("d.csv:3:") && Contains("dip of disc row 2"));
  test::write_text(tmp / "g.asc", cr_only(grid()));
  r = grid_scene(tmp);
  CAPTURE(r.err);
  CHECK(r.exit_code == 0);
  test::write_text(tmp / "g.asc",
                   cr_only(replaced(grid(), "8 8 8\n8 8 8\n8 8 8\n", "8 8 8\n8 x 8\n8 8 8\n")));
  r = grid_scene(tmp);
  CAPTURE(r.err);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("g.asc:7:") && Contains("\"x\" is not a number"));
}

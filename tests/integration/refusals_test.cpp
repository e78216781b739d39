// Issue 25 item 6 regressions ("slow refusals and misleading messages"), each named after what an
// audit found, run through the real tools: exit 1, one line that says what is wrong and how to
// fix it, once, and nothing written. Two findings were refusals of valid input: those now run.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using test::check_refused;
using test::edit_h5;
using test::run_tool;
using test::fs::path;

namespace {

std::size_t occurrences(const std::string& s, const std::string& word) {
  std::size_t n = 0;
  for (auto at = s.find(word); at != std::string::npos; at = s.find(word, at + 1)) ++n;
  return n;
}

// The cube [6, 12]^3: 8 corners, 12 triangles counter-clockwise seen from outside.
const std::vector<std::array<float, 3>> kCorners = {{6, 6, 6},    {12, 6, 6}, {12, 12, 6},
                                                    {6, 12, 6},   {6, 6, 12}, {12, 6, 12},
                                                    {12, 12, 12}, {6, 12, 12}};
const std::vector<std::array<int, 3>> kCube = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7},
                                               {0, 1, 5}, {0, 5, 4}, {3, 7, 6}, {3, 6, 2},
                                               {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};

/// A binary STL of the cube whose count field says `count`, cut to `size` bytes (0: whole).
std::string binary_stl(std::uint32_t count, std::size_t size = 0) {
  std::string s(80, ' ');
  s.replace(0, 11, "solid cube ");  // as many exporters write it: the header is no proof of ASCII
  s.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : kCube) {
    s.append(12, '\0');  // the normal: readers recompute it
    for (const int c : t)
      s.append(reinterpret_cast<const char*>(kCorners[std::size_t(c)].data()), 12);
    s.append(2, '\0');
  }
  if (size) s.resize(size);
  return s;
}

std::string cube_scene(const std::string& extra) {
  return "[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 16] }\n"
         "[[sets]]\nname = \"A\"\ndip = 10\ndip_direction = 30\nspacing = 3.1\n" +
         extra;
}

/// slice-joints on a scene written to tmp/s.toml: its run, and whether j.h5 was written.
test::ToolRun joints(const test::TempDir& tmp, const std::string& scene) {
  test::write_text(tmp / "s.toml", scene);
  test::fs::remove(tmp / "j.h5");
  return run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", (tmp / "j.h5").string()});
}

}  // namespace

TEST_CASE("binary STL with a wrong or truncated count: what it claims and holds",
          "[tools][refusals][mesh]") {
  test::TempDir tmp;
  const std::string zone = "[[zones]]\nmesh = \"cube.stl\"\n";
  test::write_text(tmp / "cube.stl", binary_stl(12));
  {
    const auto r = joints(tmp, cube_scene(zone));
    INFO(r.err);
    REQUIRE(r.exit_code == 0);  // the right count: the same bytes are a valid mesh
  }
  struct Case {
    std::string name, bytes;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {"11 for 12", binary_stl(11), {"says 11 triangles (634 bytes)", "684 bytes: 12 whole"}},
      {"13 for 12", binary_stl(13), {"says 13 triangles (734 bytes)", "684 bytes: 12 whole"}},
      {"0xFFFFFFFF", binary_stl(0xFFFFFFFF), {"says 4294967295 triangles", "12 whole triangles"}},
      {"0 for 12", binary_stl(0), {"says 0 triangles (84 bytes)", "12 whole triangles"}},
      {"truncated",
       binary_stl(12, 650),
       {"says 12 triangles (684 bytes)", "650 bytes: 11 whole triangles and 16 bytes more"}},
      {"shorter than the header", binary_stl(12, 82), {"82 bytes, shorter than its 84-byte"}},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    test::write_text(tmp / "cube.stl", c.bytes);
    const auto r = joints(tmp, cube_scene(zone));
    check_refused(r, "slice-joints", c.words);
    CHECK_THAT(r.err, Contains("s.toml:") && Contains("cube.stl"));
    CHECK(occurrences(r.err, "truncated or damaged") == 1);
    CHECK_THAT(r.err, !Contains("has no triangles"));
    CHECK_FALSE(test::fs::exists(tmp / "j.h5"));
  }
}

TEST_CASE("a 2 GB sparse .stl or .obj is refused by its size, before it is read",
          "[tools][refusals][mesh]") {
  test::TempDir tmp;
  for (const std::string name : {"big.stl", "big.obj"}) {
    CAPTURE(name);
    std::ofstream(tmp / name).close();
    test::fs::resize_file(tmp / name, std::uintmax_t(2) << 30);  // sparse: no disk, no time
    const auto r = joints(tmp, cube_scene("[[zones]]\nmesh = \"" + name + "\"\n"));
    // Advice for a mesh, not the out-of-memory line's "fewer joints, a larger spacing".
    check_refused(r, "slice-joints",
                  {name, "is 2048 MiB, more than the 256 MiB a mesh zone may have", "decimate"});
    CHECK_THAT(r.err, !Contains("joints,") && !Contains("spacing"));
    CHECK_FALSE(test::fs::exists(tmp / "j.h5"));
  }
}

TEST_CASE("mesh errors print their fix once", "[tools][refusals][mesh]") {
  test::TempDir tmp;
  SECTION("slice-joints: an open mesh") {
    std::string obj;
    for (const auto& c : kCorners)
      obj += "v " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) +
             "\n";
    for (std::size_t t = 0; t + 1 < kCube.size(); ++t)  // the last triangle left out
      obj += "f " + std::to_string(kCube[t][0] + 1) + " " + std::to_string(kCube[t][1] + 1) + " " +
             std::to_string(kCube[t][2] + 1) + "\n";
    test::write_text(tmp / "open.obj", obj);
    const auto r = joints(tmp, cube_scene("[[zones]]\nmesh = \"open.obj\"\n"));
    check_refused(r, "slice-joints", {"s.toml:", "open.obj", "the mesh is open"});
    CHECK(occurrences(r.err, "give a closed triangle mesh") == 1);
    CHECK(occurrences(r.err, "; ") == 1);
    CHECK_FALSE(test::fs::exists(tmp / "j.h5"));
  }
  SECTION("slice-cut: a joints.h5 whose mesh is not consistently oriented") {
    test::write_text(tmp / "cube.stl", binary_stl(12));
    REQUIRE(joints(tmp, cube_scene("[[zones]]\nmesh = \"cube.stl\"\n")).exit_code == 0);
    edit_h5(tmp / "j.h5",
            "t = f['zones/mesh_triangles'][...]; t[0] = t[0][::-1]; "
            "f['zones/mesh_triangles'][...] = t");
    const auto out = tmp / "b.h5";
    const auto r = run_tool("slice-cut", {(tmp / "j.h5").string(), "-o", out.string()});
    check_refused(
        r, "slice-cut",
        {"j.h5: /zones mesh 0 does not bound a solid", "regenerate it with slice-joints"});
    CHECK_THAT(r.err, !Contains("give a closed triangle mesh"));  // not the scene's fix
    CHECK(occurrences(r.err, "; ") == 1);
    CHECK_FALSE(test::fs::exists(out));
  }
}

TEST_CASE("3DEC export of a 2-D file names the input, not the output",
          "[tools][refusals][section]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "kim-persistent.toml", test::Stage::geometry);
  const auto grid = tmp / "v.3dgrid";
  const auto r = run_tool("slice-export", {geom, "--format", "3dec", "-o", grid.string()});
  check_refused(r, "slice-export", {geom + ": is a 2-D section", "--format yade"});
  CHECK_THAT(r.err, !Contains("v.3dgrid"));
  CHECK_FALSE(test::fs::exists(grid));
  CHECK_FALSE(test::fs::exists(tmp / "v.dat"));
  // The same cause in the PotentialBlock export.
  const auto py = tmp / "pb.py";
  const auto p =
      run_tool("slice-export", {geom, "--format", "yade-potential-blocks", "-o", py.string()});
  check_refused(p, "slice-export", {geom + ": is a 2-D section"});
  CHECK_THAT(p.err, !Contains("pb.py"));
  CHECK_FALSE(test::fs::exists(py));
}

TEST_CASE("a too-thin box domain: its thickness against the tolerance",
          "[tools][refusals][scene]") {
  test::TempDir tmp;
  const auto r = joints(tmp,
                        "[domain]\nbox = { min = [0, 0, 0], max = [1, 2, 1e-12] }\n"
                        "[[sets]]\nname = \"A\"\ndip = 10\ndip_direction = 30\n"
                        "spacing = 0.3\n");
  check_refused(r, "slice-joints",
                {"s.toml:2", "'box' of [domain] is only 1e-12 thick in z", "tolerance, 1e-09",
                 "length scale 1.118", "lower [scene] tolerance"});
  CHECK_THAT(r.err, !Contains("'planes'"));
  CHECK_FALSE(test::fs::exists(tmp / "j.h5"));
}

TEST_CASE("tunnel radius 1e300 and direction [0, 1e308, 1e308]", "[tools][refusals][tunnel]") {
  test::TempDir tmp;
  const auto tunnel = [](const std::string& direction, const std::string& radius) {
    return cube_scene("[[zones]]\ntunnel = { point = [10, 0, 8], direction = " + direction +
                      ", length = 30, radius = " + radius + " }\n");
  };
  SECTION("a radius beyond the precision: why, not 'no volume inside the domain'") {
    const auto r = joints(tmp, tunnel("[0, 1, 0]", "1e300"));
    check_refused(r, "slice-joints",
                  {"s.toml:", "'tunnel' of [[zones]] #1 reaches 1",
                   "e+300 from its axis, where doubles step by", "coarser than the tolerance"});
    CHECK_THAT(r.err, !Contains("no volume"));
    CHECK_FALSE(test::fs::exists(tmp / "j.h5"));
  }
  SECTION("a direction whose length overflows has a direction all the same") {
    const auto big = joints(tmp, tunnel("[0, 1e308, 1e308]", "2"));
    INFO(big.err);
    REQUIRE(big.exit_code == 0);
    const slice::JointSystem a = slice::read_joints(tmp / "j.h5");
    REQUIRE(joints(tmp, tunnel("[0, 1, 1]", "2")).exit_code == 0);
    const slice::JointSystem b = slice::read_joints(tmp / "j.h5");
    REQUIRE(a.zones.size() == b.zones.size());
    for (std::size_t z = 0; z < a.zones.size(); ++z) {
      REQUIRE(a.zones[z].planes.size() == b.zones[z].planes.size());
      for (std::size_t k = 0; k < a.zones[z].planes.size(); ++k) {
        CHECK((a.zones[z].planes[k].normal - b.zones[z].planes[k].normal).norm() < 1e-15);
        CHECK(std::abs(a.zones[z].planes[k].d - b.zones[z].planes[k].d) < 1e-13);
      }
    }
  }
}

TEST_CASE("2-D: a horizontal joint's dip direction 0 is accepted", "[tools][refusals][section]") {
  // docs/scenes.md: a horizontal plane's dip direction means nothing. The blocks are those of
  // dip direction 90.
  const auto blocks = [](const test::TempDir& tmp, const std::string& dd) {
    test::write_text(tmp / "s.toml",
                     "[scene]\ndimension = 2\n[domain]\nbox = { min = [0, 0], max = [10, 6] }\n"
                     "[[joints]]\ndip = 0\ndip_direction = " +
                         dd + "\npoint = [5, 2]\n[[joints]]\ndip = 0\ndip_direction = " + dd +
                         "\npoint = [2, 4]\nsegment = [[1, 4], [6, 4]]\n"
                         "[[sets]]\ndip = 60\ndip_direction = 90\nspacing = 2.5\n");
    const auto j = tmp / "j.h5", b = tmp / "b.h5";
    const auto r = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", j.string()});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    REQUIRE(run_tool("slice-cut", {j.string(), "-o", b.string(), "--prune"}).exit_code == 0);
    return slice::read_blocks(b).blocks.size();
  };
  test::TempDir zero, ninety;
  const std::size_t n = blocks(zero, "0");
  CHECK(n == blocks(ninety, "90"));
  CHECK(n > 4);
}

TEST_CASE("/geometry errors name slice-vertices, which writes it", "[tools][refusals]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry);
  const auto out = tmp / "m.vtu";
  const auto run = [&] {
    return run_tool("slice-export", {geom, "--format", "vtu", "-o", out.string()});
  };
  SECTION("a value") {
    edit_h5(geom, "v = f['geometry/volume'][...]; v[2] = -1; f['geometry/volume'][...] = v");
    const auto r = run();
    check_refused(r, "slice-export",
                  {"/geometry/volume row 2", "regenerate it with slice-vertices"});
    CHECK_THAT(r.err, !Contains("slice-cut"));
  }
  SECTION("a missing dataset") {
    edit_h5(geom, "del f['geometry/centroid']");
    const auto r = run();
    check_refused(r, "slice-export", {"/geometry/centroid", "regenerate it with slice-vertices"});
    CHECK_THAT(r.err, !Contains("slice-cut"));
  }
  SECTION("a /blocks value still names slice-cut") {
    edit_h5(geom, "v = f['blocks/inradius'][...]; v[1] = -1; f['blocks/inradius'][...] = v");
    check_refused(run(), "slice-export",
                  {"/blocks/inradius row 1", "regenerate it with slice-cut"});
  }
  CHECK_FALSE(test::fs::exists(out));
}

TEST_CASE("an HDF5 filter this build lacks (LZF): says so, not 'can't open directory'",
          "[tools][refusals]") {
  test::TempDir tmp;
  const std::string j = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::joints);
  // h5py has LZF built in; HDF5 itself does not.
  edit_h5(j,
          "n = f['joints/normal'][...]; del f['joints/normal']\n"
          "f['joints'].create_dataset('normal', data=n, compression='lzf')");
  const auto out = tmp / "b.h5";
  const auto r = run_tool("slice-cut", {j, "-o", out.string()});
  check_refused(
      r, "slice-cut",
      {"joints.h5: /joints/normal uses the HDF5 compression filter \"lzf\" (id 32000)",
       "this build of rockslice cannot read", "h5repack", "regenerate it with slice-joints"});
  CHECK_THAT(r.err, !Contains("directory") && !Contains("plugin"));
  CHECK_FALSE(test::fs::exists(out));
  check_refused(run_tool("slice-info", {j}), "slice-info", {"compression filter \"lzf\""});
}

// Issue 42 items 6-10 through the real tools (the library's side: tests/unit/h5io_test.cpp and
// input_refusals_test.cpp): exit 1, one line, nothing written.
TEST_CASE("inputs that passed unchecked are refused by the tools", "[tools][refusals]") {
  test::TempDir tmp;
  // Four 10 x 10 x 20 m blocks: contacts of 200 m2.
  const std::string geom =
      test::geometry_of_text(tmp,
                             "[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 20] }\n"
                             "[[joints]]\ndip = 90\ndip_direction = 90\npoint = [10, 5, 5]\n"
                             "[[joints]]\ndip = 90\ndip_direction = 0\npoint = [5, 10, 5]\n");
  const auto out = tmp / "out";
  const auto exporting = [&](const std::vector<std::string>& options) {
    std::vector<std::string> args = {geom, "-o", out.string()};
    args.insert(args.end(), options.begin(), options.end());
    return run_tool("slice-export", args);
  };
  SECTION("a /blocks/flags bit that no tool writes") {
    edit_h5(geom, "v = f['blocks/flags'][...]; v[3] = 9; f['blocks/flags'][...] = v");
    const std::vector<std::string> words = {"/blocks/flags row 3 is 9",
                                            "only bits 0 (boundary), 1 (removed) and 2 (fixed)"};
    check_refused(run_tool("slice-info", {geom}), "slice-info", words);
    check_refused(exporting({"--format", "yade"}), "slice-export", words);
    check_refused(exporting({"--format", "vtu"}), "slice-export", words);
  }
  SECTION("--yade-steps past the integers (clamped to the largest int64)") {
    check_refused(exporting({"--format", "yade", "--yade-steps", "99999999999999999999"}),
                  "slice-export", {"--yade-steps", "more than 1000000000000000"});
  }
  SECTION("--3dec-jkn 1e308: a contact stiffness of inf, a time step of 0 s") {
    check_refused(exporting({"--format", "3dec", "--3dec-jkn", "1e308"}), "slice-export",
                  {"--3dec-jkn 1e+308", "largest contact (200 m2)", "time step 0 s"});
    CHECK_FALSE(test::fs::exists(tmp / "out.dat"));
  }
  SECTION("a cylinder with ends at 1e155") {
    check_refused(
        run_tool("slice-extract", {geom, "--cylinder=-1e155,5,5,1e155,5,5,3", "-o", out.string()}),
        "slice-extract", {"--cylinder", "reaches 1e+155", "doubles step by"});
  }
  SECTION("a surface below the whole domain") {
    std::string asc = "ncols 4\nnrows 4\nxllcorner -10\nyllcorner -10\ncellsize 10\n";
    for (int row = 0; row < 4; ++row) asc += "-5 -5 -5 -5\n";
    test::write_text(tmp / "t.asc", asc);
    test::write_text(tmp / "s.toml",
                     "[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 20] }\n"
                     "[[zones]]\nsurface = \"t.asc\"\n");
    check_refused(run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", out.string()}),
                  "slice-joints", {"s.toml:", "below the domain everywhere", "remove all of it"});
  }
  CHECK_FALSE(test::fs::exists(out));
}

// Inputs and results that were once accepted without a word (a robustness audit), each named
// after what it found, run through the real tools: a scene's mesh named as -o, and wrong results.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using test::check_refused;
using test::run_tool;
using test::fs::path;

namespace {

/// Copies `from` to `to` and runs an h5py script (Debian's python3) on the copy, as `f` (r+).
void edited_copy(const path& from, const path& to, const std::string& body) {
  test::fs::copy_file(from, to, test::fs::copy_options::overwrite_existing);
  const std::string script = "import h5py, numpy as np\nf = h5py.File(" +
                             test::shell_quote(to.string()) + ", 'r+')\n" + body + "\nf.close()\n";
  REQUIRE(test::run_shell("/usr/bin/python3 -c " + test::shell_quote(script)) == 0);
}

// A 6 m cube cavern, [7, 13]^3, its triangles counter-clockwise seen from outside.
const char* kCubeObj = R"(v 7 7 7
v 13 7 7
v 13 13 7
v 7 13 7
v 7 7 13
v 13 7 13
v 13 13 13
v 7 13 13
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
)";

// A 20 m cube cut by one set, with `zone` as its only [[zones]] entry.
std::string cube_scene(const std::string& zone) {
  return "[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 20] }\n[[sets]]\ndip = 10\n"
         "dip_direction = 30\nspacing = 3.1\n[[zones]]\n" +
         zone + "\n";
}

}  // namespace

TEST_CASE("the scene's mesh file named as -o is refused, the mesh untouched",
          "[robustness][tools][mesh]") {
  test::TempDir tmp;
  test::write_text(tmp / "cavern.obj", kCubeObj);
  test::write_text(tmp / "scene.toml", cube_scene("mesh = \"cavern.obj\""));
  test::fs::create_directory(tmp / "sub");
  test::fs::create_symlink(tmp / "cavern.obj", tmp / "link.obj");
  const std::string scene = (tmp / "scene.toml").string();
  for (const path& out :
       {tmp / "cavern.obj", tmp / "link.obj", tmp / "sub" / ".." / "cavern.obj"}) {
    CAPTURE(out);
    check_refused(run_tool("slice-joints", {scene, "-o", out.string()}), "slice-joints",
                  {"same file", "[[zones]] mesh", "nothing was written"});
    CHECK(test::read_bytes(tmp / "cavern.obj") == kCubeObj);
    CHECK_FALSE(test::fs::exists(tmp / "cavern.obj.partial"));
  }
  // Another -o still works.
  CHECK(run_tool("slice-joints", {scene, "-o", (tmp / "j.h5").string()}).exit_code == 0);
}

TEST_CASE("a cut tunnel longer than doubles resolve (1e18, 1e16 in a 20 m cube)",
          "[robustness][tools][tunnel]") {
  const auto tunnel = [](const std::string& point, const std::string& length) {
    return cube_scene("tunnel = { point = " + point +
                      ", direction = [0, 1, 0], length = " + length + ", radius = 3 }\ncut = true");
  };
  // Once removed 4,000 m3 instead of 572.87 (1e18), or made 33 blocks instead of 22 (1e16).
  test::check_bad_scenes({
      {"length 1e18", tunnel("[10, 0, 10]", "1e18"), {":8", "tunnel", "doubles step by"}},
      {"length 1e16", tunnel("[10, 0, 10]", "1e16"), {":8", "doubles step by", "shorten"}},
      {"start far behind the domain", tunnel("[10, -5e15, 10]", "1e16"), {":8", "doubles step by"}},
  });
  // A tunnel well beyond the domain, but within what doubles resolve, is fine.
  test::TempDir tmp;
  test::write_text(tmp / "long.toml", tunnel("[10, -500, 10]", "1000"));
  const auto r =
      run_tool("slice-joints", {(tmp / "long.toml").string(), "-o", (tmp / "j.h5").string()});
  INFO(r.err);
  CHECK(r.exit_code == 0);
}

TEST_CASE(
    "joints.h5 with /zones/mesh_* datasets missing, or a mesh outside the "
    "domain, is refused by slice-cut",
    "[robustness][tools][mesh]") {
  test::TempDir tmp;
  test::write_text(tmp / "cavern.obj", kCubeObj);
  test::write_text(tmp / "scene.toml", cube_scene("mesh = \"cavern.obj\""));
  const path joints = tmp / "joints.h5", bad = tmp / "bad.h5", out = tmp / "blocks.h5";
  REQUIRE(
      run_tool("slice-joints", {(tmp / "scene.toml").string(), "-o", joints.string()}).exit_code ==
      0);
  for (const std::string name :
       {"mesh_vertex_offset", "mesh_vertices", "mesh_triangle_offset", "mesh_triangles"}) {
    CAPTURE(name);
    edited_copy(joints, bad, "del f['zones/" + name + "']");
    check_refused(run_tool("slice-cut", {bad.string(), "-o", out.string()}), "slice-cut",
                  {"bad.h5", "/zones/" + name, "missing"});
    CHECK_FALSE(test::fs::exists(out));
  }
  // Moved 1 km east: slice-joints refuses this mesh in a scene, slice-cut dropped the zone.
  edited_copy(joints, bad, "f['zones/mesh_vertices'][:, 0] += 1000");
  check_refused(run_tool("slice-cut", {bad.string(), "-o", out.string()}), "slice-cut",
                {"bad.h5", "/zones mesh 0", "no volume inside /domain"});
  CHECK_FALSE(test::fs::exists(out));
  std::string far = kCubeObj;  // far east: x = 1007 and 10013
  for (std::size_t at = 0; (at = far.find("\nv ", at)) != std::string::npos; ++at)
    far.insert(at + 3, "100");
  far.insert(2, "100");
  test::write_text(tmp / "far.obj", far);
  test::write_text(tmp / "far.toml", cube_scene("mesh = \"far.obj\""));
  check_refused(run_tool("slice-joints", {(tmp / "far.toml").string(), "-o", out.string()}),
                "slice-joints", {"no volume inside the domain"});
}

TEST_CASE("a --seed above 2^63 - 1 is refused, not clamped", "[robustness][tools]") {
  test::TempDir tmp;
  const std::string scene = test::data_path("cube-3sets.toml").string();
  const std::string out = (tmp / "j.h5").string();
  for (const char* seed : {"9223372036854775808", "18446744073709551616", "1e23", "-1e23"}) {
    CAPTURE(seed);
    check_refused(run_tool("slice-joints", {scene, "-o", out, "--seed", seed}), "slice-joints",
                  {"--seed", seed, "out of range", "9223372036854775807"});
    CHECK_FALSE(test::fs::exists(out));
  }
  for (const char* seed : {"-1", "x", "1.5", ""}) {
    CAPTURE(seed);
    check_refused(run_tool("slice-joints", {scene, "-o", out, "--seed", seed}), "slice-joints",
                  {"--seed"});
  }
  const auto r = run_tool("slice-joints", {scene, "-o", out, "--seed", "9223372036854775807"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(slice::read_joints(out).seed == 9223372036854775807u);
}

TEST_CASE("/geometry values no reader checked are refused", "[robustness][tools][geometry]") {
  test::TempDir tmp;
  const path geom = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry);
  const path bad = tmp / "bad.h5", out = tmp / "out.vtu";
  struct Case {
    std::string name, edit;
    std::vector<std::string> words;
  };
  const std::vector<Case> cases = {
      {"a centroid outside its block",
       "c = f['geometry/centroid'][...]; c[3] += [0, 0, 50]; f['geometry/centroid'][...] = c",
       {"/geometry/centroid row 3", "outside face", "inside its block"}},
      {"a centroid inside its block, but not its centroid",
       "g = f['geometry']; c = g['centroid'][...]; v = g['vertices'][g['vertex_offset'][3]]\n"
       "c[3] = 0.9 * c[3] + 0.1 * v; g['centroid'][...] = c",
       {"/geometry/centroid row 3", "is not the centroid"}},
      {"a wrong volume",
       "v = f['geometry/volume'][...]; v[2] *= 1.001; f['geometry/volume'][...] = v",
       {"/geometry/volume row 2", "enclose"}},
      {"a reversed face loop",
       "g = f['geometry']; o = g['face_vertex_offset'][...]; fv = g['face_vertices'][...]\n"
       "fv[o[5]:o[6]] = fv[o[5]:o[6]][::-1].copy(); g['face_vertices'][...] = fv",
       {"loop of face 5", "clockwise", "counter-clockwise"}},
      {"a loop with a repeated vertex",
       "g = f['geometry']; o = g['face_vertex_offset'][...]; fv = g['face_vertices'][...]\n"
       "fv[o[5] + 1] = fv[o[5]]; g['face_vertices'][...] = fv",
       {"loop of face 5", "visits a vertex twice"}},
      {"a wrong inertia",
       "i = f['geometry/inertia'][...]; i[3, 5] += 1e-3 * i[3, 0]; f['geometry/inertia'][...] = i",
       {"/geometry/inertia row 3 column 5 (zx)"}},
      {"a wrong face area",
       "a = f['geometry/face_area'][...]; a[7] *= 1.001; f['geometry/face_area'][...] = a",
       {"/geometry/face_area row 7", "encloses"}},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name);
    edited_copy(geom, bad, c.edit);
    for (const char* format : {"vtu", "yade"}) {
      CAPTURE(format);
      check_refused(
          run_tool("slice-export", {bad.string(), "--format", format, "-o", out.string()}),
          "slice-export", c.words);
      CHECK_FALSE(test::fs::exists(out));
    }
    CHECK_THROWS_AS(slice::read_blocks(bad), slice::Error);
  }
  // The file as slice-vertices wrote it passes every check.
  CHECK(
      run_tool("slice-export", {geom.string(), "--format", "vtu", "-o", out.string()}).exit_code ==
      0);
}

TEST_CASE("a 2-D geom.h5 with a vertex off the plane (y = 1) is refused",
          "[robustness][tools][geometry][2d]") {
  test::TempDir tmp;
  const path geom = test::run_pipeline(tmp, "vajont-section.toml", test::Stage::geometry);
  const path bad = tmp / "bad.h5", out = tmp / "out.vtu";
  edited_copy(geom, bad,
              "v = f['geometry/vertices'][...]; v[4, 1] = 1; f['geometry/vertices'][...] = v");
  check_refused(run_tool("slice-export", {bad.string(), "--format", "vtu", "-o", out.string()}),
                "slice-export", {"/geometry/vertices row 4", "y = 1", "2-D"});
  CHECK_FALSE(test::fs::exists(out));
  edited_copy(geom, bad,
              "c = f['geometry/centroid'][...]; c[2, 1] = 1; f['geometry/centroid'][...] = c");
  check_refused(run_tool("slice-export", {bad.string(), "--format", "vtu", "-o", out.string()}),
                "slice-export", {"/geometry/centroid row 2", "y = 1"});
  // An edge run the wrong way round (a 2-D loop is its edge's start and end).
  edited_copy(geom, bad,
              "g = f['geometry']; o = g['face_vertex_offset'][...]; fv = g['face_vertices'][...]\n"
              "fv[o[3]:o[4]] = fv[o[3]:o[4]][::-1].copy(); g['face_vertices'][...] = fv");
  check_refused(run_tool("slice-export", {bad.string(), "--format", "vtu", "-o", out.string()}),
                "slice-export", {"loop of face 3", "clockwise"});
  CHECK(
      run_tool("slice-export", {geom.string(), "--format", "vtu", "-o", out.string()}).exit_code ==
      0);
}

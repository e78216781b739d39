// [[zones]] mesh: a closed OBJ or STL mesh as an excavation, through the real tools.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "slice/h5io.hpp"
#include "slice/mesh.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::run_tool;

namespace {

// An L-shaped prism (non-convex): the L (5,5) (15,5) (15,9) (9,9) (9,15) (5,15) from z = 4 to
// z = 12; area 64, volume 512. Faces counter-clockwise seen from outside.
const char* kLObj = R"(# L-shaped cavern
v 5 5 4
v 15 5 4
v 15 9 4
v 9 9 4
v 9 15 4
v 5 15 4
v 5 5 12
v 15 5 12
v 15 9 12
v 9 9 12
v 9 15 12
v 5 15 12
f 1 3 2
f 1 4 3
f 1 5 4
f 1 6 5
f 7 8 9
f 7 9 10
f 7 10 11
f 7 11 12
f 1 2 8 7
f 2 3 9 8
f 3 4 10 9
f 4 5 11 10
f 5 6 12 11
f 6 1 7 12
)";

std::string scene(const std::string& zone) {
  return R"([scene]
name = "cavern"
[domain]
box = { min = [0, 0, 0], max = [20, 20, 16] }
[[sets]]
name = "A"
dip = 10
dip_direction = 30
spacing = 3.1
[[sets]]
name = "B"
dip = 80
dip_direction = 120
spacing = 3.3
[[zones]]
)" + zone +
         "\n";
}

struct Result {
  double removed = 0, kept = 0;
  std::size_t removed_blocks = 0;
  bool kept_centroid_inside = false;
};

Result run(const test::TempDir& tmp, const std::string& zone) {
  test::write_text(tmp / "s.toml", scene(zone));
  const auto j = (tmp / "j.h5").string(), b = (tmp / "b.h5").string(), g = (tmp / "g.h5").string();
  const auto r = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", j});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto info = run_tool("slice-info", {j, "--json"});
  REQUIRE(info.exit_code == 0);
  CHECK(nlohmann::json::parse(info.out)["zone_meshes"] == 1);
  REQUIRE(run_tool("slice-cut", {j, "-o", b, "--prune"}).exit_code == 0);
  REQUIRE(run_tool("slice-vertices", {b, "-o", g}).exit_code == 0);
  const auto bs = slice::read_blocks(g);
  REQUIRE(bs.joints.zone_meshes.size() == 1);
  const slice::MeshInside inside(bs.joints.zone_meshes[0]);
  Result out;
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    const bool removed = bs.blocks[i].flags & slice::kRemoved;
    (removed ? out.removed : out.kept) += bs.geometry->volume[i];
    out.removed_blocks += removed ? 1 : 0;
    CHECK(removed == inside(bs.blocks[i].origin));  // removal is by the centre
    if (!removed && inside(bs.geometry->centroid[i])) out.kept_centroid_inside = true;
  }
  return out;
}

}  // namespace

TEST_CASE("a non-convex mesh zone cut into the rock removes exactly its volume",
          "[tools][zones][mesh]") {
  test::TempDir tmp;
  test::write_text(tmp / "cavern.obj", kLObj);
  const Result cut = run(tmp, "mesh = \"cavern.obj\"\ncut = true");
  CHECK(cut.removed_blocks > 1);
  CHECK_THAT(cut.removed, WithinRel(512.0, 1e-9));
  CHECK_THAT(cut.removed + cut.kept, WithinRel(20.0 * 20 * 16, 1e-9));
  CHECK_FALSE(cut.kept_centroid_inside);
  // Without the cut the blocks straddle the mesh: the removed volume is something else.
  const Result plain = run(tmp, "mesh = \"cavern.obj\"");
  CHECK(std::abs(plain.removed - 512.0) > 1.0);
}

TEST_CASE("a mesh zone from an STL file gives the blocks the same OBJ gives",
          "[tools][zones][mesh]") {
  test::TempDir tmp;
  test::write_text(tmp / "cavern.obj", kLObj);
  const auto mesh = slice::read_mesh(tmp / "cavern.obj");
  test::write_text(tmp / "cavern.stl", test::ascii_stl(mesh));
  const Result a = run(tmp, "mesh = \"cavern.obj\"\ncut = true");
  const Result b = run(tmp, "mesh = \"cavern.stl\"\ncut = true");
  CHECK(a.removed_blocks == b.removed_blocks);
  CHECK(a.removed == b.removed);
}

TEST_CASE("bad mesh zones are refused by slice-joints with one line, nothing written",
          "[tools][zones][mesh]") {
  test::TempDir tmp;
  const std::string obj = kLObj;
  struct Case {
    std::string name, file_text, zone;
    std::vector<std::string> words;
  };
  std::string open_mesh = obj.substr(0, obj.rfind("f 6 1 7 12"));
  std::string inside_out;
  {
    std::istringstream in(obj);
    std::ostringstream out;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("f ", 0) == 0) {  // reverse the corner order
        std::istringstream ls(line.substr(2));
        std::vector<std::string> c;
        for (std::string x; ls >> x;) c.push_back(x);
        line = "f";
        for (auto it = c.rbegin(); it != c.rend(); ++it) line += " " + *it;
      }
      out << line << "\n";
    }
    inside_out = out.str();
  }
  const std::vector<Case> cases = {
      {"open.obj", open_mesh, "mesh = \"open.obj\"", {"s.toml:", "open"}},
      {"flipped.obj", inside_out, "mesh = \"flipped.obj\"", {"inside out"}},
      {"far.obj", "", "mesh = \"missing.obj\"", {"missing.obj", "not a file"}},
      {"l.obj",
       obj,
       "mesh = \"l.obj\"\nbox = { min = [0, 0, 0], max = [1, 1, 1] }",
       {"both 'mesh' and 'box'"}},
      {"l.obj", obj, "mesh = \"l.obj\"\nstage = 3", {"cut = true"}},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name, c.zone);
    if (!c.file_text.empty()) test::write_text(tmp / c.name, c.file_text);
    test::write_text(tmp / "s.toml", scene(c.zone));
    const auto out = (tmp / "j.h5").string();
    const auto r = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", out});
    CHECK(r.exit_code == 1);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    for (const auto& w : c.words) CHECK_THAT(r.err, Contains(w));
    CHECK_FALSE(test::fs::exists(out));
  }
}

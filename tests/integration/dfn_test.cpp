// [[dfn]]: the fractures of FracMan FAB and CSV files as polygon joints, their sets as sets, the
// `set` key of [[joints]], and slice-export --format fab, through the real tools.
#include "slice/dfn.hpp"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/hash.hpp"
#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "support/blocks_check.hpp"
#include "support/compare.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::run_tool;

namespace {

// Five planar convex fractures in three sets, in the 10 m cube: two horizontal (A), two vertical
// (B), one dipping 45 degrees East (C), listed as FracMan writes them (one property).
const char* kFab = R"(BEGIN FORMAT
    Format = Ascii
    XAxis = East
    Scale = 100.0
    No_Fractures = 5
    No_TessFractures = 0
    No_Nodes = 19
    No_Properties = 1
END FORMAT

BEGIN PROPERTIES
    Prop1    =    (Real*4)    "Transmissivity"
END PROPERTIES

BEGIN SETS
    Set1    =    "A"
    Set2    =    "B"
    Set3    =    "C"
END SETS

BEGIN FRACTURE
1 4 1 1e-6
1 1 1 3
2 8 1 3
3 8 8 3
4 1 8 3
0 0 0 1
2 3 1 2e-6
1 2 2 6.5
2 9 3 6.5
3 4 9 6.5
0 0 0 1
3 4 2 1e-6
1 4.25 0.5 0.5
2 4.25 9.5 0.5
3 4.25 9.5 9.5
4 4.25 0.5 9.5
0 1 0 0
4 4 2 1e-6
1 0.5 5.5 1
2 6 5.5 1
3 6 5.5 8
4 0.5 5.5 8
0 0 1 0
5 4 3 3e-6
1 3 1 7
2 8 1 2
3 8 9 2
4 3 9 7
0 0.70710678 0 0.70710678
END FRACTURE

BEGIN TESSFRACTURE
END TESSFRACTURE
)";

const char* kHead = R"([scene]
name = "dfn"
[domain]
box = { min = [0, 0, 0], max = [10, 10, 10] }
)";

std::string g17(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// slice-joints then slice-cut --prune; the blocks.
slice::BlockSystem cut(const test::TempDir& tmp, const std::string& name, const std::string& text) {
  test::write_text(tmp / (name + ".toml"), text);
  const auto j = (tmp / (name + "-j.h5")).string(), b = (tmp / (name + "-b.h5")).string();
  const auto r = run_tool("slice-joints", {(tmp / (name + ".toml")).string(), "-o", j});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  REQUIRE(run_tool("slice-cut", {j, "-o", b, "--prune"}).exit_code == 0);
  return slice::read_blocks(b);
}

// text with its first `from` replaced by `to` (which must be there).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// A malformed input (a DFN file or a scene's lines) and the words the one line must hold.
struct BadInput {
  std::string name, text;
  std::vector<std::string> words;
};

// Each case's text as the file net.fab of a scene: exit 1, one line holding the case's words
// and `every`, no output.
void check_refused(const test::TempDir& tmp, const std::vector<BadInput>& cases,
                   const std::vector<std::string>& every) {
  for (const BadInput& c : cases) {
    CAPTURE(c.name);
    test::write_text(tmp / "net.fab", c.text);
    test::write_text(tmp / "s.toml", std::string(kHead) + "[[dfn]]\nfile = \"net.fab\"\n");
    const auto out = tmp / "j.h5";
    const auto r = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", out.string()});
    CAPTURE(r.err);
    CHECK(r.exit_code == 1);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    for (const auto& w : every) CHECK_THAT(r.err, Contains(w));
    for (const auto& w : c.words) CHECK_THAT(r.err, Contains(w));
    CHECK_FALSE(std::filesystem::exists(out));
  }
}

}  // namespace

TEST_CASE("the polygons of a FAB file cut the blocks that the same polygons as [[joints]] cut",
          "[tools][dfn]") {
  test::TempDir tmp;
  test::write_text(tmp / "net.fab", kFab);
  const slice::BlockSystem fab =
      cut(tmp, "fab", std::string(kHead) + "[[dfn]]\nfile = \"net.fab\"\n");
  const slice::JointSystem& js = fab.joints;
  REQUIRE(js.joints.size() == 5);
  REQUIRE(js.sets.size() == 3);
  CHECK(js.sets[0].name == "A");
  CHECK(js.sets[2].name == "C");
  CHECK(js.sets[1].intensity == slice::SetIntensity::deterministic);
  CHECK(js.sets[1].joint_count == 2);
  CHECK_THAT(js.joints[4].dip_deg, WithinAbs(45, 1e-12));
  CHECK_THAT(js.joints[4].dip_direction_deg, WithinAbs(90, 1e-12));
  CHECK(fab.blocks.size() > 5);

  // The same nodes, written by hand: dip and dip direction as the reader fitted them.
  const slice::DfnFile file = slice::read_fab(tmp / "net.fab");
  std::string joints = kHead;
  for (std::size_t i = 0; i < file.fractures.size(); ++i) {
    // Built with += only: GCC 12 gives a false -Wrestrict for "literal" + std::string once
    // inlined (GCC bug 105651).
    joints += "[[joints]]\nset = \"";
    joints += file.sets[file.fractures[i].set];
    joints += "\"\ndip = ";
    joints += g17(js.joints[i].dip_deg);
    joints += "\ndip_direction = ";
    joints += g17(js.joints[i].dip_direction_deg);
    joints += "\npolygon = [";
    for (const Vec3& x : file.fractures[i].nodes)
      for (int k = 0; k < 3; ++k) {
        joints += k == 0 ? "[" : ", ";
        joints += g17(x(k));
        joints += k == 2 ? "], " : "";
      }
    joints += "]\n";
  }
  const slice::BlockSystem hand = cut(tmp, "hand", joints);
  test::check_same(fab, hand);  // joints, sets and blocks, bit for bit

  // 3DEC: one joint set ID per file set, named after it.
  const auto g = (tmp / "g.h5").string(), grid = (tmp / "m.3dgrid").string();
  REQUIRE(run_tool("slice-vertices", {(tmp / "fab-b.h5").string(), "-o", g}).exit_code == 0);
  REQUIRE(run_tool("slice-export", {g, "--format", "3dec", "-o", grid}).exit_code == 0);
  const std::string commands = test::read_bytes(tmp / "m.dat");
  CHECK_THAT(commands, Contains("; JS 1: set \"A\"\n"));
  CHECK_THAT(commands, Contains("; JS 2: set \"B\"\n"));
  CHECK_THAT(commands, Contains("; JS 3: set \"C\"\n"));
  CHECK_THAT(commands, !Contains("[[joints]] entry"));
}

namespace {

// kFab with two tessellated fractures: a horizontal square of four triangles about its middle
// (set A; a face line "k a b c 0" and one property) and a vertical rectangle of two (set B; a face
// line "k 3 a b c" and one property), the two layouts of face lines found in public readers.
std::string tess_fab() {
  std::string s = kFab;
  s.replace(s.find("No_TessFractures = 0"), 20, "No_TessFractures = 2");
  s.replace(s.find("BEGIN TESSFRACTURE\n"), 19, R"(BEGIN TESSFRACTURE
6 5 4 1
1 1 1 5
2 9 1 5
3 9 9 5
4 1 9 5
5 5 5 5
1 1 2 5 0 1e-6
2 2 3 5 0 1e-6
3 3 4 5 0 1e-6
4 4 1 5 0 1e-6
7 4 2 2
1 7 2 2
2 7 8 2
3 7 8 9
4 7 2 9
1 3 1 2 3 2e-6
2 3 1 3 4 2e-6
)");
  return s;
}

// The sorted volumes of the blocks.
std::vector<double> volumes(const slice::BlockSystem& bs) {
  std::vector<double> v;
  for (const auto& b : bs.blocks) v.push_back(test::block_volume(b, 1e-9));
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

TEST_CASE("FAB tessellated fractures: planar meshes that tile a convex polygon are its joint",
          "[tools][dfn]") {
  test::TempDir tmp;
  test::write_text(tmp / "net.fab", tess_fab());
  const slice::DfnFile file = slice::read_fab(tmp / "net.fab");
  REQUIRE(file.fractures.size() == 7);
  CHECK(file.fractures[5].tessellated);
  CHECK(file.fractures[5].line == 54);
  CHECK(file.fractures[5].nodes.size() == 5);
  CHECK(file.fractures[5].faces.size() == 4);
  CHECK(file.fractures[6].set == 1);
  CHECK(file.fractures[6].faces[1] == std::array<std::int64_t, 5>{2, 3, 1, 3, 4});

  const slice::BlockSystem fab =
      cut(tmp, "fab", std::string(kHead) + "[[dfn]]\nfile = \"net.fab\"\n");
  const slice::JointSystem& js = fab.joints;
  REQUIRE(js.joints.size() == 7);
  CHECK(js.joints[5].set == 0);
  CHECK(js.joints[6].set == 1);
  CHECK_THAT(js.joints[5].dip_deg, WithinAbs(0, 1e-12));
  CHECK_THAT(js.joints[6].dip_deg, WithinAbs(90, 1e-12));
  CHECK(js.joints[5].polygon_uv.size() == 4);  // the hull's corners, the middle node inside
  CHECK(js.joints[6].polygon_uv.size() == 4);
  CHECK_THAT(std::abs(js.joints[5].plane.distance(Vec3(3, 4, 5))), WithinAbs(0, 1e-12));
  CHECK_THAT(std::abs(js.joints[6].plane.distance(Vec3(7, 0, 0))), WithinAbs(0, 1e-12));

  // The same outlines as [[joints]] polygons cut blocks of the same volumes.
  std::string hand = std::string(kHead) + "[[dfn]]\nfile = \"five.fab\"\n";
  test::write_text(tmp / "five.fab", kFab);
  hand +=
      "[[joints]]\ndip = 0\ndip_direction = 0\npolygon = [[1, 1, 5], [9, 1, 5], [9, 9, 5], [1, 9, "
      "5]]\n";
  hand +=
      "[[joints]]\ndip = 90\ndip_direction = 90\npolygon = [[7, 2, 2], [7, 8, 2], [7, 8, 9], [7, "
      "2, 9]]\n";
  const slice::BlockSystem by_hand = cut(tmp, "hand", hand);
  const auto a = volumes(fab), b = volumes(by_hand);
  REQUIRE(a.size() == b.size());
  CHECK(a.size() >
        volumes(cut(tmp, "five", std::string(kHead) + "[[dfn]]\nfile = \"five.fab\"\n")).size());
  for (std::size_t i = 0; i < a.size(); ++i) CHECK_THAT(a[i], WithinAbs(b[i], 1e-9));

  // Refused with the file's line: bad lines, and meshes that are not one planar convex polygon.
  const std::string good = tess_fab();
  const auto replace = [&](const std::string& from, const std::string& to) {
    return replaced(good, from, to);
  };
  const std::vector<BadInput> cases = {
      {"count",
       replace("No_TessFractures = 2", "No_TessFractures = 3"),
       {"net.fab:1:", "No_TessFractures = 3", "2 tessellated"}},
      {"head", replace("6 5 4 1\n", "6 5 4\n"), {"net.fab:54:", "expected 4 (id, node count"}},
      {"faces", replace("6 5 4 1\n", "6 5 5 1\n"), {"net.fab:64:", "face 5 of fracture 6"}},
      {"nan", replace("2 2 3 5 0 1e-6", "2 2 3 5 0 nan"), {"net.fab:61:", "not a finite number"}},
      {"whole",
       replace("1 1 2 5 0 1e-6", "1 1.5 2 5 0 1e-6"),
       {"net.fab:60:", "not a whole number"}},
      {"index", replace("4 4 1 5 0 1e-6", "4 4 9 5 0 1e-6"), {"net.fab:54:", "within 1..5"}},
      {"planar", replace("5 5 5 5\n", "5 5 5 6\n"), {"net.fab:54:", "fracture 6", "not planar"}},
      {"convex",
       replace("3 9 9 5\n", "3 4 4 5\n"),
       {"net.fab:54:", "tessellated fracture 6", "not one convex polygon"}},
      {"end", replace("END TESSFRACTURE\n", ""), {"END TESSFRACTURE is missing", "line 53"}},
  };
  check_refused(tmp, cases, {});
}

TEST_CASE("slice-export --format fab writes a DFN that reads back as the same joints",
          "[tools][dfn]") {
  test::TempDir tmp;
  // A stochastic set (polygons), a regular set (persistent planes) and two hand-written joints.
  std::string head = kHead;
  head.insert(head.find("[domain]"), "seed = 7\n");
  test::write_text(tmp / "s.toml", head + R"([[sets]]
name = "discs"
dip = 60
dip_direction = 200
fisher_kappa = 20
count = 12
size = { distribution = "fixed", value = 4 }
shape = "ellipse"
aspect = 2
[[sets]]
name = "bedding"
dip = 5
dip_direction = 10
spacing = 4
[[joints]]
dip = 80
dip_direction = 45
point = [5, 5, 5]
polygon_uv = [[-2, -1], [2, -1], [0, 2]]
)");
  const auto j = (tmp / "j.h5").string(), fab = (tmp / "out.fab").string();
  REQUIRE(run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", j}).exit_code == 0);
  const auto r = run_tool("slice-export", {j, "--format", "fab", "-o", fab});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const slice::JointSystem js = slice::read_joints(j);
  const slice::DfnFile file = slice::read_fab(fab);
  // Every joint, persistent planes clipped to the domain (they all cross it).
  REQUIRE(file.fractures.size() == js.joints.size());
  REQUIRE(file.sets.size() == 3);
  CHECK(file.sets[0] == "discs");
  CHECK(file.sets[2] == "[[joints]]");
  for (std::size_t i = 0; i < js.joints.size(); ++i) {
    CAPTURE(i);
    const auto& f = file.fractures[i];
    CHECK(f.set == (js.joints[i].set >= 0 ? std::size_t(js.joints[i].set) : 2));
    if (!js.joints[i].persistent()) CHECK(f.nodes == slice::joint_polygon(js.joints[i]));
    for (const Vec3& x : f.nodes) CHECK(std::abs(js.joints[i].plane.distance(x)) < 1e-12);
  }
  // Read back as [[dfn]]: the same planes and polygons, the same set names.
  test::write_text(tmp / "back.toml", std::string(kHead) + "[[dfn]]\nfile = \"out.fab\"\n");
  const auto j2 = (tmp / "j2.h5").string();
  const auto r2 = run_tool("slice-joints", {(tmp / "back.toml").string(), "-o", j2});
  INFO(r2.err);
  REQUIRE(r2.exit_code == 0);
  const slice::JointSystem back = slice::read_joints(j2);
  REQUIRE(back.joints.size() == js.joints.size());
  REQUIRE(back.sets.size() == 3);
  for (std::size_t s = 0; s < 3; ++s) CHECK(back.sets[s].name == file.sets[s]);
  for (std::size_t i = 0; i < js.joints.size(); ++i) {
    CAPTURE(i);
    const auto& a = js.joints[i];
    const auto& b = back.joints[i];
    CHECK_THAT(a.plane.normal.dot(b.plane.normal), WithinAbs(1, 1e-12));
    CHECK_THAT(b.plane.d, WithinAbs(a.plane.d, 1e-9));
    if (a.persistent()) continue;
    const auto pa = slice::joint_polygon(a), pb = slice::joint_polygon(b);
    REQUIRE(pa.size() == pb.size());
    for (std::size_t k = 0; k < pa.size(); ++k) CHECK((pa[k] - pb[k]).norm() < 1e-9);
  }
  // A file PorePy writes (no SETS, no properties, float node indices, normal "0 -1 -1 -1").
  test::write_text(tmp / "porepy.fab", R"(BEGIN FORMAT
	Format = Ascii
	XAxis = East
	Scale = 100.0
	No_Fractures = 1
	No_TessFractures = 0
	No_Nodes = 3
	No_Properties = 0
END FORMAT

BEGIN FRACTURE
	0 3 1
		0.0 1.0 1.0 5.0
		1.0 9.0 1.0 5.0
		2.0 5.0 9.0 5.0
	0 -1 -1 -1
END FRACTURE)");
  const slice::DfnFile pp = slice::read_fab(tmp / "porepy.fab");
  REQUIRE(pp.fractures.size() == 1);
  CHECK(pp.sets == std::vector<std::string>{"porepy set 1"});
}

TEST_CASE("a CSV of discs: polygons of the disc's area, sets by name, properties per set",
          "[tools][dfn]") {
  test::TempDir tmp;
  test::write_text(tmp / "discs.csv",
                   "id,x,y,z,dip,dip_direction,radius,set,aspect,rotation,aperture\n"
                   "d1,5,5,5,30,120,2,north,1,0,0.001\n"
                   "d2,3,6,4,70,300,1.5,south,2,30,0.002\n"
                   "d3,7,3,6,10,0,2.5,north,1,0,0.001\n");
  test::write_text(tmp / "s.toml", std::string(kHead) + R"([[dfn]]
file = "discs.csv"
friction_angle = 25
order = "largest-first"
sets = { south = { friction_angle = 35, cohesion = 1e5, stage = 2 } }
[[joints]]
dip = 0
dip_direction = 0
point = [5, 5, 8]
set = "north"
friction_angle = 25
)");
  const auto j = (tmp / "j.h5").string();
  const auto r = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", j});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const slice::JointSystem js = slice::read_joints(j);
  REQUIRE(js.joints.size() == 4);
  REQUIRE(js.sets.size() == 2);
  CHECK(js.sets[0].name == "north");
  CHECK(js.sets[1].name == "south");
  // Stage 1: the hand-written joint and the north discs; stage 2: the south disc.
  CHECK(js.joints.back().friction_angle_deg == 35);
  CHECK(js.joints.back().cohesion == 1e5);
  CHECK(js.joints.back().set == 1);
  std::size_t north = 0;
  for (const auto& jt : js.joints)
    if (jt.set == 0) {
      ++north;
      CHECK(jt.friction_angle_deg == 25);
    }
  CHECK(north == 3);
  // Stage 1 in order: the discs largest first (d3, then d1), then the [[joints]] entry below.
  CHECK_THAT(slice::polygon_area(js.joints[0]), WithinRel(std::numbers::pi * 6.25, 1e-12));
  CHECK_THAT(slice::polygon_area(js.joints[1]), WithinRel(std::numbers::pi * 4, 1e-12));
  CHECK(js.joints[2].persistent());
  // Equal-area 16-gons: the ellipse's area pi r^2 / aspect.
  CHECK_THAT(slice::polygon_area(js.joints.back()), WithinRel(std::numbers::pi * 2.25 / 2, 1e-12));
  CHECK(js.joints.back().polygon_uv.size() == 16);
  const auto info = run_tool("slice-info", {j, "--json"});
  REQUIRE(info.exit_code == 0);
  const auto by_set = nlohmann::json::parse(info.out)["joints"]["by_set"];
  CHECK(by_set[0]["name"] == "north");
  CHECK(by_set[0]["joints"] == 3);
  CHECK(by_set[1]["intensity"] == "deterministic");
  // The provenance hashes the CSV beside the scene.
  const auto prov = slice::read_header(j).provenance;
  CHECK_THAT(prov.input_sha256, Contains(slice::sha256_file(tmp / "discs.csv")));
}

TEST_CASE("bad DFN files are refused by slice-joints with one line naming the line",
          "[tools][dfn]") {
  test::TempDir tmp;
  const std::string fab = kFab;
  const auto replace = [&](const std::string& from, const std::string& to) {
    return replaced(fab, from, to);
  };
  std::string big = "BEGIN FORMAT\nFormat = Ascii\nEND FORMAT\nBEGIN FRACTURE\n1 10000000 1\n";
  for (int k = 0; k < 40; ++k) big += "1 0 0 " + std::to_string(k) + "\n";
  const std::vector<BadInput> cases = {
      {"count",
       replace("No_Fractures = 5", "No_Fractures = 6"),
       {"net.fab:1:", "No_Fractures = 6", "5 fractures"}},
      {"nodes", replace("No_Nodes = 19", "No_Nodes = 20"), {"net.fab:1:", "No_Nodes = 20"}},
      {"props", replace("1 4 1 1e-6", "1 4 1"), {"net.fab:22:", "3 values; expected 4"}},
      {"end",
       replace("END FRACTURE\n\nBEGIN TESSFRACTURE\nEND TESSFRACTURE\n", ""),
       {"END FRACTURE is missing", "line 21"}},
      {"begin", replace("END FRACTURE\n", ""), {"net.fab:52:", "no END FRACTURE"}},
      {"nan", replace("2 8 1 3", "2 8 nan 3"), {"net.fab:24:", "not a finite number"}},
      {"huge", big, {"net.fab:5:", "claims 10000000 nodes"}},
      {"set", replace("5 4 3 3e-6", "5 4 4 3e-6"), {"net.fab:45:", "set 4", "SETS"}},
      {"planar", replace("4 3 9 7", "4 3 9 7.5"), {"net.fab:45:", "fracture 5", "not planar"}},
      {"short",
       replace("3 8 8 3\n4 1 8 3\n", "3 8 8 3\n"),
       {"net.fab:27:", "normal line of fracture 1"}},
      {"rock",
       replace("BEGIN TESSFRACTURE\n",
               "BEGIN ROCKBLOCK\n1 3 1 1\nEND ROCKBLOCK\nBEGIN TESSFRACTURE\n"),
       {"ROCKBLOCK", "not read"}},
      {"binary", replace("Format = Ascii", "Format = Binary"), {"net.fab:2:", "ASCII"}},
  };
  check_refused(tmp, cases, {"s.toml:6:"});
  // The scene's own mistakes: an unknown set in `sets`, a CSV without radius, a [[joints]] set
  // of another friction, -o on the DFN file.
  test::write_text(tmp / "net.fab", fab);
  test::write_text(tmp / "d.csv", "x,y,z,dip,dip_direction\n1,2,3,4,5\n");
  test::write_text(tmp / "t.csv", "x,y,z,dip,dip_direction,radius\n1,2,3,4,5,1e-300\n");
  const std::vector<BadInput> scenes = {
      {"sets",
       "[[dfn]]\nfile = \"net.fab\"\nsets = { D = { cohesion = 1 } }\n",
       {"unknown key 'D'"}},
      {"csv", "[[dfn]]\nfile = \"d.csv\"\n", {"d.csv:1:", "no column \"radius\""}},
      {"tiny", "[[dfn]]\nfile = \"t.csv\"\n", {"t.csv:2:", "disc row 1 reaches"}},
      {"friction",
       "[[dfn]]\nfile = \"net.fab\"\n[[joints]]\ndip = 0\ndip_direction = 0\npoint = [1, 1, 1]\n"
       "set = \"A\"\nfriction_angle = 20\n",
       {"friction_angle 20", "set \"A\""}},
  };
  for (const BadInput& c : scenes) {
    CAPTURE(c.name);
    test::write_text(tmp / "s.toml", std::string(kHead) + c.text);
    const auto r =
        run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", (tmp / "j.h5").string()});
    CAPTURE(r.err);
    CHECK(r.exit_code == 1);
    for (const auto& w : c.words) CHECK_THAT(r.err, Contains(w));
  }
  test::write_text(tmp / "s.toml", std::string(kHead) + "[[dfn]]\nfile = \"net.fab\"\n");
  const auto r =
      run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", (tmp / "net.fab").string()});
  CHECK(r.exit_code == 1);
  CHECK(test::read_bytes(tmp / "net.fab") == fab);
}

// Blocks that fail together (docs/stability.md, "Groups"): on one plane dipping 30 degrees east,
// an upper block on a weak joint leans on a lower block on a strong one. Each alone holds (the
// upper one can only move up past the lower one; the lower one has FoS tan phi_2 / tan 30); as
// one rigid body on the plane, its normal force spread over the plane by area (as for any body on
// a plane of several contacts, docs/stability.md), they have
//     FoS = (A_1 tan phi_1 + A_2 tan phi_2) / ((A_1 + A_2) tan 30),
// A_i the blocks' contact areas on the plane: the active-passive slide (YADE slides them:
// stability_dem_test.cpp). Here against that closed form, through the real tools: two blocks that
// fail together, two that hold together, three in a row (a group grown twice), --max-group 2 and
// 1 (one body at a time, the answer before groups).
#include <vtkCellData.h>
#include <vtkDataArray.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "support/pipeline.hpp"
#include "support/stability.hpp"
#include "support/vtu_read.hpp"

using Catch::Matchers::WithinRel;
using slice::Vec3;
using namespace test::stability;

namespace {

/// tests/data/stability-dem/two-block.toml with the frictions of the plane under the upper and
/// the lower block; `split`: a vertical joint x = 10 cuts the upper block in two (a, b).
std::string slab_scene(double phi_upper, double phi_lower, bool split) {
  std::string s = R"([scene]
name = "slab"
[domain]
box = { min = [0, 0, 0], max = [20, 12, 12] }
[options]
order = "as-given"
fixed_faces = ["-x", "-y", "+y", "-z"]
[[joints]]
dip = 90
dip_direction = 0
point = [10, 3, 6]
[[joints]]
dip = 90
dip_direction = 0
point = [10, 9, 6]
[[joints]]
dip = 90
dip_direction = 90
point = [15, 6, 6]
polygon_uv = [[-2.5, -7], [2.5, -7], [2.5, 7], [-2.5, 7]]
[[joints]]
dip = 0
dip_direction = 0
point = [17.5, 6, 7.5]
polygon_uv = [[-0.4, -0.4], [0.4, -0.4], [0.4, 0.4], [-0.4, 0.4]]
[[joints]]
dip = 30
dip_direction = 90
point = [10, 6, 7.886751345948]
polygon_uv = [[-0.4, -0.4], [0.4, -0.4], [0.4, 0.4], [-0.4, 0.4]]
friction_angle = )" +
                  num(phi_upper) + R"(
[[joints]]
dip = 30
dip_direction = 90
point = [17.5, 6, 3.556624327026]
polygon_uv = [[-0.4, -0.4], [0.4, -0.4], [0.4, 0.4], [-0.4, 0.4]]
friction_angle = )" +
                  num(phi_lower) + R"(
[[zones]]
box = { min = [15, 0, 7.5], max = [20, 12, 12] }
)";
  if (split)  // through the upper block only (it is cut last)
    s += R"([[joints]]
dip = 90
dip_direction = 90
point = [10, 6, 10]
polygon_uv = [[-0.4, -0.4], [0.4, -0.4], [0.4, 0.4], [-0.4, 0.4]]
)";
  return s;
}

constexpr std::int64_t kUpperPlane = 4;  // the joint under the upper block(s)
const Vec3 kDownDip(std::cos(rad(30)), 0, -std::sin(rad(30)));

/// The slab's blocks that may move, west to east.
std::vector<std::size_t> west_to_east(const Model& m) {
  auto body = movable_blocks(m);
  std::sort(body.begin(), body.end(),
            [&](std::size_t x, std::size_t y) { return m.centroid(x).x() < m.centroid(y).x(); });
  return body;
}

/// (sum of A_i tan phi_i) / (A tan 30) over blocks `of`: A_i a block's contact on its plane
/// (joint 4 under the upper blocks, 5 under the lower one).
double together(const Model& m, const std::vector<std::size_t>& of, double phi_upper,
                double phi_lower) {
  double resisting = 0, area = 0;
  for (const std::size_t b : of) {
    const bool upper = m.centroid(b).x() < 15;
    const double a = area_on(m, b, upper ? kUpperPlane : kUpperPlane + 1);
    resisting += a * tand(upper ? phi_upper : phi_lower);
    area += a;
  }
  return resisting / (area * tand(30));
}

/// The members fail together in round `generation` with FoS `fos`, down the dip; their sliding
/// plane is the joint of the group's largest contact on it: `joint`, or either plane's joint
/// when two contacts are as large (-1).
void check_fails_together(const Model& m, const std::vector<std::size_t>& members, double fos,
                          int generation, std::int64_t joint = kUpperPlane) {
  const std::int64_t first = std::int64_t(*std::min_element(members.begin(), members.end()));
  for (const std::size_t b : members) {
    CAPTURE(b);
    CHECK(m.st.mode[b] == 4);
    CHECK(m.st.removable[b] == 1);
    CHECK_THAT(m.st.fos[b], WithinRel(fos, 1e-9));
    check_direction(m.st.direction[b], kDownDip);
    CHECK(m.st.planes[b][1] == -1);
    if (joint >= 0)
      CHECK(m.st.planes[b][0] == joint);
    else
      CHECK((m.st.planes[b][0] == kUpperPlane || m.st.planes[b][0] == kUpperPlane + 1));
    CHECK(m.st.generation[b] == generation);
    CHECK(m.st.group[b] == (members.size() > 1 ? first : -1));
  }
}

}  // namespace

TEST_CASE("two blocks on one plane that hold alone fail together, as one rigid body",
          "[tools][stability]") {
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, slab_scene(15, 40, false));
  const Run run{{"--free-faces", "+x,+z"}, "+x,+z"};
  const auto m = stability_of(tmp, geom, run);
  const auto body = west_to_east(m);
  REQUIRE(body.size() == 2);
  const std::size_t upper = body[0], lower = body[1];
  // The closed-form volumes (a prism on the triangle 7 / tan 30 by 7, and on the trapezium 5 by
  // (2.5 + 7.5 - (5 - 5 tan 30)), each 6 wide) and contacts on the plane (6 wide, 7 / sin 30 and
  // 5 / cos 30 down the dip).
  CHECK_THAT(m.volume(upper), WithinRel(6 * 0.5 * 7 * 7 / tand(30), 1e-9));
  CHECK_THAT(m.volume(lower), WithinRel(6 * 5 * (2.5 + 2.5 + 5 * tand(30)) / 2, 1e-9));
  CHECK_THAT(area_on(m, upper, kUpperPlane), WithinRel(6 * 7 / std::sin(rad(30)), 1e-9));
  CHECK_THAT(area_on(m, lower, kUpperPlane + 1), WithinRel(6 * 5 / std::cos(rad(30)), 1e-9));
  const double fos = together(m, body, 15, 40);
  CAPTURE(fos);
  CHECK_THAT(fos, WithinRel(0.75295, 1e-4));
  check_fails_together(m, body, fos, 0);

  // --max-group 1: one body at a time, the answer before groups: the upper block can only move
  // up past the lower one (removable, stable), the lower one holds.
  const auto one = stability_of(
      tmp, geom, Run{{"--free-faces", "+x,+z", "--max-group", "1"}, "+x,+z"}, "one.h5");
  CHECK(one.st.mode[upper] == 2);
  CHECK(one.st.generation[upper] == -1);
  CHECK(one.st.mode[lower] == 4);
  CHECK_THAT(one.st.fos[lower], WithinRel(tand(40) / tand(30), 1e-9));
  CHECK(one.st.generation[lower] == -1);
  CHECK(one.st.group[upper] == -1);
  CHECK(one.st.group[lower] == -1);
}

TEST_CASE("two blocks on one plane that hold together keep their own answers",
          "[tools][stability]") {
  // Friction 60 under the lower block: together (A_1 tan 15 + A_2 tan 60) / (A tan 30) = 1.20.
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, slab_scene(15, 60, false));
  const auto m = stability_of(tmp, geom, Run{{"--free-faces", "+x,+z"}, "+x,+z"});
  const auto body = west_to_east(m);
  REQUIRE(body.size() == 2);
  CHECK(together(m, body, 15, 60) > 1.15);
  CHECK(m.st.mode[body[0]] == 2);
  CHECK(m.st.mode[body[1]] == 4);
  CHECK_THAT(m.st.fos[body[1]], WithinRel(tand(60) / tand(30), 1e-9));
  for (const std::size_t b : body) {
    CHECK(m.st.generation[b] == -1);
    CHECK(m.st.group[b] == -1);
  }
}

TEST_CASE("three blocks in a row fail together: the weakest group of those that fail",
          "[tools][stability]") {
  // a and b on friction 15, c on 40: {b, c} fails (0.96), {a, b, c} fails more (0.75) and is
  // taken.
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, slab_scene(15, 40, true));
  const auto m = stability_of(tmp, geom, Run{{"--free-faces", "+x,+z"}, "+x,+z"});
  const auto body = west_to_east(m);
  REQUIRE(body.size() == 3);
  const std::size_t a = body[0], b = body[1], c = body[2];
  CHECK(m.centroid(a).x() < 10);
  CHECK(m.centroid(b).x() > 10);
  CHECK(m.centroid(c).x() > 15);
  const double all = together(m, body, 15, 40), bc = together(m, {b, c}, 15, 40);
  CAPTURE(all, bc);
  CHECK(all < bc);
  CHECK(bc < 1);
  check_fails_together(m, body, all, 0);

  // At most two bodies in a group: {b, c} in round 0, then a alone (tan 15 / tan 30) in round 1.
  const auto two = stability_of(
      tmp, geom, Run{{"--free-faces", "+x,+z", "--max-group", "2"}, "+x,+z"}, "two.h5");
  CHECK_THAT(area_on(two, b, kUpperPlane), WithinRel(area_on(two, c, kUpperPlane + 1), 1e-9));
  check_fails_together(two, {b, c}, bc, 0, -1);  // b's and c's contacts: 6 x 5 / cos 30 each
  check_fails_together(two, {a}, tand(15) / tand(30), 1);
}

TEST_CASE("the VTU export carries /stability per block, the groups too", "[tools][stability]") {
  // ParaView colours blocks by these arrays (docs/stability.md, "Output"): each cell has its
  // block's values; fos is NaN where the file has +inf.
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, slab_scene(15, 40, true));
  const auto m = stability_of(
      tmp, geom, Run{{"--free-faces", "+x,+z", "--max-group", "2"}, "+x,+z"}, "stab.h5");
  const std::string vtu = (tmp / "stab.vtu").string();
  const auto r = test::run_tool("slice-export", {m.path, "--format", "vtu", "-o", vtu});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto grid = test::read_vtu(vtu);
  auto* cells = grid->GetCellData();
  auto* id = cells->GetArray("block_id");
  REQUIRE(id != nullptr);
  std::size_t kept = 0, grouped = 0, failing = 0;
  for (std::size_t b = 0; b < m.blocks(); ++b) kept += m.removed(std::int64_t(b)) ? 0 : 1;
  REQUIRE(std::size_t(grid->GetNumberOfCells()) == kept);
  for (const char* name : {"removable", "mode", "fos", "direction", "generation", "group"})
    REQUIRE(cells->GetArray(name) != nullptr);
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    const auto b = std::size_t(id->GetTuple1(c));
    CAPTURE(c, b);
    CHECK(cells->GetArray("removable")->GetTuple1(c) == m.st.removable[b]);
    CHECK(cells->GetArray("mode")->GetTuple1(c) == m.st.mode[b]);
    const double fos = cells->GetArray("fos")->GetTuple1(c);
    if (std::isinf(m.st.fos[b]))
      CHECK(std::isnan(fos));
    else
      CHECK(fos == m.st.fos[b]);
    const double* d = cells->GetArray("direction")->GetTuple3(c);
    CHECK(Vec3(d[0], d[1], d[2]) == m.st.direction[b]);
    CHECK(cells->GetArray("generation")->GetTuple1(c) == m.st.generation[b]);
    CHECK(cells->GetArray("group")->GetTuple1(c) == double(m.st.group[b]));
    grouped += m.st.group[b] >= 0 ? 1 : 0;
    failing += m.st.generation[b] >= 0 ? 1 : 0;
  }
  CHECK(grouped == 2);  // {b, c}, and a alone in round 1
  CHECK(failing == 3);
}

TEST_CASE("a stab.h5 from before groups reads as one body at a time, and a bad group is refused",
          "[tools][stability]") {
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, slab_scene(15, 40, false));
  const auto m = stability_of(tmp, geom, Run{{"--free-faces", "+x,+z"}, "+x,+z"});
  const std::size_t first = west_to_east(m)[0];
  CHECK(m.st.group[first] >= 0);
  const auto copy = [&](const std::string& name) {
    const auto to = tmp / name;
    test::fs::copy_file(m.path, to);
    return to;
  };
  // Written before groups: no /stability/group, no max_group attribute.
  const auto old = copy("old.h5");
  test::edit_h5(old, "del f['stability/group']\ndel f['stability'].attrs['max_group']\n");
  const auto info = test::run_tool("slice-info", {old.string(), "--json"});
  INFO(info.err);
  REQUIRE(info.exit_code == 0);
  const auto j = nlohmann::json::parse(info.out)["stability"];
  CHECK(j["options"]["max_group"] == 1);
  CHECK(j["failing_in_groups"]["groups"] == 0);
  CHECK(j["failing"] == 2);  // the file's own answers are kept
  // Damaged: a group that names no block, a block that does not fail, or max_group 0.
  for (const auto& [name, edit, words] :
       std::vector<std::tuple<std::string, std::string, std::vector<std::string>>>{
           {"far.h5",
            "f['stability/group'][" + std::to_string(first) + "] = 10**6",
            {"/stability/group"}},
           {"holds.h5",
            "f['stability/generation'][" + std::to_string(first) + "] = -1",
            {"/stability/group"}},
           {"zero.h5", "f['stability'].attrs.modify('max_group', np.int64(0))", {"max_group"}}}) {
    CAPTURE(name);
    const auto bad = copy(name);
    test::edit_h5(bad, edit);
    test::check_refused(test::run_tool("slice-info", {bad.string()}), "slice-info", words);
  }
}

TEST_CASE("groups only add failures: what fails one body at a time fails with groups too",
          "[tools][stability]") {
  // A group that fails is a real mechanism (a rigid body's limit equilibrium), and a body taken
  // out only frees its neighbours: whatever fails with --max-group 1 fails with groups, no later.
  struct Case {
    std::string scene, free_faces;
  };
  const auto dem = [](const std::string& name) {
    return test::read_bytes(test::test_data_path("stability-dem/" + name));
  };
  for (const auto& c :
       std::vector<Case>{{test::read_bytes(test::data_path("rock-slope.toml")), "+z,+x"},
                         {dem("slope.toml"), "+x,+z"},
                         {dem("chamber.toml"), ""},
                         {goodman_scene(Frame{}), ""},
                         {slab_scene(15, 40, true), "+x,+z"},
                         {slab_scene(25, 35, true), "+x,+z"}}) {
    CAPTURE(c.scene.substr(0, 60), c.free_faces);
    test::TempDir tmp;
    const auto geom = geometry_of(tmp, c.scene);
    std::vector<std::string> args;
    if (!c.free_faces.empty()) args = {"--free-faces", c.free_faces};
    const auto grouped = stability_of(tmp, geom, Run{args, c.free_faces}, "grouped.h5");
    args.insert(args.end(), {"--max-group", "1"});
    const auto alone = stability_of(tmp, geom, Run{args, c.free_faces}, "alone.h5");
    std::size_t more = 0;
    for (std::size_t b = 0; b < alone.blocks(); ++b) {
      CAPTURE(b);
      CHECK(alone.st.group[b] == -1);
      if (alone.st.generation[b] >= 0) {
        CHECK(grouped.st.generation[b] >= 0);
        CHECK(grouped.st.generation[b] <= alone.st.generation[b]);
      }
      more += grouped.st.generation[b] >= 0 && alone.st.generation[b] < 0 ? 1 : 0;
      // Failing alone at once in both: the same answer (round 0 analyses each body alike).
      if (alone.st.generation[b] == 0 && grouped.st.generation[b] == 0 && grouped.st.group[b] < 0)
        CHECK(grouped.st.fos[b] == alone.st.fos[b]);
    }
    // Fails only in a group: the group says so.
    for (std::size_t b = 0; b < alone.blocks(); ++b)
      if (grouped.st.generation[b] >= 0 && alone.st.generation[b] < 0)
        CHECK((grouped.st.group[b] >= 0 || grouped.st.generation[b] > 0));
    INFO(more << " blocks fail only with groups");
  }
}

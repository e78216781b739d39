// Models a DEM run can use, through the real tools: no free sliver in the examples and in the
// bench slope over several seeds (the volumes still add up, and a block removed with an
// excavation lies within the minimum size of a zone); the time step slice-info and slice-export
// report is the one the YADE script sets in YADE; the open joint area (P32) each set keeps.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "slice/h5io.hpp"
#include "slice/lp.hpp"
#include "support/blocks_check.hpp"
#include "support/support.hpp"

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using test::run_tool;

namespace {

/// joints -> cut (with --stats) + prune -> vertices on a data/ scene with an optional --seed.
std::string slice_scene(const test::TempDir& tmp, const std::string& scene, const std::string& seed,
                        nlohmann::json& stats) {
  const std::string joints = (tmp / "joints.h5").string(), blocks = (tmp / "blocks.h5").string(),
                    geom = (tmp / "geom.h5").string(), json = (tmp / "stats.json").string();
  const test::fs::path file =
      scene.find('/') == std::string::npos ? test::data_path(scene) : test::fs::path(scene);
  std::vector<std::string> args = {file.string(), "-o", joints};
  if (!seed.empty()) args.insert(args.end(), {"--seed", seed});
  const auto j = run_tool("slice-joints", args);
  INFO(j.err);
  REQUIRE(j.exit_code == 0);
  const auto c = run_tool("slice-cut", {joints, "--prune", "--stats", json, "-o", blocks});
  INFO(c.err);
  REQUIRE(c.exit_code == 0);
  const auto v = run_tool("slice-vertices", {blocks, "-o", geom});
  INFO(v.err);
  REQUIRE(v.exit_code == 0);
  stats = nlohmann::json::parse(test::read_bytes(json));
  return geom;
}

/// Whether x lies in one of the zones grown by `grow` (each zone's planes moved out by it).
bool near_a_zone(const slice::JointSystem& js, const slice::Vec3& x, double grow) {
  for (const auto& z : js.zones) {
    bool inside = true;
    for (const auto& p : z.planes) inside = inside && p.distance(x) <= grow;
    if (inside) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("no free sliver in the examples and the bench slope and the volumes add up",
          "[tools][cut][slivers]") {
  struct Case {
    std::string scene, seed;
  };
  const auto c = GENERATE(Case{"slope.toml", ""}, Case{"tunnel.toml", ""},
                          Case{"rock-slope.toml", ""}, Case{"bench-slope.toml", "7"},
                          Case{"bench-slope.toml", "8"}, Case{"bench-slope.toml", "9"});
  const bool excavate = GENERATE(false, true);  // [options] slivers = "join" | "excavate"
  CAPTURE(c.scene, c.seed, excavate);
  test::TempDir tmp;
  std::string scene = c.scene;
  if (excavate) {
    std::string text = test::read_bytes(test::data_path(c.scene));
    const auto at = text.find("[options]\n");
    REQUIRE(at != std::string::npos);
    text.insert(at + 10, "slivers = \"excavate\"\n");
    scene = (tmp / "excavate.toml").string();
    test::write_text(scene, text);
  }
  nlohmann::json stats;
  const auto bs = slice::read_blocks(slice_scene(tmp, scene, c.seed, stats));
  const auto& g = *bs.geometry;
  const double dmin = bs.joints.options.min_inscribed_diameter;
  const double L = bs.joints.length_scale;
  REQUIRE(dmin > 0);
  CHECK(stats["slivers_left"] == 0);
  if (c.scene != "rock-slope.toml") {  // the pit, slope and tunnel outlines do leave slivers
    CHECK(stats["slivers_joined"].get<int>() > 0);
    CHECK((stats["slivers_removed"].get<int>() > 0) == excavate);
  }
  double volume = 0;
  std::size_t free_blocks = 0;
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    CAPTURE(i);
    const auto& b = bs.blocks[i];
    volume += g.volume[i];
    if (b.flags & slice::kRemoved) {
      // Removed by a zone (centre inside), or a sliver gone with one: then every vertex lies
      // within the minimum size of a zone.
      if (near_a_zone(bs.joints, b.origin, 0)) continue;
      CHECK(excavate);
      CHECK(2 * b.inradius < dmin);
      for (auto v = g.vertex_offset[i]; v < g.vertex_offset[i + 1]; ++v)
        CHECK(near_a_zone(bs.joints, g.vertices[std::size_t(v)], dmin + 1e-9 * L));
      continue;
    }
    if (b.cluster >= 0) continue;
    ++free_blocks;
    CHECK(2 * b.inradius >= dmin - 1e-9 * L);
  }
  CHECK(free_blocks > 0);
  // Nor a cluster of slivers only: the smallest body of the model, as a free sliver would be.
  std::map<std::int64_t, bool> all_thin;
  for (const auto& b : bs.blocks)
    if (!(b.flags & slice::kRemoved) && b.cluster >= 0) {
      const bool thin = 2 * b.inradius < dmin - 1e-9 * L;
      all_thin.emplace(b.cluster, true).first->second &= thin;
    }
  for (const auto& [cluster, thin] : all_thin) {
    CAPTURE(cluster);
    CHECK_FALSE(thin);
  }
  CHECK_THAT(volume, WithinRel(test::domain_volume(bs.joints), 1e-9));
}

TEST_CASE("slice-info and slice-export report the time step the YADE script sets",
          "[tools][export][yade][slivers]") {
  test::TempDir tmp;
  nlohmann::json stats;
  const std::string geom = slice_scene(tmp, "rock-slope.toml", "", stats);
  const auto bs = slice::read_blocks(geom);
  const auto& g = *bs.geometry;
  // The smallest free block, found here from the file: kept, in no cluster, not fixed.
  std::int64_t smallest = -1;
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    const auto& b = bs.blocks[i];
    if ((b.flags & (slice::kRemoved | slice::kBoundary | slice::kFixed)) || b.cluster >= 0)
      continue;
    if (smallest < 0 || g.volume[i] < g.volume[std::size_t(smallest)]) smallest = std::int64_t(i);
  }
  REQUIRE(smallest >= 0);

  const auto info = run_tool("slice-info", {geom, "--json", "--yade-density", "2500"});
  INFO(info.err);
  REQUIRE(info.exit_code == 0);
  const auto j = nlohmann::json::parse(info.out);
  const auto& dem = j["dem"];
  CHECK(dem["smallest_free_block"]["block"] == smallest);
  CHECK_THAT(dem["smallest_free_block"]["volume"].get<double>(),
             WithinRel(g.volume[std::size_t(smallest)], 1e-15));
  CHECK_THAT(dem["smallest_free_block"]["inradius"].get<double>(),
             WithinRel(bs.blocks[std::size_t(smallest)].inradius, 1e-15));
  const double info_dt = dem["yade_timestep"]["dt"].get<double>();
  CHECK(dem["yade_timestep"]["density"] == 2500.0);

  const std::string model = (tmp / "model.py").string(), report = (tmp / "report.json").string();
  const auto ex =
      run_tool("slice-export", {geom, "--format", "yade", "--yade-density", "2500", "-o", model});
  INFO(ex.err);
  REQUIRE(ex.exit_code == 0);
  std::smatch m;
  REQUIRE(std::regex_search(ex.err, m, std::regex("O\\.dt = ([0-9.e+-]+) s")));
  const double export_dt = std::stod(m[1]);
  CHECK_THAT(export_dt, WithinRel(info_dt, 1e-3));  // printed with 4 digits
  CHECK(ex.err.find("smallest free block: " + std::to_string(smallest) + " ") != std::string::npos);

  const int code = test::run_yade_report(model, report, tmp / "yade.log");
  INFO("yade log (tail): " << test::tail_of(tmp / "yade.log"));
  REQUIRE(code == 0);
  const auto r = nlohmann::json::parse(test::read_bytes(report));
  REQUIRE_FALSE(r.contains("error"));
  CHECK_THAT(r["dt"].get<double>(), WithinRel(info_dt, 1e-12));
}

TEST_CASE("slice-info reports each set's open joint area in the block model (P32)",
          "[tools][info][p32]") {
  test::TempDir tmp;
  nlohmann::json stats;
  // cube-3sets: three persistent sets and no size limit, so every joint plane is cut through the
  // whole domain: the block model keeps exactly the DFN's P32 (area in the domain / volume).
  const std::string cube = slice_scene(tmp, "cube-3sets.toml", "", stats);
  auto info = run_tool("slice-info", {cube, "--json"});
  REQUIRE(info.exit_code == 0);
  auto j = nlohmann::json::parse(info.out);
  REQUIRE(j["joints"]["by_set"].size() == 3);
  for (const auto& set : j["joints"]["by_set"]) {
    CAPTURE(set.dump());
    CHECK(set["p32"].get<double>() > 0);
    CHECK_THAT(set["p32_blocks"].get<double>(), WithinRel(set["p32"].get<double>(), 1e-9));
  }
  // The bench slope: finite joints and a size limit keep less than the DFN's, never more.
  test::TempDir tmp2;
  const std::string bench = slice_scene(tmp2, "bench-slope.toml", "", stats);
  info = run_tool("slice-info", {bench, "--json"});
  REQUIRE(info.exit_code == 0);
  j = nlohmann::json::parse(info.out);
  for (const auto& set : j["joints"]["by_set"]) {
    CAPTURE(set.dump());
    CHECK(set["p32_blocks"].get<double>() > 0.3 * set["p32"].get<double>());
    CHECK(set["p32_blocks"].get<double>() < set["p32"].get<double>());
  }
}

TEST_CASE("a rock bridge carries intact rock's friction into the YADE model",
          "[tools][export][yade][bridges]") {
  // Lognormal squares (Table 3): the cut extends them through whole blocks, so many faces are
  // partly rock bridge. With [rock], a block's friction angle is the smallest over its rock
  // faces of f x the joint's + (1 - f) x [rock]'s (f: face_joint_fraction).
  test::TempDir tmp;
  std::string text = test::read_bytes(test::data_path("table3-lognormal.toml"));
  text += "\n[rock]\nfriction_angle = 50\ncohesion = 1e6\ntension = 5e5\n";
  const std::string scene = (tmp / "bridged.toml").string();
  test::write_text(scene, text);
  nlohmann::json stats;
  const std::string geom = slice_scene(tmp, scene, "", stats);
  const auto bs = slice::read_blocks(geom);
  const auto& g = *bs.geometry;
  const std::string model = (tmp / "model.py").string();
  const auto ex = run_tool("slice-export", {geom, "--format", "yade", "-o", model, "-q"});
  INFO(ex.err);
  REQUIRE(ex.exit_code == 0);
  std::map<std::size_t, double> friction;  // from the script's BLOCKS rows
  std::istringstream lines(test::read_bytes(model));
  const std::regex row("^\\((\\d+), [01], ([0-9.e+-]+),");
  for (std::string line; std::getline(lines, line);)
    if (std::smatch m; std::regex_search(line, m, row))
      friction[std::stoul(m[1])] = std::stod(m[2]);
  std::size_t face = 0, raised = 0, checked = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); face += bs.blocks[b++].faces.size()) {
    if (bs.blocks[b].flags & slice::kRemoved) continue;
    double want = 1e9, joints_only = 1e9;
    for (std::size_t k = 0; k < bs.blocks[b].faces.size(); ++k) {
      const auto j = bs.blocks[b].faces[k].joint;
      if (j < 0) continue;
      const double phi = bs.joints.joints[std::size_t(j)].friction_angle_deg;
      const double f = g.face_joint_fraction[face + k];
      want = std::min(want, f * phi + (1 - f) * 50);
      joints_only = std::min(joints_only, phi);
    }
    if (want > 1e8) continue;  // no joint face: the default
    REQUIRE(friction.count(b));
    CHECK_THAT(friction[b], WithinAbs(want, 1e-9));
    raised += friction[b] > joints_only + 1e-9 ? 1 : 0;
    ++checked;
  }
  CHECK(checked > 1000);
  CHECK(raised > 0);  // some blocks are held by bridges on every side
}

// Sections of a 3-D scene through the real tools (issue 26, item 4; docs/2d.md): slice-joints
// reports each 3-D set's trace; a 2-D tunnel zone with cut = true removes exactly its outline's
// area; slice-export --format udec writes one clockwise `block create polygon` per kept block,
// and refuses a 3-D file naming it.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "slice/export_udec.hpp"
#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec2;
using test::run_tool;

namespace {

// A star-shaped outline about the tunnel's centre (a horseshoe with a reflex floor vertex), in
// (x, z) offsets; its area by the shoelace formula.
const std::vector<Vec2> kHorseshoe = {{0, -1.5}, {2, -2},     {3.5, 0}, {3, 2},    {1.5, 3.4},
                                      {0, 3.8},  {-1.5, 3.4}, {-3, 2},  {-3.5, 0}, {-2, -2}};

double shoelace(const std::vector<Vec2>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 u = p[i], v = p[(i + 1) % p.size()];
    a += 0.5 * (u.x() * v.y() - u.y() * v.x());
  }
  return a;
}

// The pipeline on `text` into tmp; the geometry file.
std::string run_section(const test::TempDir& tmp, const std::string& text) {
  test::write_text(tmp / "s.toml", text);
  const std::string joints = (tmp / "joints.h5").string(), blocks = (tmp / "blocks.h5").string(),
                    geom = (tmp / "geom.h5").string();
  for (const auto& [tool, args] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"slice-joints", {(tmp / "s.toml").string(), "-o", joints}},
           {"slice-cut", {joints, "-o", blocks, "--prune"}},
           {"slice-vertices", {blocks, "-o", geom}}}) {
    const auto r = run_tool(tool, args);
    INFO(tool << ": " << r.err);
    REQUIRE(r.exit_code == 0);
  }
  return geom;
}

// slice-joints run again on run_section's s.toml with the same command line (the provenance
// records it): it writes the same joints.h5 bytes. Its run, for its messages.
test::ToolRun rerun_joints(const test::TempDir& tmp) {
  const std::string first = test::read_bytes(tmp / "joints.h5");
  const auto again = (tmp / "joints.h5").string();
  test::fs::remove(again);
  auto r = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", again});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(test::read_bytes(again) == first);
  return r;
}

std::string tunnel_scene(const std::string& tunnel, bool cut) {
  return "[scene]\nname = \"t\"\ndimension = 2\n[section]\npoint = [0, 0, 0]\nstrike = 30\n"
         "[domain]\nbox = { min = [-20, 0], max = [20, 30] }\n"
         "[[sets]]\ndip = 70\ndip_direction = 250\nspacing = 2.3\n"
         "[[sets]]\ndip = 25\ndip_direction = 60\nspacing = 1.7\noffset = 0.3\n"
         "[[zones]]\ntunnel = { point = [1.5, 14], " +
         tunnel + " }\n" + (cut ? "cut = true\n" : "");
}

double removed_area(const slice::BlockSystem& bs) {
  double a = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b)
    if (bs.blocks[b].flags & slice::kRemoved) a += bs.geometry->volume[b];
  return a;
}

}  // namespace

TEST_CASE("slice-joints traces the issue's 3-D set in data/tunnel-section.toml",
          "[tools][section3d]") {
  test::TempDir tmp;
  const std::string out = (tmp / "j.h5").string();
  const auto r =
      run_tool("slice-joints", {std::string(SLICE_DATA_DIR) + "/tunnel-section.toml", "-o", out});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.err, Contains("set \"J1\" (dip 85, dip direction 220) in the section (strike 90): "
                             "apparent dip 82.25 towards 270, spacing 7.737, "));
  const slice::JointSystem js = slice::read_joints(out);
  REQUIRE(js.sets.size() == 3);
  CHECK(js.dimension == 2);
  CHECK(js.sets[0].dip_direction_deg == 270);
  CHECK_THAT(js.sets[0].dip_deg, WithinAbs(82.25, 0.005));
  CHECK_THAT(js.sets[0].spacing, WithinAbs(7.737, 0.0005));
}

TEST_CASE("a cut 2-D tunnel removes exactly its outline's area", "[tools][section3d][tunnel]") {
  const double r = 3;
  const double round = 16 * r * r * std::tan(std::numbers::pi / 16);  // the 16-gon about r
  std::string outline = "outline = [";
  for (std::size_t i = 0; i < kHorseshoe.size(); ++i)
    outline += (i ? ", [" : "[") + std::to_string(kHorseshoe[i].x()) + ", " +
               std::to_string(kHorseshoe[i].y()) + "]";
  outline += "]";
  const std::vector<std::pair<std::string, double>> cases = {{"radius = 3", round},
                                                             {outline, shoelace(kHorseshoe)}};
  for (const auto& [keys, area] : cases) {
    CAPTURE(keys);
    test::TempDir tmp;
    const slice::BlockSystem cut = slice::read_blocks(run_section(tmp, tunnel_scene(keys, true)));
    CHECK_THAT(removed_area(cut), WithinRel(area, 1e-9));
    double total = 0;
    for (const double v : cut.geometry->volume) total += v;
    CHECK_THAT(total, WithinRel(40.0 * 30.0, 1e-12));
    // Without cut: whole rock blocks whose centres are inside, not the outline.
    const slice::BlockSystem whole =
        slice::read_blocks(run_section(tmp, tunnel_scene(keys, false)));
    CHECK(std::abs(removed_area(whole) - area) > 1e-3 * area);
  }
}

TEST_CASE("slice-export --format udec writes each kept block as a clockwise polygon",
          "[tools][section3d][udec]") {
  test::TempDir tmp;
  const std::string geom = test::run_pipeline(tmp, "tunnel-section.toml", test::Stage::geometry);
  const slice::BlockSystem bs = slice::read_blocks(geom);
  const std::string out = (tmp / "section.dat").string();
  const auto r = run_tool("slice-export", {geom, "--format", "udec", "-o", out});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  std::size_t kept = 0, removed = 0;
  for (const auto& b : bs.blocks) (b.flags & slice::kRemoved ? removed : kept) += 1;
  REQUIRE(removed > 0);
  CHECK_THAT(r.err, Contains(std::to_string(kept) + " blocks (" + std::to_string(removed) +
                             " removed left out)"));
  std::ifstream in(out);
  std::string line;
  std::size_t blocks = 0, row = 0;
  std::vector<std::size_t> rows;
  bool model_new = false;
  while (std::getline(in, line)) {
    if (line.rfind(";", 0) == 0) {  // a comment: "; block N ..." names the next block's row
      if (line.rfind("; block ", 0) == 0) row = std::stoul(line.substr(8)) - 1;
      continue;
    }
    if (line == "model new") {
      model_new = true;
      continue;
    }
    REQUIRE(line.rfind("block create polygon ", 0) == 0);
    REQUIRE(row < bs.blocks.size());
    CHECK_FALSE((bs.blocks[row].flags & slice::kRemoved));
    rows.push_back(row);
    std::istringstream words(line.substr(21));
    std::vector<Vec2> pts;
    std::string w;
    while (words >> w) {
      const auto comma = w.find(',');
      REQUIRE(comma != std::string::npos);
      pts.emplace_back(std::stod(w.substr(0, comma)), std::stod(w.substr(comma + 1)));
    }
    // The block's polygon, clockwise (negative area), its corners the geometry's exactly.
    const auto& g = *bs.geometry;
    const auto v0 = std::size_t(g.vertex_offset[row]), v1 = std::size_t(g.vertex_offset[row + 1]);
    REQUIRE(pts.size() == v1 - v0);
    CHECK(pts.size() >= 3);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const auto& v = g.vertices[v1 - 1 - k];
      CHECK(pts[k] == Vec2(v.x(), v.z()));
    }
    CHECK(shoelace(pts) < 0);
    CHECK_THAT(-shoelace(pts), WithinRel(g.volume[row], 1e-9));
    ++blocks;
  }
  CHECK(model_new);
  CHECK(blocks == kept);
  CHECK(std::is_sorted(rows.begin(), rows.end()));
}

TEST_CASE("the UDEC export escapes the scene's name and refuses a 3-D file naming it",
          "[tools][section3d][udec][bad-input]") {
  test::TempDir tmp;
  // A name with a newline and a UDEC command after it stays inside its comment line.
  const std::string geom =
      run_section(tmp,
                  "[scene]\nname = \"a\\nmodel new\\nblock delete\"\ndimension = 2\n"
                  "[domain]\nbox = { min = [0, 0], max = [4, 3] }\n"
                  "[[sets]]\ndip = 45\ndip_direction = 90\nspacing = 1\n");
  const std::string out = (tmp / "s.dat").string();
  REQUIRE(run_tool("slice-export", {geom, "--format", "udec", "-o", out}).exit_code == 0);
  std::ifstream in(out);
  std::string line;
  std::size_t model_new = 0;
  while (std::getline(in, line)) {
    CHECK((line.find("block delete") == std::string::npos || line.rfind(";", 0) == 0));
    model_new += line == "model new" ? 1 : 0;
  }
  CHECK(model_new == 1);

  // A 3-D geometry file: exit 1, one line naming it, nothing written.
  const std::string geom3 = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry);
  const std::string out3 = (tmp / "three.dat").string();
  const auto r = run_tool("slice-export", {geom3, "--format", "udec", "-o", out3});
  test::check_refused(r, "slice-export", {geom3, "3-D", "UDEC", "--format 3dec"});
  CHECK_FALSE(test::fs::exists(out3));
}

TEST_CASE("slice-joints refuses a bad section or 2-D tunnel with its line",
          "[tools][section3d][bad-input]") {
  const std::string head =
      "[scene]\ndimension = 2\n[section]\npoint = [0, 0, 0]\nstrike = 90\n"
      "[domain]\nbox = { min = [0, 0], max = [20, 10] }\n";
  test::check_bad_scenes({
      {"a set parallel to the section",
       head + "[[sets]]\ndip = 90\ndip_direction = 180\nspacing = 1\n",
       {":9", "parallel to the section", "no trace"}},
      {"a 2-D tunnel with a 3-D axis",
       head + "[[zones]]\ntunnel = { point = [5, 5], radius = 1, length = 3 }\n",
       {":9", "'length'", "3-D tunnels"}},
      {"a 2-D tunnel off its centre",
       head + "[[zones]]\ntunnel = { point = [5, 5], outline = [[1, 1], [2, 1], [2, 2]] }\n",
       {":9", "star-shaped"}},
      {"a p10 3-D set with a scanline (its p10 counts along its mean pole)",
       head + "[[sets]]\ndip = 60\ndip_direction = 10\np10 = 0.5\n"
              "scanline = { from = [1, 0, 1], to = [19, 0, 9] }\n"
              "size = { distribution = \"fixed\", value = 2 }\n",
       {":12", "'scanline'", "mean pole", "remove 'scanline'"}},
      {"a count 3-D set without a size",
       head + "[[sets]]\ndip = 60\ndip_direction = 10\ncount = 50\n",
       {":11", "needs a size", "segments"}},
      {"a stochastic 3-D set without a size",
       head + "[[sets]]\ndip = 60\ndip_direction = 10\ndensity = 0.01\n",
       {":11", "needs a size", "segments"}},
      {"scatter on a regular set in a section",
       head + "[[sets]]\ndip = 60\ndip_direction = 10\nspacing = 2\nfisher_kappa = 20\n",
       {":12", "fisher_kappa", "regular set"}},
      {"a stochastic set in a 2-D scene without a section",
       "[scene]\ndimension = 2\n[domain]\nbox = { min = [0, 0], max = [20, 10] }\n"
       "[[sets]]\ndip = 60\ndip_direction = 90\ndensity = 0.01\n"
       "size = { distribution = \"fixed\", value = 2 }\n",
       {":8", "regular lines", "[section]"}},
  });
}

TEST_CASE("a stochastic 3-D set in a section: its traces, reproducible byte for byte, cut",
          "[tools][section3d]") {
  test::TempDir tmp;
  const std::string scene =
      "[scene]\nname = \"traced\"\ndimension = 2\nseed = 11\n[section]\npoint = [0, 0, 0]\n"
      "strike = 30\n[domain]\nbox = { min = [-20, 0], max = [20, 30] }\n"
      "[[sets]]\nname = \"discs\"\ndip = 70\ndip_direction = 250\np32 = 0.6\n"
      "size = { distribution = \"lognormal\", mean = 5, sd = 2 }\nfisher_kappa = 25\n"
      "[[sets]]\nname = \"bedding\"\ndip = 25\ndip_direction = 60\nspacing = 3\n";
  const std::string geom = run_section(tmp, scene);
  const auto r = rerun_joints(tmp);
  INFO(r.err);
  const slice::JointSystem js = slice::read_joints((tmp / "joints.h5").string());
  REQUIRE(js.sets.size() == 2);
  const std::int64_t traces = js.sets[0].joint_count;
  CHECK(traces > 50);
  CHECK(js.sets[0].candidates > traces);  // the 3-D joints drawn, most of which miss the plane
  CHECK_THAT(r.err, Contains("set \"discs\" (dip 70, dip direction 250) in the section (strike "
                             "30): apparent dip "));
  CHECK_THAT(r.err, Contains(std::to_string(traces) + " traces of " +
                             std::to_string(js.sets[0].candidates) + " joints drawn in 3-D, P21 "));
  CHECK_THAT(r.err, Contains("(p32 x sin theta of the mean plane: "));
  const slice::BlockSystem bs = slice::read_blocks((tmp / "blocks.h5").string());
  CHECK(bs.blocks.size() > 100);
  // The blocks tile the section: their areas add up to the domain's, 40 x 30.
  const slice::BlockSystem g = slice::read_blocks(geom);
  double area = 0;
  for (const double v : g.geometry->volume) area += v;
  CHECK_THAT(area, WithinRel(1200, 1e-9));
}

TEST_CASE("count and p10 3-D sets in a section: count traces, p10 drawn as its P32, cut",
          "[tools][section3d]") {
  // count: that many traces in the section; p10 (joints per unit length along the mean pole in
  // 3-D): drawn as p32 = p10 / E|cos| (docs/2d.md), which slice-joints prints and /sets keeps.
  test::TempDir tmp;
  const std::string scene =
      "[scene]\nname = \"cp\"\ndimension = 2\nseed = 5\n[section]\npoint = [0, 0, 0]\n"
      "strike = 30\n[domain]\nbox = { min = [-20, 0], max = [20, 30] }\n"
      "[[sets]]\nname = \"by-p10\"\ndip = 70\ndip_direction = 250\np10 = 0.5\n"
      "size = { distribution = \"lognormal\", mean = 5, sd = 2 }\nfisher_kappa = 25\n"
      "[[sets]]\nname = \"by-count\"\ndip = 25\ndip_direction = 60\ncount = 40\n"
      "size = { distribution = \"fixed\", value = 6 }\nshape = \"rectangle\"\naspect = 2\n";
  const std::string geom = run_section(tmp, scene);
  const auto r = rerun_joints(tmp);
  INFO(r.err);
  const slice::JointSystem js = slice::read_joints((tmp / "joints.h5").string());
  REQUIRE(js.sets.size() == 2);
  // p10 0.5 with kappa 25: E|cos| = 1 - tanh(12.5) / 25 = 0.96, p32 = 0.5 / 0.96.
  const double p32 = 0.5 / (1 - std::tanh(12.5) / 25);
  CHECK(js.sets[0].intensity == slice::SetIntensity::p10);
  CHECK_THAT(js.sets[0].p32, WithinRel(p32, 1e-12));
  CHECK(js.sets[0].joint_count > 20);
  char printed[32];
  std::snprintf(printed, sizeof printed, "%.6g", p32);  // as slice-joints prints it
  CHECK_THAT(r.err, Contains(std::string("(p32 = p10 / E|cos| = ") + printed +
                             "; p32 x sin theta of the mean plane: "));
  CHECK(js.sets[1].intensity == slice::SetIntensity::count);
  CHECK(js.sets[1].joint_count == 40);
  CHECK_THAT(r.err, Contains("set \"by-count\" (dip 25, dip direction 60) in the section (strike "
                             "30): apparent dip "));
  CHECK_THAT(r.err, Contains(", 40 traces of "));
  // The blocks tile the section: their areas add up to the domain's, 40 x 30.
  const slice::BlockSystem g = slice::read_blocks(geom);
  CHECK(g.blocks.size() > 40);
  double area = 0;
  for (const double v : g.geometry->volume) area += v;
  CHECK_THAT(area, WithinRel(1200, 1e-9));
}

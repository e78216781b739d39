// slice-stability against real DEM runs in Debian's YADE (issue 41 item 7): scenes with blocks
// that fail and blocks that hold go through the real tools twice, into slice-stability and,
// exported with the default contact law (each contact its joint's friction), into YADE for 1 s
// of model time under gravity (tests/data/stability-dem/yade_timeline.py samples how far every
// body has moved every 0.05 s). The DEM's boundary is the analysis's: domain faces that are not
// free surfaces are the scene's fixed_faces (their blocks are fixed in YADE and get mode 0), the
// free ones are passed as --free-faces, and a removal zone makes the chamber's walls free.
//
// - A slope (tests/data/stability-dem/slope.toml: a planar slide with successive failure, and a
//   wedge) and a flat-roofed chamber (chamber.toml: a roof block that falls, a roof that cannot
//   come down, an end-wall block that slides and one held by friction), with the scenes'
//   friction: every block slice-stability fails (modes 3/4/5, FoS < 0.9) moves more than 50 mm,
//   every block it calls stable (FoS > 1.2, or modes 1/2, and never failing) less than 10 mm;
//   0.9 <= FoS <= 1.2 is not judged. Blocks that fail in round g >= 1 (successive failure) are
//   counted per round, and each starts to move no earlier than a neighbour of an earlier round.
// - The same scenes with friction 0 on every joint (no cohesion, no tension anywhere): exactly
//   the removable blocks whose mode is 3/4/5 move.
// - A case where slice-stability and YADE disagree, kept as it is measured
//   (docs/stability-vs-dem.md has the numbers and the hand calculations): a wall block that
//   slice-stability fails stays in YADE because a roof block that does not fail rests on it
//   (the analysis takes the neighbours as rigid and unloaded; the DEM passes their weight on).
//   This test case pins both sides: should slice-stability learn about loads from its
//   neighbours, it fails and becomes an agreement.
// - Two blocks that hold one by one and slide together (the upper one pushes the lower one out:
//   FoS 0.78 for the two as one): slice-stability's group and YADE agree.
//
// YADE must be installed (pipelines/setup does it): a missing yade fails these tests, it does not
// skip them. About 4 minutes on two cores, most of it the three runs of the chamber.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "support/support.hpp"

using slice::Vec3;
using test::run_tool;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
double tand(double deg) { return std::tan(deg * kPi / 180); }

constexpr double kSeconds = 1.0;    // model time of every run
constexpr double kInterval = 0.05;  // sampling of the motion
constexpr double kMoves = 0.05;     // m: a block that fails has moved more than this in 1 s ...
constexpr double kStays = 0.01;     // ... and one that holds less than this (it settles by mm)
constexpr double kFails = 0.9;      // FoS below this: fails; above kHolds: holds; between: not
constexpr double kHolds = 1.2;      //   judged

/// A scene of tests/data/stability-dem/.
std::string scene_text(const std::string& name) {
  return test::read_bytes(test::test_data_path("stability-dem/" + name));
}

/// The scene with friction 0 on every joint (the scenes have no cohesion or tension).
std::string frictionless(const std::string& scene) {
  REQUIRE(scene.find("cohesion") == std::string::npos);
  REQUIRE(scene.find("tension") == std::string::npos);
  std::istringstream in(scene);
  std::ostringstream out;
  std::size_t replaced = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("friction_angle", 0) == 0) line = "friction_angle = 0", ++replaced;
    out << line << '\n';
  }
  REQUIRE(replaced > 0);
  return out.str();
}

/// One free block (not removed, boundary or fixed): what slice-stability says and what YADE did.
struct Row {
  std::size_t block = 0;
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
  bool removable = false;
  int mode = 0;
  double fos = kInf;
  int generation = -1;
  std::array<std::int64_t, 2> planes{-1, -1};
  double moved = 0;     // m, after kSeconds
  double speed = 0;     // m/s, at the end
  double start = kInf;  // s: the first sample at which it had moved more than kStays
};

struct Run {
  std::vector<Row> rows;
  std::map<std::size_t, std::set<std::size_t>> neighbours;  // free block -> free blocks it touches
  slice::BlockSystem bs;                                    // stab.h5
  std::string table;                                        // the rows, for messages
  double yade_seconds = 0;                                  // wall time of the YADE run
  long steps = 0;
  const Row& row(std::size_t block) const {
    for (const Row& r : rows)
      if (r.block == block) return r;
    FAIL("block " << block << " is not a free block");
    return rows.front();
  }
};

bool moves(int mode) { return mode == 3 || mode == 4 || mode == 5; }
bool judged_failing(const Row& r) { return moves(r.mode) && r.fos < kFails; }
bool judged_holding(const Row& r) {
  return r.generation < 0 && (r.fos > kHolds || r.mode == 1 || r.mode == 2);
}

std::string table_of(const std::vector<Row>& rows) {
  std::ostringstream s;  // narrow enough for Catch's 80 columns
  s << "block  volume  centroid            mode    FoS gen  moved mm  m/s   start s\n";
  for (const Row& r : rows)
    s << std::setw(5) << r.block << std::fixed << std::setprecision(1) << std::setw(8) << r.volume
      << "  (" << std::setw(4) << r.centroid.x() << ", " << std::setw(4) << r.centroid.y() << ", "
      << std::setw(4) << r.centroid.z() << ")  " << r.mode << ' ' << std::setprecision(3)
      << std::setw(6) << r.fos << ' ' << std::setw(3) << r.generation << ' ' << std::setprecision(1)
      << std::setw(9) << 1000 * r.moved << ' ' << std::setprecision(3) << std::setw(6) << r.speed
      << ' ' << std::setprecision(2) << std::setw(5) << r.start << '\n';
  return s.str();
}

/// The scene through slice-joints, slice-cut --prune, slice-vertices, slice-stability (with
/// --free-faces `free_faces` unless empty) and slice-export --format yade, then kSeconds in YADE.
Run run_scene(const std::string& scene, const std::string& free_faces) {
  test::TempDir tmp;
  const std::string toml = (tmp / "scene.toml").string(), joints = (tmp / "joints.h5").string(),
                    blocks = (tmp / "blocks.h5").string(), geom = (tmp / "geom.h5").string(),
                    stab = (tmp / "stab.h5").string(), model = (tmp / "model.py").string();
  test::write_text(toml, scene);
  std::vector<std::string> stability = {geom, "-o", stab};
  if (!free_faces.empty()) stability.insert(stability.end(), {"--free-faces", free_faces});
  for (const auto& [tool, args] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"slice-joints", {toml, "-o", joints}},
           {"slice-cut", {joints, "--prune", "-o", blocks}},
           {"slice-vertices", {blocks, "-o", geom}},
           {"slice-stability", stability},
           {"slice-export", {geom, "--format", "yade", "-o", model}}}) {
    const auto r = run_tool(tool, args);
    INFO(tool << ": " << r.err);
    REQUIRE(r.exit_code == 0);
  }

  const auto report = tmp / "motion.json", log = tmp / "yade.log";
  std::ostringstream yade_args;
  yade_args << test::shell_quote(model) << ' ' << test::shell_quote(report) << ' ' << kSeconds
            << ' ' << kInterval;
  const int code = test::run_yade(test::test_data_path("stability-dem/yade_timeline.py").string(),
                                  yade_args.str(), log);
  INFO("yade log (tail): " << test::tail_of(log));
  REQUIRE(code == 0);
  REQUIRE(test::fs::exists(report));
  const auto j = nlohmann::json::parse(test::read_bytes(report));
  INFO(j.value("error", std::string()));
  REQUIRE_FALSE(j.contains("error"));
  REQUIRE(j["time"].get<double>() > 0.99 * kSeconds);

  Run run;
  run.bs = slice::read_blocks(stab);
  REQUIRE(run.bs.geometry);
  REQUIRE(run.bs.stability);
  run.yade_seconds = j["wall_seconds"].get<double>();
  run.steps = j["steps"].get<long>();
  const auto& st = run.bs.stability->result;
  const auto& g = *run.bs.geometry;
  const auto times = j["times"].get<std::vector<double>>();
  for (const auto& [block, body] : j["body_of_block"].items()) {
    Row r;
    r.block = std::stoul(block);
    const auto& b = run.bs.blocks.at(r.block);
    if (b.flags & (slice::kRemoved | slice::kBoundary | slice::kFixed)) continue;
    const std::string id = std::to_string(body.get<long>());
    const auto& d = j["moved"][id];
    for (const auto& x : d) REQUIRE_FALSE(x.is_null());  // no NaN
    r.moved = Vec3(d[0].get<double>(), d[1].get<double>(), d[2].get<double>()).norm();
    REQUIRE_FALSE(j["speed"][id].is_null());
    r.speed = j["speed"][id].get<double>();
    const auto& track = j["track"][id];
    REQUIRE(track.size() == times.size());
    for (std::size_t k = 0; k < times.size() && r.start == kInf; ++k) {
      REQUIRE_FALSE(track[k].is_null());
      if (track[k].get<double>() > kStays) r.start = times[k];
    }
    r.volume = g.volume[r.block];
    r.centroid = g.centroid[r.block];
    r.removable = st.removable[r.block] != 0;
    r.mode = st.mode[r.block];
    r.fos = st.fos[r.block];
    r.generation = st.generation[r.block];
    r.planes = st.planes[r.block];
    run.rows.push_back(r);
  }
  std::sort(run.rows.begin(), run.rows.end(),
            [](const Row& a, const Row& b) { return a.block < b.block; });
  const auto& c = run.bs.stability->contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto [a, b] = c.pairs[k];
    if (b < 0) continue;
    run.neighbours[std::size_t(a)].insert(std::size_t(b));
    run.neighbours[std::size_t(b)].insert(std::size_t(a));
  }
  run.table = table_of(run.rows);
  return run;
}

/// Successive failure as YADE shows it: every block failing in round g >= 1 starts to move no
/// earlier than a neighbour that failed in an earlier round (the one whose going freed it).
/// Returns, per round, the blocks failing in it.
std::map<int, std::vector<std::size_t>> check_rounds(const Run& run) {
  std::map<int, std::vector<std::size_t>> rounds;
  std::map<std::size_t, const Row*> by_block;
  for (const Row& r : run.rows) by_block[r.block] = &r;
  for (const Row& r : run.rows) {
    if (r.generation < 0) continue;
    rounds[r.generation].push_back(r.block);
    if (r.generation == 0 || r.start == kInf) continue;
    double first = kInf;  // the earliest start among the neighbours that failed before it
    auto it = run.neighbours.find(r.block);
    REQUIRE(it != run.neighbours.end());
    for (const std::size_t n : it->second) {
      const auto o = by_block.find(n);
      if (o != by_block.end() && o->second->generation >= 0 && o->second->generation < r.generation)
        first = std::min(first, o->second->start);
    }
    INFO("block " << r.block << " (round " << r.generation << ") starts at " << r.start
                  << " s; its first neighbour of an earlier round at " << first << " s");
    CHECK(first < kInf);
    CHECK(r.start >= first);
  }
  return rounds;
}

/// Claim (a), with the scenes' friction: the blocks slice-stability fails move, those it calls
/// stable stay. Returns the numbers of blocks failing, holding and not judged.
std::array<std::size_t, 3> check_friction(const Run& run) {
  INFO(run.table);
  std::array<std::size_t, 3> n{0, 0, 0};
  for (const Row& r : run.rows) {
    INFO("block " << r.block << ": mode " << r.mode << ", FoS " << r.fos << ", round "
                  << r.generation << "; moved " << 1000 * r.moved << " mm");
    if (judged_failing(r)) {
      ++n[0];
      CHECK(r.generation >= 0);
      CHECK(r.moved > kMoves);
    } else if (judged_holding(r)) {
      ++n[1];
      CHECK(r.moved < kStays);
    } else {
      ++n[2];
    }
  }
  return n;
}

/// Claim (b), friction 0 on every joint: exactly the removable blocks of modes 3/4/5 move (each
/// then fails, at FoS 0), the others stay. Returns the numbers of blocks moving and staying.
std::array<std::size_t, 2> check_frictionless(const Run& run) {
  INFO(run.table);
  std::array<std::size_t, 2> n{0, 0};
  for (const Row& r : run.rows) {
    INFO("block " << r.block << ": removable " << r.removable << ", mode " << r.mode << ", round "
                  << r.generation << "; moved " << 1000 * r.moved << " mm");
    if (r.removable && moves(r.mode)) {
      ++n[0];
      CHECK(r.fos == 0);
      CHECK(r.generation >= 0);
      CHECK(r.moved > kMoves);
    } else {
      ++n[1];
      CHECK(r.generation < 0);
      CHECK(r.moved < kStays);
    }
  }
  return n;
}

std::size_t count_mode(const Run& run, int mode) {
  return std::size_t(std::count_if(run.rows.begin(), run.rows.end(),
                                   [&](const Row& r) { return r.mode == mode; }));
}

}  // namespace

TEST_CASE(
    "in a slope run in YADE, the blocks slice-stability fails slide and the ones it calls "
    "stable stay",
    "[tools][stability][physics]") {
  const bool with_friction = GENERATE(true, false);
  CAPTURE(with_friction);
  const std::string scene = scene_text("slope.toml");
  const Run run = run_scene(with_friction ? scene : frictionless(scene), "+x,+z");
  INFO(run.table);
  CAPTURE(run.yade_seconds, run.steps);
  // The slope's free blocks: 5 in the planar slab, 6 in the wedge's.
  REQUIRE(run.rows.size() == 11);
  const auto rounds = check_rounds(run);
  if (with_friction) {
    const auto n = check_friction(run);
    CHECK(n[0] == 5);  // three on the 35-degree plane, the two wedges
    CHECK(n[1] == 6);  // on the 20-degree plane (1.28), beside the wedge (1.73), mode 2 (3)
    CHECK(n[2] == 0);
    CHECK(count_mode(run, 5) >= 4);  // the wedges and the rock beside them: two planes
    // Successive failure: the front block on the 35-degree plane and the front wedge (round 0),
    // the blocks behind them (rounds 1 and 2).
    CHECK(rounds.at(0).size() == 2);
    CHECK(rounds.at(1).size() == 2);
    CHECK(rounds.at(2).size() == 1);
  } else {
    const auto n = check_frictionless(run);
    CHECK(n[0] == 11);  // every free block slides, the last in round 2
    CHECK(rounds.size() == 3);
  }
}

TEST_CASE(
    "in a flat-roofed chamber run in YADE, the blocks slice-stability fails fall or slide "
    "and the ones it calls stable stay",
    "[tools][stability][physics]") {
  const bool with_friction = GENERATE(true, false);
  CAPTURE(with_friction);
  const std::string scene = scene_text("chamber.toml");
  const Run run = run_scene(with_friction ? scene : frictionless(scene), "");
  INFO(run.table);
  CAPTURE(run.yade_seconds, run.steps);
  REQUIRE(run.rows.size() == 21);
  CHECK(count_mode(run, 0) == 4);                        // under the walls: no free face
  CHECK(count_mode(run, 1) == (with_friction ? 3 : 2));  // the south half's roof, and under the
                                                         // end wall's east block while it holds
  CHECK(count_mode(run, 2) >= 8);  // floor, walls, the roof's blocks beside the one that falls
  CHECK(count_mode(run, 3) == 2);  // the north half's roof block and its top
  const auto rounds = check_rounds(run);
  if (with_friction) {
    const auto n = check_friction(run);
    CHECK(n[0] == 3);   // the roof block, its top (round 1), the end wall's west block (0.78)
    CHECK(n[1] == 18);  // its east block (FoS 1.34) among them
    CHECK(n[2] == 0);
    CHECK(rounds.at(0).size() == 2);
    CHECK(rounds.at(1).size() == 1);
  } else {
    const auto n = check_frictionless(run);
    CHECK(n[0] == 4);  // the end wall's east block slides too
    CHECK(n[1] == 17);
  }
}

TEST_CASE(
    "where slice-stability and YADE disagree: a wall block that a roof block rests on holds "
    "in YADE although slice-stability fails it",
    "[tools][stability][physics]") {
  // The chamber with a block in each side wall that slides into it on its own (planes dipping
  // 50 degrees east, friction 40, FoS 0.70, and 45 degrees west, friction 38, FoS 0.78); blocks
  // of the roof that do not fail rest on their tops (the south half's west block, which cannot
  // move; the north half's east one, beside the block that falls). slice-stability takes the
  // roof block as a rigid neighbour that the wall block leaves; in YADE its weight presses on the
  // wall block, and friction on that top face holds it: 0.34 and 0.21 of the wall block's
  // weight would do, YADE's contact forces are 3.9 and 2.2 of it (docs/stability-vs-dem.md).
  std::string scene = scene_text("chamber.toml");
  const std::string walls = R"(
[[joints]]                      # west wall, south half: 50 degrees, z = 6.81 at the chamber
dip = 50
dip_direction = 90
point = [7, 4.5, 8]
polygon_uv = [[-0.4, -0.4], [0.4, -0.4], [0.4, 0.4], [-0.4, 0.4]]
friction_angle = 40
stage = 2

[[joints]]                      # east wall, north half: 45 degrees, z = 7 at the chamber
dip = 45
dip_direction = 270
point = [17, 7.5, 8]
polygon_uv = [[-0.4, -0.4], [0.4, -0.4], [0.4, 0.4], [-0.4, 0.4]]
friction_angle = 38
stage = 2
)";
  scene.insert(scene.find("[[zones]]"), walls.substr(1) + "\n");
  const Run run = run_scene(scene, "");
  INFO(run.table);
  CAPTURE(run.yade_seconds, run.steps);
  const auto joints = std::int64_t(run.bs.joints.joints.size());
  std::vector<const Row*> loaded;  // the wall blocks on the two new planes
  for (const Row& r : run.rows)
    if (r.generation >= 0 && r.mode == 4 && r.planes[0] >= joints - 2) loaded.push_back(&r);
  REQUIRE(loaded.size() == 2);
  const auto& c = run.bs.stability->contacts;
  for (const Row* r : loaded) {
    INFO("wall block " << r->block << ": FoS " << r->fos << ", moved " << 1000 * r->moved
                       << " mm, speed " << r->speed << " m/s at 1 s");
    CHECK(r->fos < kFails);  // slice-stability: it slides at once
    CHECK(r->generation == 0);
    CHECK(r->moved < kStays);  // YADE: it holds, as a block that holds (2 mm)
    CHECK(r->speed < 1e-3);
    // under a block of the roof that does not fail
    std::size_t on_top = 0;
    for (std::size_t k = 0; k < c.size(); ++k) {
      const auto [a, b] = c.pairs[k];
      if (b < 0 || (std::size_t(a) != r->block && std::size_t(b) != r->block)) continue;
      const std::size_t other = std::size_t(a) == r->block ? std::size_t(b) : std::size_t(a);
      const Vec3 up = std::size_t(a) == r->block ? c.normal[k] : Vec3(-c.normal[k]);
      const auto& o = run.bs.blocks[other];
      if (up.z() > 0.99 && !(o.flags & (slice::kRemoved | slice::kBoundary | slice::kFixed)) &&
          run.row(other).generation < 0)
        ++on_top;
    }
    CHECK(on_top >= 1);
  }
  // The rest of the chamber as without them: the roof block and its top fall, the end wall's west
  // block slides, the others stay (the roof blocks on the wall blocks among them).
  for (const Row& r : run.rows) {
    if (std::find(loaded.begin(), loaded.end(), &r) != loaded.end()) continue;
    INFO("block " << r.block << ": mode " << r.mode << ", FoS " << r.fos << ", moved "
                  << 1000 * r.moved << " mm");
    if (judged_failing(r)) CHECK(r.moved > kMoves);
    if (judged_holding(r)) CHECK(r.moved < kStays);
  }
}

TEST_CASE("two blocks that hold alone fail together, in slice-stability and in YADE",
          "[tools][stability][physics]") {
  // tests/data/stability-dem/two-block.toml: on one plane dipping 30 degrees, an upper block on
  // friction 15 leans on a lower block on friction 40. Alone, the upper block can only move up
  // past the lower one (mode 2), the lower one has FoS tan 40 / tan 30 = 1.45. As one body on the
  // plane (they move the same way, so the joint between them does not slip) they have FoS
  // (A1 tan 15 + A2 tan 40) / ((A1 + A2) tan 30) = 0.753 (N spread by area over their contacts on
  // the plane, A1 = 6 x 7 / sin 30, A2 = 6 x 5 / cos 30), or 0.778 with W1, W2 in place of A1, A2
  // (each keeping its own weight's normal force): slice-stability's group, and YADE slides them.
  const Run run = run_scene(scene_text("two-block.toml"), "+x,+z");
  INFO(run.table);
  CAPTURE(run.yade_seconds, run.steps);
  REQUIRE(run.rows.size() == 2);
  const Row& upper =
      run.rows[0].centroid.x() < run.rows[1].centroid.x() ? run.rows[0] : run.rows[1];
  const Row& lower = &upper == &run.rows[0] ? run.rows[1] : run.rows[0];
  const double a1 = 6 * 7 / std::sin(30 * kPi / 180), a2 = 6 * 5 / std::cos(30 * kPi / 180);
  const double together = (a1 * tand(15) + a2 * tand(40)) / ((a1 + a2) * tand(30));
  const double by_weight = (upper.volume * tand(15) + lower.volume * tand(40)) /
                           ((upper.volume + lower.volume) * tand(30));
  CAPTURE(together, by_weight);
  CHECK(together < kFails);  // the hand calculations: the two fail as one
  CHECK(by_weight < kFails);
  for (const Row* r : {&upper, &lower}) {
    CHECK(r->mode == 4);
    CHECK(r->generation == 0);
    CHECK(std::abs(r->fos - together) < 1e-9 * together);
  }
  CHECK(upper.moved > kMoves);  // YADE: both slide
  CHECK(lower.moved > kMoves);
}

// slice-export --format 3dec: the grid file parsed back (TOL, G, F, B, JS lines) against
// /geometry, and the command file (joined clusters in their own group slot, boundary group,
// contact properties per joint set, rock bridges, the time step) against the blocks and joints.
#include "slice/export_3dec.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "slice/h5io.hpp"
#include "slice/vertices.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::run_tool;

namespace {

struct Grid {
  double tol = -1;
  std::map<long, Vec3> points;
  std::map<long, std::vector<long>> faces;
  std::map<long, std::vector<long>> blocks;                     // block id -> face ids
  std::map<long, std::vector<std::pair<long, long>>> contacts;  // JS id -> block pairs
};

Grid parse_grid(const std::string& text) {
  Grid g;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '*') continue;
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    INFO(line);
    if (tag == "TOL") {
      REQUIRE(g.tol < 0);  // one TOL line, before the gridpoints
      REQUIRE(g.points.empty());
      ls >> g.tol;
      REQUIRE(!ls.fail());
      continue;
    }
    long id = 0;
    ls >> id;
    REQUIRE(id > 0);
    if (tag == "G") {
      Vec3 x;
      ls >> x.x() >> x.y() >> x.z();
      REQUIRE(!ls.fail());
      REQUIRE(g.points.emplace(id, x).second);
    } else if (tag == "F") {
      std::vector<long> pts;
      for (long p; ls >> p;) pts.push_back(p);
      REQUIRE(pts.size() >= 3);
      REQUIRE(g.faces.emplace(id, pts).second);
    } else if (tag == "B") {
      long zone = 0;
      std::string f;
      ls >> zone >> f;
      REQUIRE(f == "F");
      std::vector<long> fs;
      for (long x; ls >> x;) fs.push_back(x);
      REQUIRE(g.blocks.emplace(id, fs).second);
    } else if (tag == "JS") {
      for (std::string pair; ls >> pair;) {
        const auto dash = pair.find('-');
        REQUIRE(dash != std::string::npos);
        g.contacts[id].emplace_back(std::stol(pair.substr(0, dash)),
                                    std::stol(pair.substr(dash + 1)));
      }
    } else {
      FAIL("unknown line: " << line);
    }
  }
  REQUIRE(g.tol > 0);
  return g;
}

/// The volume inside faces whose points go counter-clockwise seen from outside (negative if
/// they go the other way): divergence theorem over a fan of each face.
double volume(const Grid& g, const std::vector<long>& faces, std::vector<Vec3>* normals) {
  double v = 0;
  for (const long f : faces) {
    const auto& pts = g.faces.at(f);
    std::vector<Vec3> poly;
    for (const long p : pts) poly.push_back(g.points.at(p));
    for (std::size_t k = 1; k + 1 < poly.size(); ++k)
      v += poly[0].dot(poly[k].cross(poly[k + 1])) / 6;
    if (normals) normals->push_back(slice::newell_normal(poly).normalized());
  }
  return v;
}

/// The TOL rule of export_3dec.hpp, from the grid's own points and faces.
double expected_tol(const Grid& g, double floor) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (const auto& [id, x] : g.points) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  double shortest = INFINITY;
  for (const auto& [id, pts] : g.faces)
    for (std::size_t k = 0; k < pts.size(); ++k)
      shortest =
          std::min(shortest, (g.points.at(pts[(k + 1) % pts.size()]) - g.points.at(pts[k])).norm());
  return std::max(floor, std::min(0.0012 * (hi - lo).sum() / 3, 0.2 * shortest));
}

/// The joint-set ID the export gives each joint: set s -> s + 1, the k-th joint of set -1 ->
/// sets + 1 + k.
std::vector<long> js_ids(const slice::JointSystem& js) {
  std::vector<long> ids;
  long k = 0;
  for (const auto& j : js.joints)
    ids.push_back(j.set >= 0 ? j.set + 1 : long(js.sets.size()) + 1 + k++);
  return ids;
}

/// The command file's `block contact property ...` lines: range joint-set ID (0: no range) ->
/// keyword -> value.
std::map<long, std::map<std::string, double>> contact_properties(const std::string& dat) {
  std::map<long, std::map<std::string, double>> out;
  std::istringstream in(dat);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("block contact property ", 0) != 0) continue;
    std::istringstream ls(line.substr(23));
    std::map<std::string, double> props;
    long id = 0;
    for (std::string key; ls >> key;) {
      if (key == "range") {
        std::string what;
        ls >> what >> id;
        REQUIRE(what == "joint-set");
        break;
      }
      ls >> props[key];
    }
    INFO(line);
    REQUIRE(out.emplace(id, props).second);
  }
  return out;
}

/// A number that follows `label` in `text`.
double number_after(const std::string& text, const std::string& label) {
  const auto at = text.find(label);
  INFO("looking for \"" << label << "\" in " << text);
  REQUIRE(at != std::string::npos);
  return std::stod(text.substr(at + label.size()));
}

void require_run(const std::string& tool, const std::vector<std::string>& args) {
  const auto r = run_tool(tool, args);
  INFO(tool << ": " << r.err);
  REQUIRE(r.exit_code == 0);
}

/// slice-joints, slice-cut --prune and slice-vertices on the scene text; returns geom.h5.
std::string pipeline_of(const test::TempDir& tmp, const std::string& scene) {
  test::write_text(tmp / "scene.toml", scene);
  require_run("slice-joints", {(tmp / "scene.toml").string(), "-o", (tmp / "j.h5").string()});
  require_run("slice-cut",
              {(tmp / "j.h5").string(), "-o", (tmp / "b.h5").string(), "--prune", "-q"});
  require_run("slice-vertices", {(tmp / "b.h5").string(), "-o", (tmp / "geom.h5").string()});
  return (tmp / "geom.h5").string();
}

}  // namespace

TEST_CASE("the 3DEC grid parses back: blocks, faces, volumes and contacts match /geometry",
          "[tools][export][3dec]") {
  const std::string scene = GENERATE(as<std::string>{}, "cube-3sets.toml", "rock-slope.toml");
  CAPTURE(scene);
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, scene, test::Stage::geometry);
  const std::string grid_file = (tmp / "model.3dgrid").string();
  const auto r = run_tool("slice-export", {geom, "--format", "3dec", "-o", grid_file});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto bs = slice::read_blocks(geom);
  const auto& geo = *bs.geometry;
  const Grid g = parse_grid(test::read_bytes(grid_file));
  CHECK_THAT(g.tol, WithinRel(expected_tol(g, bs.joints.options.tolerance * bs.joints.length_scale),
                              1e-12));
  CHECK_THAT(r.err, Contains("TOL "));

  std::size_t kept = 0, row = 0;
  std::vector<std::size_t> first_row;
  for (const auto& b : bs.blocks) {
    first_row.push_back(row);
    row += b.faces.size();
    kept += (b.flags & slice::kRemoved) ? 0 : 1;
  }
  REQUIRE(g.blocks.size() == kept);
  std::set<long> seen_faces;
  for (const auto& [id, faces] : g.blocks) {
    const auto b = std::size_t(id - 1);
    REQUIRE(b < bs.blocks.size());
    const auto& blk = bs.blocks[b];
    CHECK_FALSE(blk.flags & slice::kRemoved);
    REQUIRE(faces.size() == blk.faces.size());
    for (const long f : faces) CHECK(seen_faces.insert(f).second);  // faces are not shared
    std::vector<Vec3> normals;
    const double v = volume(g, faces, &normals);
    // Clockwise seen from outside (Itasca's block create): the divergence theorem gives minus
    // the volume, and the right-hand normals point in.
    CHECK(std::abs(-v - geo.volume[b]) <= 1e-9 * geo.volume[b]);
    for (std::size_t f = 0; f < faces.size(); ++f)
      CHECK(normals[f].dot(blk.faces[f].normal) < -1 + 1e-9);
  }
  CHECK(seen_faces.size() == g.faces.size());

  // Contacts: both blocks kept, each has a face on a joint of that ID, facing the other's.
  const std::vector<long> ids = js_ids(bs.joints);
  std::size_t pairs = 0;
  for (const auto& [js, list] : g.contacts) {
    for (const auto& [a, b] : list) {
      ++pairs;
      REQUIRE(a < b);
      const auto& ba = bs.blocks[std::size_t(a - 1)];
      const auto& bb = bs.blocks[std::size_t(b - 1)];
      bool facing = false;
      for (const auto& fa : ba.faces)
        for (const auto& fb : bb.faces)
          if (fa.joint >= 0 && fa.joint == fb.joint && fa.normal.dot(fb.normal) < -1 + 1e-9)
            facing = facing || ids[std::size_t(fa.joint)] == js;
      CHECK(facing);
    }
  }
  const std::string dat = test::read_bytes(tmp / "model.dat");
  if (scene == "cube-3sets.toml") {  // 10 x 10 x 10 unit cubes: 900 contacts per set
    REQUIRE(g.contacts.size() == 3);
    for (const auto& [js, list] : g.contacts) CHECK(list.size() == 900);
    // Every contact is a unit square, every body a unit cube: dt = 0.1 x 2 sqrt(2650 / 1e10).
    CHECK_THAT(r.err, Contains(" (volume 1, inradius 0.5); smallest moving body: block "));
    CHECK_THAT(r.err, Contains("3DEC critical time step 0.000103 s"));
    CHECK_THAT(number_after(dat, "sqrt(m_min / k_max): "),
               WithinRel(0.2 * std::sqrt(2650 / 1e10), 1e-12));
    CHECK_THAT(number_after(dat, " s (m_min "), WithinRel(2650, 1e-12));
    CHECK_THAT(number_after(dat, " kg, k_max "), WithinRel(1e10, 1e-12));
  } else {
    CHECK(pairs > 0);
  }

  // The command file: imports the grid; group "boundary" (Default slot) and the clusters, each
  // "cluster-c" in slot "cluster" and joined.
  CHECK_THAT(dat, Contains("\nblock import filename \"model.3dgrid\"\n"));
  std::set<long> boundary;
  std::map<long, std::set<long>> clusters;
  std::istringstream in(dat);
  for (std::string line; std::getline(in, line);) {
    long c = 0, lo = 0, hi = 0;
    if (int n = std::sscanf(line.c_str(),
                            "block group \"cluster-%ld\" slot \"cluster\" range id %ld %ld", &c,
                            &lo, &hi);
        n >= 2) {
      for (long id = lo; id <= (n == 3 ? hi : lo); ++id) clusters[c].insert(id);
    } else if (int m =
                   std::sscanf(line.c_str(), "block group \"boundary\" range id %ld %ld", &lo, &hi);
               m >= 1) {
      for (long id = lo; id <= (m == 2 ? hi : lo); ++id) boundary.insert(id);
    } else {
      CHECK(line.rfind("block group", 0) != 0);  // no other groups
    }
  }
  std::map<long, std::set<long>> want_clusters;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const auto& blk = bs.blocks[b];
    if (blk.flags & slice::kRemoved) continue;
    CHECK(boundary.count(long(b) + 1) ==
          ((blk.flags & (slice::kBoundary | slice::kFixed)) ? 1u : 0u));
    if (blk.cluster >= 0) want_clusters[blk.cluster].insert(long(b) + 1);
  }
  std::erase_if(want_clusters, [](const auto& c) { return c.second.size() < 2; });
  CHECK(clusters == want_clusters);
  for (const auto& [c, members] : clusters)
    CHECK_THAT(dat, Contains("\nblock join range group \"cluster-" + std::to_string(c) +
                             "\" slot \"cluster\"\n"));
  if (!boundary.empty()) CHECK_THAT(dat, Contains("\nblock fix range group \"boundary\"\n"));
  if (scene == "rock-slope.toml") CHECK(!clusters.empty());

  // Contact properties: all contacts, then every JS ID of the grid with its joints' values.
  const auto props = contact_properties(dat);
  REQUIRE(props.size() == g.contacts.size() + 1);
  CHECK(props.at(0).at("friction") == 30);
  for (const auto& [js, p] : props) {
    CHECK(p.at("stiffness-normal") == 1e10);
    CHECK(p.at("stiffness-shear") == 1e9);
    if (js == 0) continue;
    REQUIRE(g.contacts.count(js));
    const auto at = std::find(ids.begin(), ids.end(), js);
    REQUIRE(at != ids.end());
    const auto& joint = bs.joints.joints[std::size_t(at - ids.begin())];
    CHECK(p.at("friction") == joint.friction_angle_deg);
    CHECK(p.at("cohesion") == joint.cohesion);
    CHECK(p.at("tension") == joint.tension);
  }
  CHECK_THAT(dat,
             Contains("\nblock contact generate-subcontacts\nblock contact jmodel assign mohr\n"));
  CHECK_THAT(dat, Contains("\nblock property density 2650\n"));
}

TEST_CASE(
    "slice-export 3dec: joint sets with their own friction, cohesion and tension, rock "
    "bridges with [rock]'s, and the time step",
    "[tools][export][3dec]") {
  test::TempDir tmp;
  // Persistent set A, finite set B (each joint extended through its blocks: rock bridges), and a
  // [[joints]] entry of its own; B's friction is the lowest, so A's and B's IDs differ in value.
  const std::string geom = pipeline_of(tmp, R"([scene]
name = "bridges"
seed = 7
[domain]
box = { min = [0, 0, 0], max = [10, 10, 10] }
[rock]
friction_angle = 50
cohesion = 3e6
tension = 1.5e6
[[joints]]
dip = 90
dip_direction = 0
point = [5, 5.5, 5]
friction_angle = 40
cohesion = 2e4
tension = 5e3
[[sets]]
name = "A"
dip = 0
dip_direction = 0
spacing = 2.5
friction_angle = 35
cohesion = 1e4
tension = 1e3
[[sets]]
name = "B"
dip = 90
dip_direction = 90
count = 6
size = { distribution = "fixed", value = 4 }
friction_angle = 25
)");
  const std::string grid = (tmp / "m.3dgrid").string();
  const auto r = run_tool("slice-export",
                          {geom, "--format", "3dec", "-o", grid, "--3dec-jkn", "2e10", "--3dec-jks",
                           "3e9", "--3dec-density", "2000", "--3dec-friction", "33"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto bs = slice::read_blocks(geom);
  REQUIRE(bs.joints.rock.given);
  const Grid g = parse_grid(test::read_bytes(grid));
  const std::string dat = test::read_bytes(tmp / "m.dat");
  const auto props = contact_properties(dat);
  const std::vector<long> ids = js_ids(bs.joints);
  const long count = long(bs.joints.sets.size()) +
                     long(std::count_if(bs.joints.joints.begin(), bs.joints.joints.end(),
                                        [](const auto& j) { return j.set < 0; }));
  CHECK(count == 3);  // A, B and the [[joints]] entry: IDs 1, 2, 3; bridges 4, 5, 6

  CHECK(props.at(0).at("friction") == 33);
  std::size_t bridges = 0;
  for (const auto& [js, p] : props) {
    CAPTURE(js);
    CHECK(p.at("stiffness-normal") == 2e10);
    CHECK(p.at("stiffness-shear") == 3e9);
    if (js == 0) continue;
    REQUIRE(g.contacts.count(js));
    const long base = js > count ? js - count : js;
    const auto& joint =
        bs.joints.joints[std::size_t(std::find(ids.begin(), ids.end(), base) - ids.begin())];
    if (js > count) {
      bridges += g.contacts.at(js).size();
      CHECK(p.at("friction") == 50);
      CHECK(p.at("cohesion") == 3e6);
      CHECK(p.at("tension") == 1.5e6);
    } else {
      CHECK(p.at("friction") == joint.friction_angle_deg);
      CHECK(p.at("cohesion") == joint.cohesion);
      CHECK(p.at("tension") == joint.tension);
    }
  }
  CHECK(props.at(1).at("tension") == 1e3);  // set A
  CHECK(props.at(2).at("friction") == 25);  // set B
  CHECK(bridges > 0);
  CHECK_THAT(r.err, Contains(" rock bridges)"));
  CHECK_THAT(r.err, Contains(std::to_string(bridges) + " rock bridges"));

  // A bridge contact's faces: the smaller part of either on its joint's polygon is under half
  // the smaller face (which bounds the contact's area).
  std::vector<std::size_t> first_row;
  std::size_t row = 0;
  for (const auto& b : bs.blocks) first_row.push_back(row), row += b.faces.size();
  const auto& geo = *bs.geometry;
  for (const auto& [js, list] : g.contacts) {
    if (js <= count) continue;
    for (const auto& [a, b] : list) {
      double open = INFINITY, area = INFINITY;
      for (const long id : {a, b}) {
        const auto blk = std::size_t(id - 1);
        for (std::size_t f = 0; f < bs.blocks[blk].faces.size(); ++f) {
          const auto joint = bs.blocks[blk].faces[f].joint;
          if (joint < 0 || ids[std::size_t(joint)] != js - count) continue;
          const auto k = first_row[blk] + f;
          open = std::min(open, geo.face_joint_fraction[k] * geo.face_area[k]);
          area = std::min(area, geo.face_area[k]);
        }
      }
      CHECK(open < 0.5 * area);
    }
  }

  // The time step: the smallest free block by /geometry/volume (clusters: none here), and
  // dt = 0.1 x 2 sqrt(m / k) with m = 2000 V, k = 2e10 x the largest contact area.
  std::size_t smallest = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b)
    if (geo.volume[b] < geo.volume[smallest]) smallest = b;
  // The shared summary (dem.hpp) names blocks by their row in blocks.h5 (3DEC ID - 1).
  const std::string free = "smallest free block: " + std::to_string(smallest) + " (volume ";
  CHECK_THAT(r.err, Contains(free));
  CHECK_THAT(number_after(r.err, free), WithinRel(geo.volume[smallest], 5e-4));
  CHECK_THAT(number_after(r.err.substr(r.err.find(free)), ", inradius "),
             WithinRel(bs.blocks[smallest].inradius, 5e-4));
  const double m = number_after(dat, " s (m_min "), k = number_after(dat, " kg, k_max ");
  CHECK_THAT(m, WithinRel(2000 * geo.volume[smallest], 1e-12));
  CHECK(k <= 2e10 * 100 * (1 + 1e-12));  // no contact is larger than a 10 x 10 m face
  CHECK(k >= 2e10 * 2.5 * 2.5 * (1 - 1e-9));
  CHECK_THAT(number_after(dat, "sqrt(m_min / k_max): "), WithinRel(0.2 * std::sqrt(m / k), 1e-12));

  SECTION("without [rock], no contact is a rock bridge") {
    test::TempDir t2;
    std::string scene = test::read_bytes(tmp / "scene.toml");
    scene.erase(scene.find("[rock]"), scene.find("[[joints]]") - scene.find("[rock]"));
    const std::string g2 = pipeline_of(t2, scene);
    const auto r2 =
        run_tool("slice-export", {g2, "--format", "3dec", "-o", (t2 / "m.3dgrid").string()});
    REQUIRE(r2.exit_code == 0);
    for (const auto& [js, p] : contact_properties(test::read_bytes(t2 / "m.dat")))
      CHECK(js <= count);
    CHECK_THAT(r2.err, Contains("(0 rock bridges)"));
  }
}

TEST_CASE("a 3DEC scene name with newlines adds no line to the script", "[tools][export][3dec]") {
  test::TempDir tmp;
  const std::string geom = pipeline_of(tmp, R"([scene]
name = "evil\nmodel new\nG 1 0 0 0\r\nJS 1 1-2\n* x"
[domain]
box = { min = [0, 0, 0], max = [2, 2, 2] }
[[sets]]
name = "J1\nblock delete\n"
dip = 0
dip_direction = 0
spacing = 1
)");
  const std::string grid = (tmp / "m.3dgrid").string();
  const auto r = run_tool("slice-export", {geom, "--format", "3dec", "-o", grid});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string text = test::read_bytes(grid), dat = test::read_bytes(tmp / "m.dat");
  CHECK(text.find('\r') == std::string::npos);
  CHECK(dat.find('\r') == std::string::npos);
  const Grid g = parse_grid(text);  // fails on any line it does not know
  CHECK(g.points.size() == 8 * 2);  // two cubes of 8 gridpoints, one gridpoint 1
  CHECK(g.contacts.size() == 1);
  CHECK(g.contacts.at(1).size() == 1);
  std::size_t model_new = 0, commands = 0;
  std::istringstream in(dat);
  for (std::string line; std::getline(in, line);) {
    model_new += line == "model new" ? 1 : 0;
    if (!line.empty() && line[0] != ';') {
      ++commands;
      CHECK((line.rfind("block ", 0) == 0 || line.rfind("model ", 0) == 0));
    }
  }
  CHECK(model_new == 1);
  CHECK(dat.find("\nblock delete") == std::string::npos);
  CHECK_THAT(dat, Contains("evil\\nmodel new\\nG 1 0 0 0\\r\\nJS 1 1-2\\n* x"));
  CHECK_THAT(text, Contains("evil\\nmodel new"));

  SECTION("a grid name no 3DEC string can hold is refused, nothing written") {
    for (const std::string name : {"a\nb.3dgrid", "a\"b'c.3dgrid"}) {
      CAPTURE(name);
      const auto bad =
          run_tool("slice-export", {geom, "--format", "3dec", "-o", (tmp / name).string(),
                                    "--3dec-commands", (tmp / "bad.dat").string()});
      CHECK(bad.exit_code == 1);
      CHECK(std::count(bad.err.begin(), bad.err.end(), '\n') == 1);
      CHECK_FALSE(test::fs::exists(tmp / name));
      CHECK_FALSE(test::fs::exists(tmp / "bad.dat"));
    }
    // One kind of quote is fine: the other quotes it.
    const auto ok =
        run_tool("slice-export", {geom, "--format", "3dec", "-o", (tmp / "it's.3dgrid").string()});
    REQUIRE(ok.exit_code == 0);
    CHECK_THAT(test::read_bytes(tmp / "it's.dat"),
               Contains("block import filename \"it's.3dgrid\"\n"));
  }
}

TEST_CASE("slice-export 3dec: reruns give the same bytes -- bad options are refused",
          "[tools][export][3dec]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "rock-slope.toml", test::Stage::geometry);
  const std::string a = (tmp / "a.3dgrid").string(), b = (tmp / "b.3dgrid").string();
  REQUIRE(run_tool("slice-export", {geom, "--format", "3dec", "-o", a}).exit_code == 0);
  REQUIRE(run_tool("slice-export", {geom, "--format", "3dec", "-o", b, "--3dec-commands",
                                    (tmp / "import.dat").string()})
              .exit_code == 0);
  CHECK(test::read_bytes(a) == test::read_bytes(b));
  CHECK(test::fs::exists(tmp / "a.dat"));
  CHECK_THAT(test::read_bytes(tmp / "import.dat"), Contains("block import filename \"b.3dgrid\""));
  REQUIRE(run_tool("slice-export", {geom, "--format", "3dec", "-o", a}).exit_code == 0);
  std::string import = test::read_bytes(tmp / "import.dat");
  import.replace(import.find("\"b.3dgrid\""), 10, "\"a.3dgrid\"");
  CHECK(test::read_bytes(tmp / "a.dat") == import);

  SECTION("--3dec-commands with another format") {
    const auto r = run_tool("slice-export", {geom, "-o", (tmp / "x.vtu").string(),
                                             "--3dec-commands", (tmp / "x.dat").string()});
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("--3dec-commands"));
    CHECK_FALSE(test::fs::exists(tmp / "x.vtu"));
  }
  SECTION("the command file on the grid file") {
    const auto r =
        run_tool("slice-export", {geom, "--format", "3dec", "-o", (tmp / "y.dat").string()});
    CHECK(r.exit_code == 1);
    CHECK_FALSE(test::fs::exists(tmp / "y.dat"));
  }
  SECTION("blocks without /geometry") {
    const auto r =
        run_tool("slice-export", {(tmp / "blocks.h5").string(), "--format", "3dec", "-o", a});
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("slice-vertices"));
  }
  SECTION("bad stiffness, density or friction") {
    for (const auto& [option, value] :
         std::vector<std::pair<std::string, std::string>>{{"--3dec-jkn", "0"},
                                                          {"--3dec-jks", "-1"},
                                                          {"--3dec-density", "nan"},
                                                          {"--3dec-friction", "90"}}) {
      CAPTURE(option, value);
      const auto r = run_tool("slice-export", {geom, "--format", "3dec", "-o",
                                               (tmp / "z.3dgrid").string(), option, value});
      CHECK(r.exit_code == 1);
      CHECK_THAT(r.err, Contains(option));
      CHECK_FALSE(test::fs::exists(tmp / "z.3dgrid"));
      CHECK_FALSE(test::fs::exists(tmp / "z.dat"));
    }
  }
}

TEST_CASE("the Snakemake workflow exports 3dec, with its options",
          "[tools][workflow][snakemake][3dec]") {
  test::TempDir tmp;
  const test::fs::path root = test::fs::path(SLICE_TEST_DATA_DIR).parent_path().parent_path();
  test::write_text(tmp / "config.yaml",
                   "scenes:\n  cube: " + test::data_path("cube-3sets.toml").string() +
                       "\nseeds: [1]\nout: " + (tmp / "out").string() + "\ntools: " +
                       SLICE_TOOLS_DIR + "\nexports: [3dec]\n3dec_options: \"--3dec-jkn 5e9\"\n" +
                       "plots: false\nsummary: false\n");
  const int code = test::run_shell("cd " + test::shell_quote(tmp.path()) + " && snakemake -s " +
                                   test::shell_quote(root / "pipelines" / "Snakefile") +
                                   " --configfile " + test::shell_quote(tmp / "config.yaml") +
                                   " --cores 1 > " + test::shell_quote(tmp / "log") + " 2>&1");
  INFO(test::read_bytes(tmp / "log"));
  REQUIRE(code == 0);
  const auto dir = tmp / "out" / "cube" / "seed-1";
  const Grid g = parse_grid(test::read_bytes(dir / "model.3dgrid"));
  CHECK(g.blocks.size() == 1000);
  const std::string dat = test::read_bytes(dir / "model.dat");
  CHECK_THAT(dat, Contains("block import filename \"model.3dgrid\"\n"));
  CHECK(contact_properties(dat).at(1).at("stiffness-normal") == 5e9);
}

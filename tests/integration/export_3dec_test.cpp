// slice-export --format 3dec: the grid file parsed back (G, F, B, JS lines) against /geometry,
// and the command file's groups against the block flags and clusters.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "slice/h5io.hpp"
#include "slice/vertices.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using slice::Vec3;
using test::run_tool;

namespace {

struct Grid {
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
    long id = 0;
    ls >> tag >> id;
    INFO(line);
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
    // Clockwise seen from outside: the divergence theorem gives minus the volume, and the
    // right-hand normals point in.
    CHECK(std::abs(-v - geo.volume[b]) <= 1e-9 * geo.volume[b]);
    for (std::size_t f = 0; f < faces.size(); ++f)
      CHECK(normals[f].dot(blk.faces[f].normal) < -1 + 1e-9);
  }
  CHECK(seen_faces.size() == g.faces.size());

  // Contacts: both blocks kept, each has a face on a joint of that set, facing the other's.
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
          if (fa.joint >= 0 && fa.joint == fb.joint && fa.normal.dot(fb.normal) < -1 + 1e-9) {
            const auto& joint = bs.joints.joints[std::size_t(fa.joint)];
            const long want = joint.set >= 0 ? joint.set + 1 : long(bs.joints.sets.size()) + 1;
            facing = facing || want == js;
          }
      CHECK(facing);
    }
  }
  if (scene == "cube-3sets.toml") {  // 10 x 10 x 10 unit cubes: 900 contacts per set
    REQUIRE(g.contacts.size() == 3);
    for (const auto& [js, list] : g.contacts) CHECK(list.size() == 900);
  } else {
    CHECK(pairs > 0);
  }

  // The command file: imports the grid, groups "boundary" and "cluster-c" by ID.
  const std::string dat = test::read_bytes(tmp / "model.dat");
  CHECK_THAT(dat, Contains("block import filename \"model.3dgrid\""));
  std::set<long> boundary;
  std::map<long, std::set<long>> clusters;
  std::istringstream in(dat);
  for (std::string line; std::getline(in, line);) {
    long lo = 0, hi = 0;
    char name[64];
    int n = std::sscanf(line.c_str(), "block group \"%63[^\"]\" range id %ld %ld", name, &lo, &hi);
    if (n < 2) continue;
    if (n == 2) hi = lo;
    for (long id = lo; id <= hi; ++id) {
      if (std::string(name) == "boundary")
        boundary.insert(id);
      else
        clusters[std::stol(std::string(name).substr(8))].insert(id);
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
  if (!boundary.empty()) CHECK_THAT(dat, Contains("block fix range group \"boundary\""));
  if (scene == "rock-slope.toml") CHECK(!clusters.empty());
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
}

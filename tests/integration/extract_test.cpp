// slice-extract (issue 26 item 3, docs/submodels.md) on the tunnel scene: the blocks kept are
// those the rule says, recomputed here from the source file's vertices (the distance to the
// tunnel zone by enumerating its faces, edges and corners, not by the library's triangles; the
// blocks the region reaches between their vertices by sampling points in them);
// the fixed flags and volumes follow; the sub-model passes slice-info and every exporter, and
// its YADE model runs; bad input is refused with one line and nothing written.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/hash.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::run_tool;

namespace {

// The distance from x to the convex region planes (n . p <= d): 0 inside; else the nearest of
// the projections onto one plane, onto the line of two, and the corners of three that lie in
// the region (the nearest point lies inside a face, an edge or at a corner).
struct ConvexDistance {
  std::vector<slice::Plane> planes;
  std::vector<Vec3> corners;
  static constexpr double kFeasible = 1e-7;
  explicit ConvexDistance(std::vector<slice::Plane> p) : planes(std::move(p)) {
    const std::size_t n = planes.size();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        for (std::size_t k = j + 1; k < n; ++k) {
          Eigen::Matrix3d m;
          m << planes[i].normal.transpose(), planes[j].normal.transpose(),
              planes[k].normal.transpose();
          if (std::abs(m.determinant()) < 1e-9) continue;
          const Vec3 c = m.inverse() * Vec3(planes[i].d, planes[j].d, planes[k].d);
          if (feasible(c)) corners.push_back(c);
        }
  }
  bool feasible(const Vec3& p) const {
    return std::all_of(planes.begin(), planes.end(),
                       [&](const slice::Plane& q) { return q.distance(p) <= kFeasible; });
  }
  double operator()(const Vec3& x) const {
    if (std::all_of(planes.begin(), planes.end(),
                    [&](const slice::Plane& q) { return q.distance(x) <= 0; }))
      return 0;
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& c : corners) best = std::min(best, (c - x).norm());
    for (std::size_t i = 0; i < planes.size(); ++i) {
      const Vec3 p = x - planes[i].distance(x) * planes[i].normal;
      if (feasible(p)) best = std::min(best, (p - x).norm());
      for (std::size_t j = i + 1; j < planes.size(); ++j) {
        Eigen::Matrix<double, 2, 3> nn;
        nn << planes[i].normal.transpose(), planes[j].normal.transpose();
        const Eigen::Matrix2d g = nn * nn.transpose();
        if (std::abs(g.determinant()) < 1e-9) continue;
        const Vec3 q = x - nn.transpose() *
                               (g.inverse() * (nn * x - Eigen::Vector2d(planes[i].d, planes[j].d)));
        if (feasible(q)) best = std::min(best, (q - x).norm());
      }
    }
    return best;
  }
};

struct Case {
  std::string name;
  std::vector<std::string> args;             // the region and ring options
  std::function<double(const Vec3&)> depth;  // recomputed here
  double ring = 0;
};

std::vector<Case> cases(const slice::BlockSystem& bs) {
  std::vector<Case> out;
  out.push_back({"cylinder of 10 m about the tunnel's axis",
                 {"--cylinder", "15,-1,15,15,21,15,10"},
                 [](const Vec3& x) {
                   const double radial = std::hypot(x.x() - 15, x.z() - 15);
                   return std::min({10 - radial, x.y() + 1, 21 - x.y()});
                 },
                 0});
  out.push_back({"sphere with a 2 m ring",
                 {"--sphere", "12,8,16,9", "--ring", "2"},
                 [](const Vec3& x) { return 9 - (x - Vec3(12, 8, 16)).norm(); },
                 2});
  out.push_back({"box with a 1.5 m ring",
                 {"--box", "4.5,2.5,6,24.5,17,27.25", "--ring", "1.5"},
                 [](const Vec3& x) {
                   return std::min({x.x() - 4.5, 24.5 - x.x(), x.y() - 2.5, 17 - x.y(), x.z() - 6,
                                    27.25 - x.z()});
                 },
                 1.5});
  REQUIRE(bs.joints.zones.size() == 1);  // the tunnel's prism (a convex outline: one region)
  const auto zone = std::make_shared<ConvexDistance>(bs.joints.zones[0].planes);
  out.push_back({"6 m from the tunnel zone with a 1 m ring",
                 {"--near-zone", "0", "--distance", "6", "--ring", "1"},
                 [zone](const Vec3& x) { return 6 - (*zone)(x); },
                 1});
  return out;
}

// The rule of docs/submodels.md, from the source's vertices: which blocks are kept, and which of
// them become fixed. A block with no vertex in may still be reached between its vertices (the
// library decides that exactly, with CGAL): here points sampled in it decide, which finds every
// block reached deeper than the samples' spacing (`lower`: kept for sure) and bounds the others
// (`upper`: a block kept must have a sample within kMargin of the region).
constexpr double kMargin = 0.5;

struct Expected {
  std::vector<std::int64_t> lower, upper;
  std::vector<bool> fixed;  // by source block, for the blocks of `lower`
};

struct State {
  bool in = false, out = false, near = false;
  double shallowest = std::numeric_limits<double>::infinity();
  void add(const State& o) {
    in = in || o.in;
    out = out || o.out;
    near = near || o.near;
    shallowest = std::min(shallowest, o.shallowest);
  }
};

// The deepest of points spread over the block: on the segments between each pair of its
// vertices (eighths) and 200 random convex combinations (a fixed seed).
double sampled_depth(const std::vector<Vec3>& v, const Case& c) {
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = i + 1; j < v.size(); ++j)
      for (int k = 1; k < 8; ++k) best = std::max(best, c.depth(v[i] + (v[j] - v[i]) * (k / 8.0)));
  std::mt19937 rng(26);
  for (int n = 0; n < 200; ++n) {
    Vec3 x = Vec3::Zero();
    double sum = 0;
    for (const Vec3& p : v) {
      const double w = -std::log((double(rng()) + 0.5) / 4294967296.0);
      x += w * p;
      sum += w;
    }
    best = std::max(best, c.depth(x / sum));
  }
  return best;
}

Expected expected(const slice::BlockSystem& bs, const Case& c) {
  const auto& g = *bs.geometry;
  const double tol = bs.joints.options.tolerance * bs.joints.length_scale;
  std::vector<State> block(bs.blocks.size());
  std::map<std::int64_t, State> cluster;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    std::vector<Vec3> v(g.vertices.begin() + g.vertex_offset[b],
                        g.vertices.begin() + g.vertex_offset[b + 1]);
    for (const Vec3& x : v) {
      const double d = c.depth(x);
      block[b].in = block[b].in || d > tol;
      block[b].out = block[b].out || d < -tol;
      block[b].shallowest = std::min(block[b].shallowest, d);
    }
    if (!block[b].in) {
      const double deepest = sampled_depth(v, c);
      block[b].in = deepest > tol;
      block[b].near = deepest > -kMargin;
    }
    if (const auto id = bs.blocks[b].cluster; id >= 0) cluster[id].add(block[b]);
  }
  Expected e;
  e.fixed.assign(bs.blocks.size(), false);
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const auto& blk = bs.blocks[b];
    const State& s = blk.cluster >= 0 ? cluster[blk.cluster] : block[b];
    if (s.in || s.near) e.upper.push_back(std::int64_t(b));
    if (!s.in) continue;
    e.lower.push_back(std::int64_t(b));
    e.fixed[b] = !(blk.flags & slice::kRemoved) && (s.out || s.shallowest <= c.ring + tol);
  }
  return e;
}

std::vector<std::int64_t> read_ids(const test::fs::path& file) {
  std::ifstream in(file);
  std::vector<std::int64_t> ids;
  for (std::int64_t b; in >> b;) ids.push_back(b);
  return ids;
}

}  // namespace

TEST_CASE("slice-extract answers --help and --version", "[tools][extract]") {
  const auto help = run_tool("slice-extract", {"--help"});
  CHECK(help.exit_code == 0);
  CHECK_THAT(help.out, Contains("--cylinder") && Contains("--ring"));
  const auto version = run_tool("slice-extract", {"--version"});
  CHECK(version.exit_code == 0);
  CHECK_THAT(version.out, Contains("rockslice"));
}

TEST_CASE("slice-extract keeps the blocks the rule says, from the source's vertices",
          "[tools][extract]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "tunnel.toml", test::Stage::geometry);
  const auto bs = slice::read_blocks(geom);
  const auto& g = *bs.geometry;
  for (const Case& c : cases(bs)) {
    CAPTURE(c.name);
    const auto sub = tmp / "sub.h5", ids = tmp / "ids.txt";
    std::vector<std::string> args = {geom, "-o", sub.string(), "--ids", ids.string()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = run_tool("slice-extract", args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK_FALSE(test::fs::exists(tmp / "sub.h5.partial"));

    const Expected e = expected(bs, c);
    const auto s = slice::read_blocks(sub);
    REQUIRE(s.geometry);
    const auto kept = read_ids(ids);
    REQUIRE(s.blocks.size() == kept.size());
    CHECK(std::is_sorted(kept.begin(), kept.end()));
    CHECK(std::includes(kept.begin(), kept.end(), e.lower.begin(), e.lower.end()));
    CHECK(std::includes(e.upper.begin(), e.upper.end(), kept.begin(), kept.end()));
    INFO(kept.size() << " kept, " << e.lower.size() << " found by the test's samples");
    CHECK(kept.size() - e.lower.size() <= 10);  // reached only between the samples: few
    CHECK(kept.size() < bs.blocks.size());      // a sub-model, not the whole
    double volume = 0, source_volume = 0;
    std::size_t fixed = 0, cut_free = 0;
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const auto b = std::size_t(kept[k]);
      const auto& src = bs.blocks[b];
      const auto& blk = s.blocks[k];
      // The block unchanged but for kFixed, which the cut and ring blocks gain (those reached
      // between the test's samples are cut: fixed unless removed).
      const bool sampled = std::binary_search(e.lower.begin(), e.lower.end(), kept[k]);
      const bool fix = sampled ? bool(e.fixed[b]) : !(src.flags & slice::kRemoved);
      const std::uint8_t want = src.flags | (fix ? slice::kFixed : 0);
      CHECK(int(blk.flags) == int(want));
      CHECK(blk.cluster == src.cluster);
      CHECK(blk.faces.size() == src.faces.size());
      CHECK(s.geometry->volume[k] == g.volume[b]);
      CHECK(s.geometry->centroid[k] == g.centroid[b]);
      fixed += fix ? 1 : 0;
      cut_free += !slice::is_fixed(blk) && !(blk.flags & slice::kRemoved) ? 1 : 0;
      volume += s.geometry->volume[k];
      source_volume += g.volume[b];
    }
    CHECK(fixed > 0);
    CHECK(cut_free > 0);  // some blocks still move
    CHECK_THAT(volume, WithinRel(source_volume, 1e-12));
    // The provenance names the source, its hash and the region as given.
    const auto h = slice::read_header(sub);
    CHECK(h.provenance.tool == "slice-extract");
    CHECK(h.provenance.input == geom);
    CHECK(h.provenance.input_sha256 == slice::sha256_file(geom));
    CHECK_THAT(h.provenance.command_line, Contains(c.args[0] + " " + c.args[1]));
    // The same command gives the same bytes.
    const std::string bytes = test::read_bytes(sub);
    REQUIRE(run_tool("slice-extract", args).exit_code == 0);
    CHECK(test::read_bytes(sub) == bytes);
  }
}

TEST_CASE("a sub-model passes slice-info and every exporter, and its YADE model runs",
          "[tools][extract][yade]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "tunnel.toml", test::Stage::geometry);
  const std::string sub = (tmp / "sub.h5").string();
  // 6 m of rock about the 4 m opening, its outer 1 m fixed.
  const auto ex = run_tool("slice-extract",
                           {geom, "-o", sub, "--cylinder", "15,-1,15,15,21,15,10", "--ring", "1"});
  INFO(ex.err);
  REQUIRE(ex.exit_code == 0);
  const auto s = slice::read_blocks(sub);

  const auto info = run_tool("slice-info", {sub, "--json"});
  INFO(info.err);
  REQUIRE(info.exit_code == 0);
  const auto j = nlohmann::json::parse(info.out);
  CHECK(j["blocks"]["total"] == s.blocks.size());
  CHECK(j["provenance"]["tool"] == "slice-extract");

  for (const std::string format : {"vtu", "yade", "yade-potential-blocks", "3dec"}) {
    CAPTURE(format);
    const auto out = (tmp / ("model-" + format)).string();
    const auto r = run_tool("slice-export", {sub, "--format", format, "-o", out});
    INFO(r.err);
    CHECK(r.exit_code == 0);
    CHECK(test::fs::file_size(out) > 0);
  }

  // YADE builds the model and runs 2 steps: one body per kept block plus one per clump, the
  // fixed ones blocked.
  const auto model = tmp / "run.py", report = tmp / "report.json";
  const auto ey = run_tool("slice-export",
                           {sub, "--format", "yade", "--yade-steps", "2", "-o", model.string()});
  REQUIRE(ey.exit_code == 0);
  const int code = test::run_yade_report(model, report, tmp / "yade.log");
  INFO("yade log (tail): " << test::tail_of(tmp / "yade.log"));
  REQUIRE(code == 0);
  const auto rep = nlohmann::json::parse(test::read_bytes(report));
  REQUIRE_FALSE(rep.contains("error"));
  CHECK(rep["iterations"] == 2);
  std::size_t kept = 0, fixed = 0;
  std::map<std::int64_t, std::size_t> members;
  for (const auto& b : s.blocks) {
    if (b.flags & slice::kRemoved) continue;
    ++kept;
    fixed += slice::is_fixed(b) ? 1 : 0;
    if (b.cluster >= 0) ++members[b.cluster];
  }
  // Members under 1e-2 of the smallest moving body are no bodies (docs/dem-exports.md, "Small
  // cluster members"); export_yade_test checks the rule itself.
  for (const auto& [key, into] : rep["merged_into"].items())
    --members[s.blocks.at(std::size_t(std::stoll(key))).cluster];
  const std::size_t merged = rep["merged_into"].size();
  std::size_t clumps = 0;
  for (const auto& [c, n] : members) clumps += n >= 2 ? 1 : 0;
  CHECK(rep["bodies"].size() == kept - merged + clumps);
  CHECK(rep["body_of_block"].size() == kept - merged);
  CHECK(fixed > 0);
  for (const auto& [key, id] : rep["body_of_block"].items()) {
    const auto& blk = s.blocks.at(std::size_t(std::stoll(key)));
    if (!slice::is_fixed(blk) || blk.cluster >= 0) continue;
    CHECK(rep["bodies"].at(id.get<std::size_t>())["blocked"] == "xyzXYZ");
  }
}

TEST_CASE("slice-extract refuses bad input with one line and writes nothing", "[tools][extract]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "tunnel.toml", test::Stage::geometry);
  const auto out = tmp / "sub.h5";
  test::write_text(out, "an existing file");
  struct Bad {
    std::vector<std::string> args;
    std::vector<std::string> words;
  };
  const std::vector<Bad> bad = {
      {{"--box", "100,100,100,101,101,101"}, {"geom.h5", "keeps no block"}},
      {{"--sphere", "15,10,15,-3"}, {"--sphere", "radius is -3"}},
      {{"--cylinder", "15,-1,15,15,21,x,10"}, {"--cylinder", "'x' is not a finite number"}},
      {{"--cylinder", "15,-1,15,15,-1,15,10"}, {"--cylinder", "same point"}},
      {{"--box", "1,2,3"}, {"--box", "3 numbers; expected 6"}},
      {{"--box", "0,0,0,1,1,1e999"}, {"--box", "not a finite number"}},
      {{"--box", "5,0,0,1,1,1"}, {"--box", "not below max"}},
      {{"--sphere", "15,10,15,3", "--ring", "-1"}, {"--ring"}},
      {{"--sphere", "15,10,15,3", "--ring", "thick"}, {"--ring", "not a finite number"}},
      {{"--near-zone", "3", "--distance", "2"}, {"no zone 3", "from 0 to 0"}},
      {{"--near-zone", "tunnel", "--distance", "2"}, {"'tunnel' is not a zone index", "no names"}},
      {{"--near-zone", "0"}, {"--near-zone", "needs --distance"}},
      {{"--near-zone", "0", "--distance", "-2"}, {"--near-zone", "distance is -2"}},
      {{"--sphere", "15,10,15,3", "--distance", "2"}, {"--distance", "is for --near-zone"}},
      {{}, {"no region given"}},
      {{"--sphere", "15,10,15,3", "--box", "0,0,0,1,1,1"}, {"one region, not 2"}},
  };
  for (const Bad& b : bad) {
    std::vector<std::string> args = {geom, "-o", out.string()};
    args.insert(args.end(), b.args.begin(), b.args.end());
    CAPTURE(args);
    test::check_refused(run_tool("slice-extract", args), "slice-extract", b.words);
    CHECK(test::read_bytes(out) == "an existing file");
    CHECK_FALSE(test::fs::exists(tmp / "sub.h5.partial"));
  }
  // -o on the input, and an input that has no /geometry.
  test::check_refused(run_tool("slice-extract", {geom, "-o", geom, "--sphere", "15,10,15,8"}),
                      "slice-extract", {"the same file"});
  const auto blocks = (tmp / "blocks.h5").string();
  test::check_refused(
      run_tool("slice-extract", {blocks, "-o", out.string(), "--sphere", "15,10,15,8"}),
      "slice-extract", {"blocks.h5", "no /geometry", "slice-vertices"});
  CHECK(test::read_bytes(out) == "an existing file");
}

// slice-vertices on the example scenes: volumes, loops and half-spaces of every block.
#include <catch2/catch.hpp>

#include "slice/h5io.hpp"
#include "slice/vertices.hpp"
#include "support/blocks_check.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using test::run_tool;

TEST_CASE("slice-vertices on cube-3sets: every block is a unit cube", "[tools][vertices]") {
  test::TempDir tmp;
  const auto bs =
      slice::read_blocks(test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry));
  REQUIRE(bs.geometry);
  const auto& g = *bs.geometry;
  REQUIRE(bs.blocks.size() == 1000);
  CHECK(g.vertices.size() == 8000);
  for (std::size_t b = 0; b < 1000; ++b) {
    CAPTURE(b);
    CHECK_THAT(g.volume[b], WithinAbs(1, 1e-12));
    CHECK_THAT((g.centroid[b] - bs.blocks[b].origin).norm(), WithinAbs(0, 1e-12));
    for (std::size_t k = 0; k < 3; ++k) CHECK_THAT(g.inertia[b][k], WithinAbs(1.0 / 6, 1e-12));
  }
  for (const double a : g.face_area) CHECK_THAT(a, WithinAbs(1, 1e-12));
}

TEST_CASE("slice-vertices on every example: volumes add up, loops and vertices are right",
          "[tools][vertices]") {
  const std::string scene =
      GENERATE(as<std::string>{}, "cube-3sets.toml", "rock-slope.toml", "table3-persistent.toml");
  CAPTURE(scene);
  test::TempDir tmp;
  const auto bs = slice::read_blocks(test::run_pipeline(tmp, scene, test::Stage::geometry));
  REQUIRE(bs.geometry);
  const auto& g = *bs.geometry;
  const auto tol =
      slice::Tolerances::from_scale(bs.joints.length_scale, bs.joints.options.tolerance);

  double total = 0;
  std::size_t row = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const auto& blk = bs.blocks[b];
    total += g.volume[b];
    const auto v0 = std::size_t(g.vertex_offset[b]), v1 = std::size_t(g.vertex_offset[b + 1]);
    // Every vertex satisfies all the block's half-spaces within the tolerance.
    std::size_t outside = 0;
    for (std::size_t v = v0; v < v1; ++v)
      for (const auto& f : blk.faces)
        outside += f.normal.dot(g.vertices[v] - blk.origin) - f.d > tol.geometry ? 1 : 0;
    CHECK(outside == 0);
    // Each face loop's Newell normal points along the face normal, with the face's area.
    for (const auto& f : blk.faces) {
      std::vector<slice::Vec3> poly;
      for (auto k = g.face_vertex_offset[row]; k < g.face_vertex_offset[row + 1]; ++k)
        poly.push_back(g.vertices[v0 + std::size_t(g.face_vertices[std::size_t(k)])] - blk.origin);
      const slice::Vec3 nw = slice::newell_normal(poly);
      if (nw.normalized().dot(f.normal) < 1 - 1e-9)
        FAIL_CHECK("block " << b << " face row " << row);
      CHECK_THAT(nw.norm() / 2, WithinRel(g.face_area[row], 1e-9));
      ++row;
    }
  }
  // Removed blocks are in the file too: the volumes add up to the domain's.
  CHECK_THAT(total, WithinRel(test::domain_volume(bs.joints), 1e-9));
  // An independent volume (vertex enumeration by plane triples) for a sample of blocks.
  for (std::size_t b = 0; b < bs.blocks.size(); b += 1 + bs.blocks.size() / 200)
    CHECK_THAT(g.volume[b],
               WithinRel(test::block_volume(bs.blocks[b], 1e-12 * bs.joints.length_scale), 1e-9));
}

TEST_CASE("slice-vertices refuses unpruned blocks unless told to prune", "[tools][vertices]") {
  test::TempDir tmp;
  const std::string joints = (tmp / "joints.h5").string(), blocks = (tmp / "blocks.h5").string();
  REQUIRE(run_tool("slice-joints", {test::data_path("rock-slope.toml").string(), "-o", joints})
              .exit_code == 0);
  REQUIRE(run_tool("slice-cut", {joints, "-o", blocks}).exit_code == 0);
  const auto refused = run_tool("slice-vertices", {blocks, "-o", (tmp / "g.h5").string()});
  CHECK(refused.exit_code == 1);
  CHECK_THAT(refused.err, Contains(blocks) && Contains("not pruned") && Contains("slice-prune"));
  CHECK_FALSE(test::fs::exists(tmp / "g.h5"));

  const auto a = run_tool("slice-vertices", {blocks, "-o", (tmp / "a.h5").string(), "--prune"});
  INFO(a.err);
  REQUIRE(a.exit_code == 0);
  const auto b = run_tool("slice-vertices", {blocks, "-o", (tmp / "b.h5").string(), "--prune"});
  REQUIRE(b.exit_code == 0);
  const auto bs = slice::read_blocks(tmp / "a.h5");
  CHECK(bs.pruned);
  CHECK(bs.geometry);
  // Same input, same bytes (the command lines differ only in the output name: compare /geometry).
  const auto bs2 = slice::read_blocks(tmp / "b.h5");
  CHECK(bs.geometry->vertices == bs2.geometry->vertices);
  CHECK(bs.geometry->volume == bs2.geometry->volume);
}

TEST_CASE("slice-vertices reruns give identical files", "[tools][vertices]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "rock-slope.toml", test::Stage::geometry);
  const auto again = run_tool("slice-vertices", {(tmp / "blocks.h5").string(), "-o", geom});
  REQUIRE(again.exit_code == 0);
  const auto first = test::read_bytes(geom);
  REQUIRE(run_tool("slice-vertices", {(tmp / "blocks.h5").string(), "-o", geom}).exit_code == 0);
  CHECK(test::read_bytes(geom) == first);
}

TEST_CASE("slice-vertices reports its time per block", "[tools][vertices]") {
  test::TempDir tmp;
  const auto blocks = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::blocks);
  const auto r = run_tool("slice-vertices", {blocks, "-o", (tmp / "geom.h5").string()});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.err, Catch::Contains("us per block"));
}

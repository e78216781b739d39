// The 2-D examples of data/ (the paper's Figs. 23 and 24, docs/2d.md) through the real tools:
// slice-joints, slice-cut --prune, slice-vertices, slice-export (VTU and YADE), checked against
// what the scenes say independently of the slicer.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

namespace {

struct Run {
  slice::JointSystem joints;
  slice::BlockSystem blocks;
};

Run run(const test::TempDir& tmp, const std::string& scene) {
  const std::string geom = test::run_pipeline(tmp, scene, test::Stage::geometry);
  Run r;
  r.joints = slice::read_joints(tmp.path() / "joints.h5");
  r.blocks = slice::read_blocks(geom);
  REQUIRE(r.blocks.joints.dimension == 2);
  REQUIRE(r.blocks.geometry);
  for (const char* format : {"vtu", "yade"}) {
    const auto e = test::run_tool(
        "slice-export",
        {geom, "--format", format, "-o", (tmp.path() / (std::string("model.") + format)).string()});
    CHECK(e.exit_code == 0);
    CHECK(e.err.find("error") == std::string::npos);
  }
  return r;
}

double total_area(const slice::BlockSystem& bs, bool removed) {
  double a = 0;
  for (std::size_t i = 0; i < bs.blocks.size(); ++i)
    if (bool(bs.blocks[i].flags & slice::kRemoved) == removed) a += bs.geometry->volume[i];
  return a;
}

/// 1 + P + V: the cells of an arrangement of lines in a convex section, P lines through its
/// interior, V crossings inside it (no three lines through one point: true of these traces).
std::size_t arrangement_cells(const slice::JointSystem& js, double w, double h) {
  std::vector<std::pair<slice::Vec3, double>> lines;
  const auto inside = [&](double x, double z) { return x > 0 && x < w && z > 0 && z < h; };
  for (const slice::Joint& j : js.joints) {
    const slice::Vec3& n = j.plane.normal;
    double lo = INFINITY, hi = -INFINITY;  // n . x over the corners
    for (const double x : {0.0, w})
      for (const double z : {0.0, h}) {
        lo = std::min(lo, n.x() * x + n.z() * z);
        hi = std::max(hi, n.x() * x + n.z() * z);
      }
    if (lo < j.plane.d && j.plane.d < hi) lines.push_back({n, j.plane.d});
  }
  std::size_t crossings = 0;
  for (std::size_t a = 0; a < lines.size(); ++a)
    for (std::size_t b = a + 1; b < lines.size(); ++b) {
      const auto& [n1, d1] = lines[a];
      const auto& [n2, d2] = lines[b];
      const double det = n1.x() * n2.z() - n1.z() * n2.x();
      if (std::abs(det) < 1e-12) continue;
      const double x = (d1 * n2.z() - d2 * n1.z()) / det;
      const double z = (n1.x() * d2 - n2.x() * d1) / det;
      if (inside(x, z)) ++crossings;
    }
  return 1 + lines.size() + crossings;
}

}  // namespace

TEST_CASE("Fig. 23 (Kim et al.'s pattern) through the tools", "[tools][section]") {
  const test::TempDir a, b, c;
  const Run persistent = run(a, "kim-persistent.toml");
  const Run segments = run(b, "kim-nonpersistent.toml");
  const Run min_size = run(c, "kim-min-size.toml");
  // Persistent lines: exactly the arrangement's cells.
  CHECK(persistent.blocks.blocks.size() == arrangement_cells(persistent.joints, 20, 12));
  // Segments cut fewer blocks; the size limit undoes some more cuts (the paper's Fig. 23).
  CHECK(segments.blocks.blocks.size() < persistent.blocks.blocks.size());
  CHECK(min_size.blocks.blocks.size() < segments.blocks.blocks.size());
  for (const Run* r : {&persistent, &segments, &min_size}) {
    CHECK(std::abs(total_area(r->blocks, false) - 240) <= 1e-9 * 240);  // the 20 x 12 section
    for (const auto& blk : r->blocks.blocks) CHECK(blk.origin.y() == 0);
  }
  const double tol = 1e-9 * min_size.blocks.joints.length_scale;
  for (const auto& blk : min_size.blocks.blocks) CHECK(2 * blk.inradius >= 0.4 - tol);
  std::size_t thin = 0;
  for (const auto& blk : segments.blocks.blocks) thin += 2 * blk.inradius < 0.4 ? 1 : 0;
  CHECK(thin > 0);  // the limit had something to do

  // slice-joints counts a section's finite joints as segments (stored as rectangles).
  const auto joints = test::run_tool(
      "slice-joints",
      {test::data_path("kim-nonpersistent.toml").string(), "-o", (b.path() / "again.h5").string()});
  CHECK(joints.exit_code == 0);
  CHECK_THAT(
      joints.err,
      Catch::Contains(std::to_string(segments.joints.joints.size()) + " joints (0 persistent, " +
                      std::to_string(segments.joints.joints.size()) + " segments)"));
}

TEST_CASE("Fig. 24 (a slope section built the Vajont way) through the tools", "[tools][section]") {
  const test::TempDir tmp;
  const Run r = run(tmp, "vajont-section.toml");
  const slice::BlockSystem& bs = r.blocks;
  // The profile P0 (0, 460) - P1 (220, 440) - P2 (520, 260) - P3 (800, 220) in the 800 x 500
  // section: the air above it is 400000 - 271200 m2, and the construction joints outline it
  // exactly.
  CHECK(std::abs(total_area(bs, true) - 128800) <= 1e-9 * 128800);
  CHECK(std::abs(total_area(bs, false) - 271200) <= 1e-9 * 271200);
  std::size_t boundary = 0;
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    const slice::Block& blk = bs.blocks[i];
    if (blk.flags & slice::kBoundary) {
      ++boundary;
      // Below the slide surface: the back z = 440 - x tan 40 or the seat.
      const slice::Vec3& c = bs.geometry->centroid[i];
      CHECK((c.z() < 440 - c.x() * std::tan(40 * M_PI / 180) ||
             c.z() < 150 + (c.x() - 600) * std::tan(3 * M_PI / 180)));
    }
    if (blk.cluster >= 0) CHECK_FALSE(blk.flags & slice::kRemoved);
    // The size limit holds for every block an exempt (construction) cut did not make.
    if (2 * blk.inradius < 3.0 - 1e-9 * bs.joints.length_scale) {
      bool exempt = false;
      for (const slice::Face& f : blk.faces)
        exempt = exempt || (f.joint >= 0 && !bs.joints.joints[std::size_t(f.joint)].limits);
      CHECK(exempt);
    }
  }
  CHECK(boundary == 2);
  // pipelines/plot: the stereonet and the areas' distribution (pipelines/setup installs h5py
  // and matplotlib: without them this fails, not skips).
  const std::string plot = (test::data_path("..") / "pipelines" / "plot").string();
  REQUIRE(test::run_shell("/usr/bin/python3 " + test::shell_quote(plot) + " " +
                          test::shell_quote(tmp / "geom.h5") + " -o " +
                          test::shell_quote(tmp / "png") + " 2>/dev/null") == 0);
  for (const char* png : {"geom-stereonet.png", "geom-volumes.png"}) {
    CAPTURE(png);
    const std::string bytes = test::read_bytes(tmp / "png" / png);
    REQUIRE(bytes.size() > 1000);
    CHECK(bytes.substr(1, 3) == "PNG");
  }
}

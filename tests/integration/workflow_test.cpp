// Issue 13: the paper's slope and tunnel workflow end to end (section 3.4, Fig. 24) on
// data/tunnel.toml and data/slope.toml, through the real tools: boundary joints (stage 1), rock
// joints (stage 2), construction joints outlining the opening or the free surface (stage 3,
// limits = false; the tunnel's come from its zone, cut = true), clusters, removal. The YADE run of
// both is in export_yade_test.cpp.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <set>
#include <string>

#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

namespace {

using slice::Vec3;

struct Workflow {
  const char* scene;
  double outline_volume;  // the volume the construction joints outline (the zone)
};

}  // namespace

TEST_CASE("the tunnel and the slope built the paper's way keep their outline",
          "[tools][workflow]") {
  // The 16-gon about a circle of radius 4 m (a [[zones]] tunnel, cut = true), 20 m of it inside
  // the domain: n R^2 tan(pi / n) L. The air above the slope: 20 m wide, (20 x 20 / 2 + 20 x 20)
  // m2 across.
  const Workflow w =
      GENERATE(Workflow{"tunnel.toml", 16 * 16 * std::tan(std::numbers::pi / 16) * 20},
               Workflow{"slope.toml", 600.0 * 20});
  CAPTURE(w.scene);
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, w.scene, test::Stage::geometry);
  const slice::BlockSystem bs = slice::read_blocks(geom);
  REQUIRE(bs.geometry);
  const auto& g = *bs.geometry;
  const auto& js = bs.joints;
  const double tol = js.options.tolerance * js.length_scale;
  REQUIRE(js.zones.size() == 1);
  const auto& zone = js.zones[0].planes;

  // The sequence: boundary joint, then the rock sets, then the construction joints.
  std::vector<int> rank;
  for (const auto& j : js.joints)
    rank.push_back(j.kind == slice::JointKind::boundary       ? 0
                   : j.kind == slice::JointKind::construction ? 2
                                                              : 1);
  CHECK(std::is_sorted(rank.begin(), rank.end()));

  double removed_volume = 0;
  std::size_t removed = 0, fixed = 0, boundary = 0, exempt_small = 0;
  std::set<std::int64_t> clusters_of_removed;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    CAPTURE(b);
    const auto& blk = bs.blocks[b];
    fixed += (blk.flags & slice::kFixed) ? 1 : 0;
    boundary += (blk.flags & slice::kBoundary) ? 1 : 0;
    if (blk.flags & slice::kRemoved) {
      ++removed;
      removed_volume += g.volume[b];
      if (blk.cluster >= 0) clusters_of_removed.insert(blk.cluster);
      // A removed block lies inside the outline (it is convex: its vertices suffice).
      for (auto v = g.vertex_offset[b]; v < g.vertex_offset[b + 1]; ++v)
        for (const auto& p : zone) CHECK(p.distance(g.vertices[std::size_t(v)]) <= tol);
    }
    // The size limit holds for every block but those an exempt (limits = false) joint made.
    if (2 * blk.inradius < js.options.min_inscribed_diameter - tol) {
      bool made_by_exempt = false;
      for (const auto& f : blk.faces)
        made_by_exempt |= f.joint >= 0 && !js.joints[std::size_t(f.joint)].limits;
      CHECK(made_by_exempt);
      exempt_small += 1;
    }
  }
  // Removed blocks fill the outline: with every removed block inside it, no kept block reaches
  // into the opening (the blocks tile the domain), and no removed block reaches into the rock.
  CHECK(std::abs(removed_volume - w.outline_volume) <= 0.01 * w.outline_volume);
  CHECK(std::abs(removed_volume - w.outline_volume) <= 1e-9 * w.outline_volume);
  CHECK(clusters_of_removed.empty());  // no cluster contains a removed block
  CHECK(removed > 0);
  CHECK(boundary >= 1);
  CHECK(fixed > 0);
  CHECK(exempt_small > 0);  // the outline made thin pieces, exempt from the limit
}

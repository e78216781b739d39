// No free sliver (docs/design.md, "Clusters and slivers"): on random scenes with rock joints, an
// exempt construction joint outlining an excavation (limits = false) and the removal zone beyond
// it, no kept block in no cluster breaks the size limit; the volumes still add up to the domain;
// and every block removed though its centre is in no zone lies within the minimum size of one.
#include <catch2/catch.hpp>
#include <random>
#include <sstream>

#include "slice/cut.hpp"
#include "slice/decide.hpp"
#include "slice/lp.hpp"
#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "support/blocks_check.hpp"
#include "support/support.hpp"

using slice::Vec3;

namespace {

struct RandomScene {
  std::string toml;
  double min_diameter = 0;
  bool excavate = false;  // [options] slivers = "excavate" (else the default, "join")
};

Vec3 unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0, 1);
  Vec3 v(g(rng), g(rng), g(rng));
  return v.normalized();
}

void joint(std::ostringstream& s, const Vec3& n, const Vec3& p) {
  const slice::DipAndDirection dd = slice::dip_from_normal(n);
  s << "[[joints]]\ndip = " << dd.dip_deg << "\ndip_direction = " << dd.dip_direction_deg
    << "\npoint = [" << p.x() << ", " << p.y() << ", " << p.z() << "]\n";
}

/// A 10 x 8 x 6 box; 6 to 14 rock joints (half persistent, half squares); one plane through the
/// box as a persistent construction joint exempt from the limits, with the region above it a
/// removal zone (an excavation face); a minimum inscribed diameter of 0.3 to 1.
RandomScene random_scene(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  std::ostringstream s;
  s.precision(17);
  RandomScene out;
  out.min_diameter = 0.3 + 0.7 * u01(rng);
  out.excavate = seed % 2 == 0;
  const Vec3 size(10, 8, 6);
  s << "[domain]\nbox = { min = [0, 0, 0], max = [10, 8, 6] }\n[options]\norder = \"as-given\"\n"
    << "min_inscribed_diameter = " << out.min_diameter << "\n";
  if (out.excavate) s << "slivers = \"excavate\"\n";
  const int joints = 6 + int(seed % 9);
  for (int j = 0; j < joints; ++j) {
    const Vec3 p = size.cwiseProduct(Vec3(u01(rng), u01(rng), u01(rng)));
    joint(s, unit(rng), p);
    if (u01(rng) < 0.5) {
      const double h = 1 + 3 * u01(rng);
      s << "polygon_uv = [[" << -h << ", " << -h << "], [" << h << ", " << -h << "], [" << h << ", "
        << h << "], [" << -h << ", " << h << "]]\n";
    }
  }
  // The excavation face: through a point near the box's middle, facing mostly up.
  Vec3 n = unit(rng);
  n.z() = std::abs(n.z()) + 0.5;
  n.normalize();
  const Vec3 p = size.cwiseProduct(Vec3(0.3 + 0.4 * u01(rng), 0.3 + 0.4 * u01(rng), 0.5));
  joint(s, n, p);
  s << "kind = \"construction\"\nlimits = false\nstage = 2\n";
  s << "[[zones]]\nplanes = [{ normal = [" << -n.x() << ", " << -n.y() << ", " << -n.z()
    << "], d = " << -n.dot(p) << " }]\n";
  out.toml = s.str();
  return out;
}

}  // namespace

TEST_CASE("random excavations leave no free sliver and lose no volume",
          "[property][cut][slivers]") {
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(120))));
  CAPTURE(seed);
  const RandomScene rs = random_scene(seed);
  CAPTURE(rs.toml);
  const auto js = slice::generate_joints(slice::parse_scene(rs.toml, "random.toml"));
  auto r = slice::cut_blocks(js, slice::CutOptions{});
  slice::prune_blocks(r.blocks, slice::LpBackend::native);
  const auto& blocks = r.blocks.blocks;
  CHECK(r.stats.slivers_left == 0);

  const double L = js.length_scale;
  const slice::Tolerances tol = slice::Tolerances::from_scale(L, js.options.tolerance);
  auto exact = slice::make_solver(slice::LpBackend::exact);
  const slice::Plane face = js.zones.at(0).planes.at(0);  // outward from the zone: rock side
  double volume = 0;
  std::size_t zone_removed = 0;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    CAPTURE(i);
    const auto& b = blocks[i];
    volume += test::block_volume(b, 1e-9 * L);
    const bool removed = b.flags & slice::kRemoved;
    const bool in_zone = face.distance(b.origin) < 0;
    zone_removed += removed && in_zone ? 1 : 0;
    if (!removed && b.cluster < 0) {
      // The exact Chebyshev ball, not the cut's own figure.
      const slice::ChebyshevBall c = slice::chebyshev_ball(*exact, b.faces, tol);
      REQUIRE(c.status == slice::LpStatus::optimal);
      CHECK(2 * c.radius >= rs.min_diameter - 1e-9 * L);
    }
    if (removed && !in_zone) {
      CHECK(rs.excavate);  // "join" removes exactly the zone's blocks
      // A sliver gone with the excavation: under the limit, and no deeper behind the face than
      // the minimum size (its extreme point against the face's normal, by the exact LP).
      const slice::ChebyshevBall c = slice::chebyshev_ball(*exact, b.faces, tol);
      CHECK(2 * c.radius < rs.min_diameter);
      slice::DenseLp& lp = slice::extents_lp(*exact, b.faces, tol);
      lp.c.setZero();
      lp.c.head<3>() = face.normal;
      const slice::LpResult deepest = exact->solve(lp);
      REQUIRE(deepest.status == slice::LpStatus::optimal);
      CHECK(face.distance(b.origin) + deepest.objective <= rs.min_diameter + 1e-9 * L);
    }
  }
  CHECK(zone_removed > 0);
  if (!rs.excavate) CHECK(r.stats.slivers_removed == 0);
  CHECK_THAT(volume, Catch::Matchers::WithinRel(test::domain_volume(js), 1e-9));
}

TEST_CASE("slivers are resolved the same way on every thread count", "[property][cut][slivers]") {
  const auto seed = GENERATE(range(1u, 1u + static_cast<unsigned>(test::scaled_cases(10))));
  CAPTURE(seed);
  const auto js =
      slice::generate_joints(slice::parse_scene(random_scene(seed).toml, "random.toml"));
  slice::CutOptions one, two;
  one.threads = 1;
  two.threads = 2;
  one.tasks = two.tasks = 4;  // hand blocks to tasks early, so threads do split the work
  const auto a = slice::cut_blocks(js, one), b = slice::cut_blocks(js, two);
  REQUIRE(a.blocks.blocks.size() == b.blocks.blocks.size());
  CHECK(a.stats.slivers_removed == b.stats.slivers_removed);
  CHECK(a.stats.slivers_joined == b.stats.slivers_joined);
  for (std::size_t i = 0; i < a.blocks.blocks.size(); ++i) {
    CAPTURE(i);
    CHECK(a.blocks.blocks[i].flags == b.blocks.blocks[i].flags);
    CHECK(a.blocks.blocks[i].cluster == b.blocks.blocks[i].cluster);
  }
}

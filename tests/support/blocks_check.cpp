#include "support/blocks_check.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "slice/polytope.hpp"
#include "slice/tolerance.hpp"

namespace test {

using slice::Vec3;

std::vector<slice::Plane> global_planes(const slice::Block& b) {
  std::vector<slice::Plane> p;
  for (const auto& f : b.faces) p.push_back(slice::to_global({f.normal, f.d}, b.origin));
  return p;
}

double block_volume(const slice::Block& b, double tol) {
  // In the block's frame: the vertex enumeration then works on small numbers.
  std::vector<slice::Plane> p;
  for (const auto& f : b.faces) p.push_back({f.normal, f.d});
  return slice::analyse_polytope(p, tol).volume;
}

double domain_volume(const slice::JointSystem& js) {
  return slice::analyse_polytope(js.domain.planes, js.options.tolerance * js.length_scale).volume;
}

InvariantReport check_invariants(const slice::BlockSystem& bs, std::size_t points,
                                 std::uint64_t seed) {
  InvariantReport rep;
  const auto& js = bs.joints;
  const double tol = js.options.tolerance * js.length_scale;
  const auto tols = slice::Tolerances::from_scale(js.length_scale, js.options.tolerance);
  const auto dom = slice::analyse_polytope(js.domain.planes, tol);
  rep.domain_volume = dom.volume;

  // (c) inradius and (d) volumes. Vertices are merged at 1e-12 L, well below the cut
  // tolerance: a block as thin as the tolerance keeps its volume.
  std::vector<double> volume(bs.blocks.size());
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    CAPTURE(i);
    CHECK(bs.blocks[i].inradius > 0);
    volume[i] = block_volume(bs.blocks[i], 1e-12 * js.length_scale);
    CHECK(volume[i] > 0);
    rep.volume_sum += volume[i];
  }
  CHECK_THAT(rep.volume_sum, Catch::Matchers::WithinRel(rep.domain_volume, 1e-9));

  // (a) Monte Carlo point location.
  std::mt19937_64 rng(seed);
  std::vector<std::size_t> hits(bs.blocks.size(), 0);
  std::size_t inside_domain = 0;
  const double box_volume = (dom.max - dom.min).prod();
  while (rep.points < points) {
    Vec3 x;
    for (int k = 0; k < 3; ++k)
      x[k] = std::uniform_real_distribution<double>(dom.min[k], dom.max[k])(rng);
    const bool in_domain = std::all_of(js.domain.planes.begin(), js.domain.planes.end(),
                                       [&](const slice::Plane& p) { return p.distance(x) < 0; });
    ++rep.points;
    if (!in_domain) continue;
    ++inside_domain;
    std::size_t count = 0, last = 0;
    bool near = false;
    for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
      const auto& b = bs.blocks[i];
      if ((x - b.bsphere.head<3>()).norm() > b.bsphere[3] + tol) continue;
      const Vec3 l = x - b.origin;
      double worst = -INFINITY;
      for (const auto& f : b.faces) worst = std::max(worst, f.normal.dot(l) - f.d);
      if (std::abs(worst) <= tol) near = true;
      if (worst < -tol) {
        ++count;
        last = i;
      }
    }
    if (near) {
      ++rep.points_near_face;
      continue;
    }
    if (count == 0) ++rep.points_outside;
    if (count > 1) ++rep.points_in_two;
    if (count == 1) ++hits[last];
  }
  CHECK(rep.points_outside == 0);
  CHECK(rep.points_in_two == 0);
  // Hit fractions estimate the volumes: binomial counts within 6 sigma.
  const double per_volume = double(rep.points) / box_volume;
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    const double expected = volume[i] * per_volume;
    const double sigma = std::sqrt(std::max(expected, 1.0));
    const double err = std::abs(double(hits[i]) - expected) / sigma;
    rep.worst_hit_error_sigma = std::max(rep.worst_hit_error_sigma, err);
  }
  CHECK(rep.worst_hit_error_sigma < 6.0);
  CHECK_THAT(
      double(inside_domain) / double(rep.points),
      Catch::Matchers::WithinAbs(rep.domain_volume / box_volume, 6 / std::sqrt(double(points))));

  // (b) No overlap: the largest ball inside two blocks at once has radius <= tol.
  const auto solver = slice::make_solver(slice::LpBackend::native);
  std::vector<slice::Face> merged;
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    const auto& a = bs.blocks[i];
    for (std::size_t j = i + 1; j < bs.blocks.size(); ++j) {
      const auto& b = bs.blocks[j];
      if ((a.bsphere.head<3>() - b.bsphere.head<3>()).norm() >= a.bsphere[3] + b.bsphere[3])
        continue;
      merged = a.faces;
      const Vec3 shift = b.origin - a.origin;
      for (auto f : b.faces) {
        f.d += f.normal.dot(shift);
        merged.push_back(f);
      }
      const auto ball = slice::chebyshev_ball(*solver, merged, tols);
      ++rep.pairs_checked;
      if (ball.status == slice::LpStatus::optimal && ball.radius > tol) {
        ++rep.overlapping_pairs;
        CAPTURE(i, j, ball.radius);
        CHECK(ball.radius <= tol);
      }
    }
  }
  return rep;
}

}  // namespace test

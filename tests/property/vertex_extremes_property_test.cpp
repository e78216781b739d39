// The vertex extremes' kernels (libslice/src/lp/vertex_extremes.hpp): four triples of faces at a
// time where the CPU has AVX2, against the portable kernel one triple at a time. slice-cut's blocks
// (their origins and spheres) depend on every bit of the vertices found, so the two must find the
// same directions with the same bits, on one block and on both pieces of a split: random blocks of
// 4 to 10 faces (every remainder of four triples), blocks whose normals come from a few directions
// as a DFN's fixed-orientation sets make them (parallel faces, many triples without a vertex),
// boxes cut through a corner (several triples at one vertex), planes through a vertex, along an
// edge and on a face, blocks 1e6 m from the origin, and blocks of more than 10 faces (left whole).
// Fixed seeds; SLICE_PROPERTY_SCALE (support.hpp) runs a share.
#include <bit>
#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <vector>

#include "cpu.hpp"
#include "lp/vertex_extremes.hpp"
#include "support/lp_cases.hpp"
#include "support/support.hpp"

namespace {

using namespace test::lp;
using slice::VertexExtremes;
using slice::detail::vertex_extremes_of;

constexpr std::uint64_t kSeed = 3030;

/// A block of `n` faces whose normals are drawn (with either sign) from `directions` unit vectors
/// and the axes, as the faces of a scene of fixed-orientation sets in a box domain; offsets put
/// the faces 0.1 to 1 from the origin, so it is bounded wherever its normals span space.
std::vector<Face> few_directions(Rng& rng, std::size_t n, const std::vector<Vec3>& directions) {
  std::vector<Face> faces;
  while (faces.size() < n) {
    const int pick = rng.index(int(directions.size()) + 3);
    Vec3 normal = pick < int(directions.size()) ? directions[std::size_t(pick)]
                                                : Vec3::Unit(pick - int(directions.size()));
    if (rng.chance(0.5)) normal = -normal;
    faces.push_back({normal, rng.uniform(0.1, 1.0)});
  }
  return faces;
}

/// Faces moved so that the block's origin lies `shift` away (d grows with the shift).
std::vector<Face> shifted(std::vector<Face> faces, const Vec3& shift) {
  for (Face& f : faces) f.d += f.normal.dot(shift);
  return faces;
}

}  // namespace

TEST_CASE("vertex extremes: the AVX2 kernel gives the portable kernel's bits",
          "[property][lp][extents]") {
#if defined(__x86_64__)
  // On x86-64 the vector kernel must be the one under test (an AVX2 CPU, SLICE_NO_AVX2 unset),
  // or the comparison is empty.
  REQUIRE(slice::use_avx2());
#endif
  const long n = test::scaled_cases(200'000, 16);
  long answered = 0, wanted_total = 0, wrong = 0, whole = 0;
  std::string first_wrong;
  std::vector<Vec3> directions;
  for (long i = 0; i < n; ++i) {
    Rng rng(mix(kSeed, static_cast<std::uint64_t>(i)));
    const int kind = static_cast<int>(i % 6);
    std::vector<Face> faces;
    switch (kind) {
      case 0:  // a random block, 4 to 12 faces (over 10: left whole)
      case 1: {
        RandomBlock block = random_block(rng, 4 + rng.index(9), 1.0, kind == 1);
        faces = block.faces;
        break;
      }
      case 2:  // few directions
      case 3: {
        directions.clear();
        for (int d = 0; d < 1 + rng.index(3); ++d) directions.push_back(rng.unit_vector());
        faces = few_directions(rng, 4 + std::size_t(rng.index(7)), directions);
        break;
      }
      default: {  // a block and a plane through its inside, a vertex, an edge, on a face ...
        RandomBlock block = random_block(rng, 4 + rng.index(6), 1.0, rng.chance(0.3));
        enumerate_vertices(block, 1.0);
        faces = block.faces;
        if (!block.vertices.empty()) {
          const Plane p = random_plane(rng, block, static_cast<PlaneKind>(rng.index(7)), 1.0);
          faces.push_back({p.normal, p.d});
        }
      }
    }
    if (rng.chance(0.25)) faces = shifted(faces, Vec3(1e6, -2e6, 3e5));
    const unsigned w0 = rng.chance(0.3) ? 0x3fu : unsigned(rng.index(64));
    const unsigned w1 = rng.chance(0.3) ? 0x3fu : unsigned(rng.index(64));
    const auto one = vertex_extremes_of<1>(faces, {w0}, true);
    const auto one_portable = vertex_extremes_of<1>(faces, {w0}, false);
    const auto two = vertex_extremes_of<2>(faces, {w0, w1}, true);
    const auto two_portable = vertex_extremes_of<2>(faces, {w0, w1}, false);
    const bool same = same_bits(one[0], one_portable[0]) && same_bits(two[0], two_portable[0]) &&
                      same_bits(two[1], two_portable[1]);
    wanted_total += std::popcount(w0) * 2 + std::popcount(w1);
    answered +=
        std::popcount(one[0].found) + std::popcount(two[0].found) + std::popcount(two[1].found);
    whole += faces.size() > slice::kVertexFaces && !one[0].found && !two[0].found && !two[1].found;
    if (!same && ++wrong <= 10)
      first_wrong += "case " + std::to_string(i) + " kind " + std::to_string(kind) + " (" +
                     std::to_string(faces.size()) + " faces); ";
  }
  INFO(answered << " of " << wanted_total << " wanted directions answered");
  INFO(first_wrong);
  CHECK(wrong == 0);
  CHECK(answered >= wanted_total / 3);  // the cases are not trivially empty
  CHECK(whole > 0);                     // blocks of more than 10 faces met
}

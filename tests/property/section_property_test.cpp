// 2-D mode (docs/2d.md) against 3-D: a random section in (x, z) is cut with two-variable LPs;
// the same scene written in 3-D, as a prism of height kHeight along y with the same (vertical)
// joints, is cut with the three-variable LPs. The blocks must be the same, block by block: the
// prisms of the section's polygons.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "slice/cut.hpp"
#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "slice/vertices.hpp"
#include "support/support.hpp"

namespace {

constexpr double kHeight = 100;  // the prism: tall, so no inscribed ball touches its ends

struct Line {
  double dip, dip_direction, x, z;
  bool segment;
  double a, b;  // the segment's ends along the line, from (x, z)
};

/// The point at distance t along the line from (x, z): the line runs along
/// (cos dip, -s sin dip) with s = +1 for dip direction 90, -1 for 270.
std::pair<double, double> along(const Line& l, double t) {
  const double d = l.dip * M_PI / 180, s = l.dip_direction == 90 ? 1 : -1;
  return {l.x + t * std::cos(d), l.z - t * s * std::sin(d)};
}

/// The scene as a section (dimension 2) or as the prism (dimension 3).
std::string scene_text(std::uint64_t seed, int dimension) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  const auto dd = [&] { return u01(rng) < 0.5 ? 90.0 : 270.0; };
  const bool three = dimension == 3;
  std::ostringstream s;
  s.precision(17);
  const auto point = [&](double x, double y, double z) {
    std::ostringstream p;
    p.precision(17);
    if (three)
      p << "[" << x << ", " << y << ", " << z << "]";
    else
      p << "[" << x << ", " << z << "]";
    return p.str();
  };
  s << "[scene]\nseed = " << seed << "\n" << (three ? "" : "dimension = 2\n");
  s << "[domain]\nbox = { min = " << point(0, -kHeight / 2, 0)
    << ", max = " << point(10, kHeight / 2, 6) << " }\n";
  s << "[options]\norder = \"" << (seed % 2 ? "as-given" : "largest-first") << "\"\n";
  if (seed % 3 == 0) s << "min_inscribed_diameter = 0.2\n";
  if (seed % 4 == 0) s << "fixed_faces = [\"-z\", \"+x\"]\n";
  std::vector<Line> lines;
  lines.push_back({20 * u01(rng), dd(), 5, 1 + u01(rng), false, 0, 0});
  for (int j = 0; j < 5; ++j) {
    Line l{90 * u01(rng), dd(), 10 * u01(rng), 6 * u01(rng), j >= 2, 0, 0};
    l.a = -4 * u01(rng) - 0.5;
    l.b = 4 * u01(rng) + 0.5;
    lines.push_back(l);
  }
  for (std::size_t j = 0; j < lines.size(); ++j) {
    const Line& l = lines[j];
    s << "[[joints]]\ndip = " << l.dip << "\ndip_direction = " << l.dip_direction
      << "\npoint = " << point(l.x, 0, l.z) << "\n";
    if (j == 0) s << "kind = \"boundary\"\nkeep = \"below\"\n";
    if (j == 1 || j == 3) s << "kind = \"construction\"\nlimits = false\n";
    if (l.segment) {
      const auto [x1, z1] = along(l, l.a);
      const auto [x2, z2] = along(l, l.b);
      if (three)  // the rectangle of the plane through the whole prism
        s << "polygon = [" << point(x1, -kHeight, z1) << ", " << point(x1, kHeight, z1) << ", "
          << point(x2, kHeight, z2) << ", " << point(x2, -kHeight, z2) << "]\n";
      else
        s << "segment = [" << point(x1, 0, z1) << ", " << point(x2, 0, z2) << "]\n";
    }
  }
  for (int k = 0; k < 2; ++k)
    s << "[[sets]]\ndip = " << 90 * u01(rng) << "\ndip_direction = " << dd()
      << "\nspacing = " << 0.8 + u01(rng) << "\noffset = " << u01(rng) << "\n";
  s << "[[zones]]\nbox = { min = " << point(6, -kHeight, 3) << ", max = " << point(10, kHeight, 6)
    << " }\n";
  return s.str();
}

slice::BlockSystem cut_and_prune(const std::string& text,
                                 slice::LpBackend backend = slice::LpBackend::native) {
  const slice::JointSystem js = slice::generate_joints(slice::parse_scene(text, "section.toml"));
  slice::CutOptions opt;
  opt.backend = backend;
  opt.threads = 1;
  slice::BlockSystem bs = slice::cut_blocks(js, opt).blocks;
  slice::prune_blocks(bs, opt.backend, {}, false, 1);
  slice::compute_geometry(bs, {}, 1);
  return bs;
}

std::vector<std::int64_t> joints_of(const slice::Block& b) {
  std::vector<std::int64_t> j;
  for (const slice::Face& f : b.faces) j.push_back(f.joint);
  std::sort(j.begin(), j.end());
  return j;
}

}  // namespace

TEST_CASE("a section gives the blocks of its prism block by block", "[property][section]") {
  const long n = test::scaled_cases(30);
  long blocks = 0;
  for (long seed = 1; seed <= n; ++seed) {
    CAPTURE(seed);
    const slice::BlockSystem two = cut_and_prune(scene_text(std::uint64_t(seed), 2));
    const slice::BlockSystem three = cut_and_prune(scene_text(std::uint64_t(seed), 3));
    REQUIRE(two.joints.dimension == 2);
    REQUIRE(three.joints.dimension == 3);
    REQUIRE(two.blocks.size() == three.blocks.size());
    const double L = two.joints.length_scale;
    for (std::size_t i = 0; i < two.blocks.size(); ++i) {
      CAPTURE(i);
      const slice::Block& a = two.blocks[i];
      const slice::Block& b = three.blocks[i];
      CHECK(a.flags == b.flags);
      CHECK(a.cluster == b.cluster);
      CHECK(std::abs(a.inradius - b.inradius) <= 1e-9 * L);
      CHECK(a.origin.y() == 0);
      CHECK(std::abs(a.origin.x() - b.origin.x()) <= 1e-9 * L);
      CHECK(std::abs(a.origin.z() - b.origin.z()) <= 1e-9 * L);
      // The prism has the section's faces and its two ends (domain faces, joint -1).
      std::vector<std::int64_t> ends = joints_of(a);
      ends.insert(ends.begin(), {-1, -1});
      CHECK(joints_of(b) == ends);
      for (const slice::Face& f : a.faces) CHECK(f.normal.y() == 0);
      // Areas are the prisms' volumes over their height; centroids the same in (x, z).
      const slice::Geometry& ga = *two.geometry;
      const slice::Geometry& gb = *three.geometry;
      CHECK(std::abs(ga.volume[i] - gb.volume[i] / kHeight) <= 1e-9 * ga.volume[i]);
      CHECK(std::abs(ga.centroid[i].x() - gb.centroid[i].x()) <= 1e-9 * L);
      CHECK(std::abs(ga.centroid[i].z() - gb.centroid[i].z()) <= 1e-9 * L);
    }
    blocks += static_cast<long>(two.blocks.size());
    double area = 0;
    for (const double a : two.geometry->volume) area += a;
    CHECK(std::abs(area - 60) <= 1e-9 * 60);  // the 10 x 6 section, tiled
  }
  INFO(blocks << " blocks in " << n << " sections");
  CHECK(blocks > 30 * n);
}

// The two-variable LPs on every backend: exact (CGAL) and ipopt make the blocks native makes.
TEST_CASE("a section cuts the same on every LP backend", "[property][section][lp]") {
  const long n = test::scaled_cases(3);
  for (long seed = 1; seed <= n; ++seed) {
    CAPTURE(seed);
    const std::string text = scene_text(std::uint64_t(seed), 2);
    const slice::BlockSystem native = cut_and_prune(text);
    const double L = native.joints.length_scale;
    for (const auto backend : {slice::LpBackend::exact, slice::LpBackend::ipopt}) {
      CAPTURE(slice::to_string(backend));
      const slice::BlockSystem other = cut_and_prune(text, backend);
      REQUIRE(other.blocks.size() == native.blocks.size());
      double worst = 0;
      for (std::size_t i = 0; i < native.blocks.size(); ++i) {
        CHECK(other.blocks[i].flags == native.blocks[i].flags);
        CHECK(joints_of(other.blocks[i]) == joints_of(native.blocks[i]));
        worst =
            std::max(worst, (other.geometry->centroid[i] - native.geometry->centroid[i]).norm());
        CHECK(std::abs(other.geometry->volume[i] - native.geometry->volume[i]) <=
              1e-6 * native.geometry->volume[i]);
      }
      CHECK(worst <= 1e-6 * L);
    }
  }
}

// Tunnel zones through the real tools (issue 16, item 3): slice-joints, slice-cut and
// slice-vertices on a 20 m cube cut by two persistent sets. With cut = true the construction
// joints outline the tunnel first, so the removed blocks fill its prism exactly and no kept block
// reaches into it; without, the removed blocks are whatever rock blocks have their centre inside.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/tunnel.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using slice::Vec2;
using slice::Vec3;
using test::run_tool;

namespace {

// A horseshoe, counter-clockwise: a floor with an upward bump (a reflex vertex), walls that
// bulge out, an arch. Star-shaped about the axis, not convex.
const std::vector<Vec2> kHorseshoe = {{0, -1.5}, {2, -2},     {3.5, 0}, {3, 2},    {1.5, 3.4},
                                      {0, 3.8},  {-1.5, 3.4}, {-3, 2},  {-3.5, 0}, {-2, -2}};

struct Section {
  const char* name;
  std::string toml;  // the section's keys in `tunnel`
  double area;       // of the section
};

std::vector<Section> sections() {
  std::string outline = "outline = [";
  for (std::size_t i = 0; i < kHorseshoe.size(); ++i)
    outline += (i ? ", [" : "[") + std::to_string(kHorseshoe[i].x()) + ", " +
               std::to_string(kHorseshoe[i].y()) + "]";
  outline += "]";
  double area = 0;  // shoelace
  for (std::size_t i = 0; i < kHorseshoe.size(); ++i) {
    const Vec2 a = kHorseshoe[i], b = kHorseshoe[(i + 1) % kHorseshoe.size()];
    area += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  // The 12-gon about a circle of radius 3: n R^2 tan(pi / n).
  return {{"round", "radius = 3, sides = 12", 12 * 9 * std::tan(std::numbers::pi / 12)},
          {"horseshoe", outline, area}};
}

// The tunnel of the scene: axis from (9, 4, 10.5) along (0.2, 1, 0.1), 12 m; both ends inside.
const Vec3 kPoint(9, 4, 10.5), kDirection(0.2, 1, 0.1);
constexpr double kLength = 12;

std::string scene(const Section& s, bool cut) {
  std::string t =
      "[scene]\nname = \"tunnel-zone\"\n"
      "[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 20] }\n"
      "[options]\nmin_inscribed_diameter = 0.2\n"
      "[[sets]]\nname = \"A\"\ndip = 35\ndip_direction = 70\nspacing = 3.1\n"
      "[[sets]]\nname = \"B\"\ndip = 80\ndip_direction = 200\nspacing = 4.3\noffset = 0.7\n"
      "[[zones]]\ntunnel = { point = [9, 4, 10.5], direction = [0.2, 1, 0.1], length = 12, ";
  t += s.toml + " }\n";
  if (cut) t += "cut = true\n";
  return t;
}

// Whether x is inside the tunnel's prism by more than `margin`, tested directly in the section
// frame (the polygon shrunk by sampling: x and the four points `margin` away in the section).
bool deep_inside(const std::vector<Vec2>& outline, const Vec3& x, double margin) {
  const slice::TunnelFrame f = slice::tunnel_frame(kDirection);
  const Vec3 r = x - kPoint;
  const double s = f.d.dot(r);
  const Vec2 uv(f.u.dot(r), f.v.dot(r));
  if (!(s > margin && s < kLength - margin)) return false;
  for (const Vec2& step :
       {Vec2(0, 0), Vec2(margin, 0), Vec2(-margin, 0), Vec2(0, margin), Vec2(0, -margin)})
    if (!test::in_polygon(outline, uv + step)) return false;
  return true;
}

struct Result {
  double removed_volume = 0;
  std::size_t removed = 0, kept_inside = 0;
};

Result run(const test::TempDir& tmp, const std::string& text, const std::vector<Vec2>& outline) {
  test::write_text(tmp / "tunnel.toml", text);
  const std::string joints = (tmp / "joints.h5").string(), blocks = (tmp / "blocks.h5").string(),
                    geom = (tmp / "geom.h5").string();
  for (const auto& [tool, args] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"slice-joints", {(tmp / "tunnel.toml").string(), "-o", joints}},
           {"slice-cut", {joints, "-o", blocks, "--prune"}},
           {"slice-vertices", {blocks, "-o", geom}}}) {
    const auto r = run_tool(tool, args);
    INFO(tool << ": " << r.err);
    REQUIRE(r.exit_code == 0);
  }
  const slice::BlockSystem bs = slice::read_blocks(geom);
  REQUIRE(bs.geometry);
  Result out;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const auto& blk = bs.blocks[b];
    if (blk.flags & slice::kRemoved) {
      out.removed_volume += bs.geometry->volume[b];
      ++out.removed;
    } else {
      // Neither the block's centre nor its centroid inside the opening.
      out.kept_inside += deep_inside(outline, blk.origin, 1e-6) ||
                                 deep_inside(outline, bs.geometry->centroid[b], 1e-6)
                             ? 1
                             : 0;
    }
  }
  return out;
}

}  // namespace

TEST_CASE("a cut tunnel zone removes exactly its prism", "[tools][tunnel]") {
  const auto all = sections();
  const auto k = GENERATE(0, 1);
  const Section& s = all[std::size_t(k)];
  CAPTURE(s.name);
  const std::vector<Vec2> outline =
      std::string(s.name) == "round" ? slice::regular_outline(3, 12) : kHorseshoe;
  const double prism = s.area * kLength;
  test::TempDir tmp;

  const Result cut = run(tmp, scene(s, true), outline);
  CHECK(cut.removed > 0);
  CHECK_THAT(cut.removed_volume, WithinRel(prism, 1e-9));
  CHECK(cut.kept_inside == 0);

  // The opening exports: the kept blocks to VTU and to a YADE script.
  const std::string geom = (tmp / "geom.h5").string();
  for (const std::string format : {"vtu", "yade"}) {
    const std::string out = (tmp / ("tunnel." + format)).string();
    const auto r = run_tool("slice-export", {geom, "--format", format, "-o", out});
    INFO(r.err);
    CHECK(r.exit_code == 0);
    CHECK(test::fs::file_size(out) > 0);
  }

  // Without cut, the rock blocks are not cut along the outline: what is removed is a set of
  // whole rock blocks whose centres are inside, not the prism.
  const Result whole = run(tmp, scene(s, false), outline);
  CHECK(whole.removed > 0);
  CHECK(std::abs(whole.removed_volume - prism) > 1e-3 * prism);
}

TEST_CASE("slice-joints refuses a bad tunnel with its line", "[tools][tunnel][bad-input]") {
  const std::string head = "[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 20] }\n[[zones]]\n";
  test::check_bad_scenes({
      {"sides out of range",
       head + "tunnel = { point = [9, 0, 9], direction = [0, 1, 0], length = 20, radius = 3, "
              "sides = 5000 }\n",
       {":4", "'sides'", "[3, 1000]"}},
      {"outline not star-shaped about the axis",
       head + "tunnel = { point = [9, 0, 9], direction = [0, 1, 0], length = 20, outline = [\n"
              "  [1, 1], [2, 1],\n  [2, 2], [1, 2]] }\n",
       {":5", "not star-shaped about the axis", "visible"}},
  });
}

TEST_CASE("an open cut is a tunnel whose outline is the cut's profile (data/open-cut.toml)",
          "[tools][tunnel]") {
  // docs/scenes.md, "An open cut or bench": the profile (a bench at z = 10 east of x = 25, a face
  // from (25, 10) up to (18.6, 35)) closed above the ground and past the east side, swept along
  // the whole 20 m of the domain. Removed: 20 x the profile's area under the ground (z = 30) and
  // inside x <= 40, a trapezium 20 high between widths 15 and 40 - (25 - 6.4 x 20 / 25).
  test::TempDir tmp;
  const auto geom = test::geometry_of_text(tmp, test::read_bytes(test::data_path("open-cut.toml")));
  const auto bs = slice::read_blocks(geom);
  REQUIRE(bs.geometry);
  const double top_width = 40 - (25 - 6.4 * 20 / 25);
  const double removed_want = 20 * 20 * (15 + top_width) / 2;
  double removed = 0, total = 0;
  std::size_t inside = 0;
  const auto face_x = [](double z) { return 25 - 6.4 * (z - 10) / 25; };  // the face at height z
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const double v = bs.geometry->volume[b];
    total += v;
    if (bs.blocks[b].flags & slice::kRemoved) {
      removed += v;
      continue;
    }
    const Vec3& c = bs.geometry->centroid[b];
    inside += c.z() > 10 + 1e-9 && c.x() > face_x(c.z()) + 1e-9 ? 1 : 0;
  }
  CHECK_THAT(total, WithinRel(40.0 * 20 * 30, 1e-12));
  CHECK_THAT(removed, WithinRel(removed_want, 1e-9));
  CHECK(inside == 0);  // the kept rock ends on the bench and the face
}

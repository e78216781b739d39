// slice-stability's invariants on real files: the same answers when the scene is turned, moved
// or scaled, the same bytes on any number of threads, successive failure (a block freed by
// another's failure fails in the next round, and not when the other holds), and its command line:
// --help, --version, and bad input refused with exit 1, one line and no output. Every scene goes
// through the real tools; each run is read back and checked against the contract's rules
// (tests/support/stability.hpp); the closed forms are in stability_test.cpp.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/pipeline.hpp"
#include "support/stability.hpp"
#include "support/support.hpp"

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::run_tool;
using namespace test::stability;

TEST_CASE("slice-stability answers --help and --version", "[tools][stability]") {
  CHECK(run_tool("slice-stability", {"--help"}).exit_code == 0);
  CHECK_THAT(run_tool("slice-stability", {"--version"}).out, Catch::Contains("rockslice"));
}
TEST_CASE("slice-stability gives the same answers when the scene is turned, moved or scaled",
          "[tools][stability]") {
  // Goodman's roof with cohesion on two sets, once as given and once with an earthquake and a
  // water table. Turned 37 degrees about the vertical (dip directions and the seismic azimuth +
  // 37, domain and zone turned; the directions turned back), moved 1e6 m east and north, and
  // scaled by 1000 (lengths and cohesion: c / (rho g L) and so every FoS stay).
  const std::array<double, 3> cohesion = {1e3, 3e3, 0};
  struct Variant {
    std::string name;
    Frame f;
  };
  const std::vector<Variant> variants = {{"turned 37 degrees", {37, 1, Vec3::Zero()}},
                                         {"moved 1e6 m", {0, 1, Vec3(1e6, 1e6, 0)}},
                                         {"scaled by 1000", {0, 1000, Vec3::Zero()}}};
  test::TempDir tmp;
  const auto geom0 = geometry_of(tmp, goodman_scene(Frame{}, cohesion), "base");
  for (const bool loads : {false, true}) {
    CAPTURE(loads);
    const auto args = [&](const Frame& f) {
      std::vector<std::string> a;
      if (loads)
        a = {"--seismic",         "0.08",          "--seismic-azimuth",
             num(f.azimuth(200)), "--water-table", num(f.scale * 10 + f.shift.z())};
      return a;
    };
    const auto m0 = stability_of(tmp, geom0, Run{args(Frame{}), ""}, "base-stab.h5");
    int moving = 0;
    for (std::size_t b = 0; b < m0.blocks(); ++b) moving += m0.st.mode[b] >= 3 ? 1 : 0;
    CHECK(moving >= 5);
    const double L = m0.bs.joints.length_scale;
    for (const auto& v : variants) {
      CAPTURE(v.name);
      const auto geom = geometry_of(tmp, goodman_scene(v.f, cohesion), "variant");
      const auto m = stability_of(tmp, geom, Run{args(v.f), ""}, "variant-stab.h5");
      REQUIRE(m.blocks() == m0.blocks());
      // Blocks by their centroids: the variant's is the frame's image of the original's.
      std::vector<std::size_t> match(m0.blocks(), m.blocks());
      for (std::size_t b = 0; b < m0.blocks(); ++b) {
        const Vec3 c = v.f.point(m0.centroid(b));
        for (std::size_t k = 0; k < m.blocks(); ++k)
          if ((m.centroid(k) - c).norm() < 1e-6 * v.f.scale * L) match[b] = k;
      }
      // Shifting by t rounds each plane's offset by up to ulp(|t|) (2.3e-10 m here): a block of
      // inradius r is then another by about ulp(|t|) / r of its size, and so may its FoS and,
      // under water or an earthquake, its direction be (64 ulp of margin). Turning and scaling
      // round by ulp(L): 1e-9 holds for every block.
      const double noise = v.f.shift.norm() > 0
                               ? 64 * (std::nextafter(v.f.shift.norm(), kInf) - v.f.shift.norm())
                               : 0.0;
      int mismatched = 0;
      for (std::size_t b = 0; b < m0.blocks(); ++b) {
        const std::size_t k = match[b];
        const double tol = 1e-9 + noise / m0.bs.blocks[b].inradius;
        INFO("block " << b << " (volume " << m0.volume(b) << ", inradius "
                      << m0.bs.blocks[b].inradius << ") -> " << k);
        REQUIRE(k < m.blocks());
        CHECK(m.bs.blocks[k].flags == m0.bs.blocks[b].flags);
        const bool same =
            m.st.mode[k] == m0.st.mode[b] && m.st.removable[k] == m0.st.removable[b] &&
            m.st.generation[k] == m0.st.generation[b] && m.st.planes[k] == m0.st.planes[b];
        INFO("mode " << m0.st.mode[b] << " -> " << m.st.mode[k] << ", fos " << m0.st.fos[b]
                     << " -> " << m.st.fos[k] << ", direction " << m0.st.direction[b].transpose()
                     << " -> " << v.f.back(m.st.direction[k]).transpose());
        CHECK(same);
        if (m0.st.fos[b] == kInf) {
          CHECK(m.st.fos[k] == kInf);
        } else {
          CHECK_THAT(m.st.fos[k], WithinRel(m0.st.fos[b], tol) || WithinAbs(m0.st.fos[b], 1e-12));
        }
        CHECK((v.f.back(m.st.direction[k]) - m0.st.direction[b]).norm() < tol);
        mismatched += same ? 0 : 1;
      }
      CHECK(mismatched == 0);
    }
  }
}

TEST_CASE("slice-stability writes the same bytes on 1 and 2 threads", "[tools][stability]") {
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, goodman_scene(Frame{}, {1e3, 3e3, 0}));
  std::string bytes[2];
  for (int threads = 1; threads <= 2; ++threads) {
    CAPTURE(threads);
    // The same output name for both: the file records its command line (without --threads).
    const auto out = tmp / "stab.h5";
    test::fs::remove(out);
    const auto r = run_tool("slice-stability",
                            {geom, "-o", out.string(), "--seismic", "0.08", "--seismic-azimuth",
                             "200", "--water-table", "10", "--threads", std::to_string(threads)});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    bytes[threads - 1] = test::read_bytes(out);
  }
  CHECK(!bytes[0].empty());
  CHECK(bytes[0] == bytes[1]);
}

TEST_CASE("a block that can move only once another has gone fails in the next round",
          "[tools][stability]") {
  // stack.toml: the front block on the 30-degree bedding slides out at once; the back block, held
  // by it, slides once it has gone. Both on the bedding (joint 0), FoS tan 20 / tan 30 < 1.
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, data_scene("stack.toml"));
  const PlaneBlock pb;  // the same dip: down_dip
  const double fos = tand(20) / tand(30);
  std::size_t front = 0, back = 0;
  {
    const auto m = stability_of(tmp, geom, Run{{"--free-faces", kPlaneFree}, kPlaneFree});
    const auto body = movable_blocks(m);
    REQUIRE(body.size() == 2);
    front = m.centroid(body[0]).x() > 6 ? body[0] : body[1];
    back = m.centroid(body[0]).x() > 6 ? body[1] : body[0];
    REQUIRE(m.centroid(front).x() > 6);
    REQUIRE(m.centroid(back).x() < 6);
    for (const auto& [b, generation] : {std::pair{front, 0}, std::pair{back, 1}}) {
      CAPTURE(b, generation);
      CHECK(m.st.generation[b] == generation);
      CHECK(m.st.mode[b] == 4);
      check_direction(m.st.direction[b], pb.down_dip);
      CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{0, -1});
      CHECK_THAT(m.st.fos[b], WithinRel(fos, 1e-6));
      CHECK(m.st.fos[b] < 1);
    }
    for (std::size_t b = 0; b < m.blocks(); ++b)
      if (!m.movable(b)) CHECK(m.st.generation[b] == -1);
  }
  {  // --fos-target 0.5: the front block holds (0.63 >= 0.5), so the back one is never freed:
     // removable only upwards, against its weight.
    const auto m = stability_of(
        tmp, geom, Run{{"--free-faces", kPlaneFree, "--fos-target", "0.5"}, kPlaneFree, 0.5},
        "target.h5");
    CHECK(m.st.generation[front] == -1);
    CHECK(m.st.mode[front] == 4);
    CHECK_THAT(m.st.fos[front], WithinRel(fos, 1e-6));
    CHECK(m.st.generation[back] == -1);
    CHECK(m.st.mode[back] == 2);
    CHECK(m.st.removable[back] == 1);
  }
}

TEST_CASE("slice-stability refuses bad input with exit 1, one line and no output",
          "[tools][stability]") {
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, plane_scene(30, 0));
  const auto blocks = (tmp / "scene-blocks.h5").string();
  const auto out = (tmp / "stab.h5").string();
  // A 2-D section (kim-persistent.toml) through slice-vertices, as tmp/geom.h5.
  const auto section = test::run_pipeline(tmp, "kim-persistent.toml", test::Stage::geometry);
  struct Case {
    std::string input;
    std::vector<std::string> args, words;  // the words the line must hold: the file, the option
  };
  for (const auto& c : std::vector<Case>{
           {blocks, {}, {"scene-blocks.h5", "geometry"}},  // from slice-cut: no /geometry
           {section, {}, {"geom.h5", "2-D"}},
           {geom, {"--free-faces", "+q"}, {"+q"}},
           {geom, {"--density", "-1"}, {"density"}},
           {geom, {"--seismic", "-0.1"}, {"seismic", "-0.1"}},
           {geom, {"--seismic-azimuth", "nan"}, {"azimuth"}},
           {geom, {"--water-table", "nan"}, {"water"}},
           {geom, {"--max-group", "0"}, {"--max-group"}},
           {geom, {"--max-group", "65"}, {"--max-group", "64"}},
           {geom, {"--max-group", "-3"}, {"--max-group"}}}) {
    std::vector<std::string> args = {c.input, "-o", out};
    args.insert(args.end(), c.args.begin(), c.args.end());
    CAPTURE(args);
    const auto r = run_tool("slice-stability", args);
    test::check_refused(r, "slice-stability", c.words);
    CHECK_FALSE(test::fs::exists(out));
    CHECK_FALSE(test::fs::exists(out + ".partial"));
  }
  // An existing output is left as it was.
  test::write_text(out, "an older file");
  const auto r = run_tool("slice-stability", {geom, "-o", out, "--density", "-1"});
  test::check_refused(r, "slice-stability", {"density"});
  CHECK(test::read_bytes(out) == "an older file");
}

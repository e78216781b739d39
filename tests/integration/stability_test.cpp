// slice-stability on real files against closed forms: a block on a plane (Hoek & Bray's plane
// failure, FoS = (c A + (W cos a - U) tan phi) / (W sin a), with water, a pseudo-static
// earthquake and support), Hoek & Bray's tetrahedral wedge of Itasca's 3DEC "Sliding Wedge"
// verification (planes 40/130 and 60/220), a pyramid that falls from a roof, a block hanging by
// its tension (FoS = t A / W), and Goodman's three sets 30/90, 60/45 and 20/330 over a flat roof
// (only joint pyramid 101 is removable: Brady & Brown, Rock Mechanics for Underground Mining, 3rd
// ed., section 9.2.3, after Goodman 1989), each roof block against an independent
// limit-equilibrium analysis. Every scene goes through the real tools; each run is read back and
// checked against the contract's rules (tests/support/stability.hpp); the invariants (turned,
// moved, scaled, threads, successive failure) and bad input are in stability_invariants_test.cpp.
#include "support/stability.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "slice/h5io.hpp"

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using namespace test::stability;

TEST_CASE("a block on a plane slides down the dip with FoS (c A + W cos a tan phi) / (W sin a)",
          "[tools][stability]") {
  struct Case {
    double phi, cohesion;
    bool cluster;
  };
  // Friction either side of the dip, with and without cohesion; the last as a cluster of two.
  const auto k = GENERATE(Case{20, 0, false}, Case{40, 0, false}, Case{20, 2e4, false},
                          Case{25, 5e3, false}, Case{25, 5e3, true});
  CAPTURE(k.phi, k.cohesion, k.cluster);
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, plane_scene(k.phi, k.cohesion, k.cluster));
  const Run run{{"--free-faces", kPlaneFree}, kPlaneFree};
  const auto m = stability_of(tmp, geom, run);

  // The output is geom.h5 and more: the same blocks, the same geometry.
  const auto g = slice::read_blocks(geom);
  REQUIRE(g.blocks.size() == m.blocks());
  CHECK(g.geometry->volume == m.bs.geometry->volume);
  CHECK(g.geometry->face_area == m.bs.geometry->face_area);
  for (std::size_t b = 0; b < m.blocks(); ++b) {
    CHECK(g.blocks[b].flags == m.bs.blocks[b].flags);
    CHECK(g.blocks[b].faces.size() == m.bs.blocks[b].faces.size());
  }

  const PlaneBlock pb;
  const auto body = movable_blocks(m);  // the block on the plane, or the cluster's two members
  REQUIRE(body.size() == (k.cluster ? 2u : 1u));
  double volume = 0, area = 0;
  for (const auto b : body) {
    volume += m.volume(b);
    area += area_on(m, b, 0);
    for (const auto& t : touches(m, b))
      if (t.joint == 0) check_direction(t.normal, pb.outward, 1e-12);
  }
  CHECK_THAT(volume, WithinRel(pb.volume, 1e-9));
  CHECK_THAT(area, WithinRel(pb.area, 1e-9));
  const double w = kRho * kG * volume, a = pb.a;
  const double fos = (k.cohesion * area + w * std::cos(a) * tand(k.phi)) / (w * std::sin(a));
  CAPTURE(volume, area, w, fos);
  for (const auto b : body) {
    CAPTURE(b);
    CHECK(m.st.mode[b] == 4);
    CHECK(m.st.removable[b] == 1);
    check_direction(m.st.direction[b], pb.down_dip);
    CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{0, -1});
    CHECK_THAT(m.st.fos[b], WithinRel(fos, 1e-6));
    CHECK(m.st.generation[b] == (fos < 1 ? 0 : -1));
  }
  // The fixed rock below: nothing.
  for (std::size_t b = 0; b < m.blocks(); ++b)
    if (!m.movable(b)) CHECK(m.st.mode[b] == 0);
}

TEST_CASE(
    "water, an earthquake, support and the density change the plane's FoS as the closed "
    "forms say",
    "[tools][stability]") {
  const double phi = 40, cohesion = 1e4;
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, plane_scene(phi, cohesion));
  const PlaneBlock pb;
  const double a = pb.a, t = tand(phi);
  struct Case {
    std::string name;
    std::vector<std::string> args;
    double fos;  // 0: computed below from the block's own volume and contact
    Vec3 direction;
  };
  // The block's weight and contact from a dry run.
  const Run dry{{"--free-faces", kPlaneFree}, kPlaneFree};
  const auto m0 = stability_of(tmp, geom, dry, "dry.h5");
  const auto body = movable_blocks(m0);
  REQUIRE(body.size() == 1);
  const std::size_t b = body[0];
  const double v = m0.volume(b), area = area_on(m0, b, 0), w = kRho * kG * v, ca = cohesion * area;
  CHECK_THAT(m0.st.fos[b], WithinRel((ca + w * std::cos(a) * t) / (w * std::sin(a)), 1e-6));
  // The contact's centroid, for the water's pressure.
  double zc = 0;
  for (const auto& x : touches(m0, b))
    if (x.joint == 0) zc = m0.st.contacts[x.row].centroid.z();
  CHECK_THAT(zc, WithinAbs(pb.z_centroid, 1e-9));

  std::vector<Case> cases;
  {  // A water table at the top of the plane: U = rho_w g (z_w - z_c) A on all of it.
    const double u = kRhoWater * kG * (8 - pb.z_centroid) * area;
    cases.push_back({"water table at z = 8",
                     {"--water-table", "8"},
                     (ca + (w * std::cos(a) - u) * t) / (w * std::sin(a)),
                     pb.down_dip});
  }
  {  // Part of it under water: U = rho_w g width h^2 / (2 sin a), h = z_w - z of its lowest edge.
    const double h = 4 - pb.z_low, u = kRhoWater * kG * 4 * h * h / (2 * std::sin(a));
    cases.push_back({"water table at z = 4",
                     {"--water-table", "4"},
                     (ca + (w * std::cos(a) - u) * t) / (w * std::sin(a)),
                     pb.down_dip});
  }
  {  // k W towards the dip direction (east): N = W (cos a - k sin a), S = W (sin a + k cos a).
    const double kk = 0.1;
    cases.push_back(
        {"seismic 0.1 towards 90",
         {"--seismic", "0.1", "--seismic-azimuth", "90"},
         (ca + w * (std::cos(a) - kk * std::sin(a)) * t) / (w * (std::sin(a) + kk * std::cos(a))),
         pb.down_dip});
  }
  {  // k W towards north, along the strike: S = W sqrt(sin^2 a + k^2), turned towards north.
    const double kk = 0.15, s = std::sqrt(std::sin(a) * std::sin(a) + kk * kk);
    cases.push_back({"seismic 0.15 towards 0",
                     {"--seismic", "0.15", "--seismic-azimuth", "0"},
                     (ca + w * std::cos(a) * t) / (w * s),
                     Vec3(std::sin(a) * std::cos(a), kk, -std::sin(a) * std::sin(a)) / s});
  }
  {  // p on the free faces, inwards: the east face pushes west, the top down, the sides cancel.
    const double p = 5e4;
    const double n = w * std::cos(a) + p * (pb.area_east * std::sin(a) + pb.area_top * std::cos(a));
    const double s = w * std::sin(a) + p * (pb.area_top * std::sin(a) - pb.area_east * std::cos(a));
    cases.push_back(
        {"support 5e4 Pa", {"--support-pressure", "5e4"}, (ca + n * t) / s, pb.down_dip});
  }
  {  // A lighter rock: cohesion counts for more.
    const double w2 = 2000 * kG * v;
    cases.push_back({"density 2000",
                     {"--density", "2000"},
                     (ca + w2 * std::cos(a) * t) / (w2 * std::sin(a)),
                     pb.down_dip});
  }
  int i = 0;
  for (const auto& c : cases) {
    CAPTURE(c.name, c.fos);
    Run run{{"--free-faces", kPlaneFree}, kPlaneFree};
    run.args.insert(run.args.end(), c.args.begin(), c.args.end());
    const auto m = stability_of(tmp, geom, run, "case" + std::to_string(i++) + ".h5");
    CHECK(m.st.mode[b] == 4);
    check_direction(m.st.direction[b], c.direction);
    CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{0, -1});
    CHECK_THAT(m.st.fos[b], WithinRel(c.fos, 1e-6));
    CHECK(m.st.generation[b] == (c.fos < 1 ? 0 : -1));
  }
  // The free faces the support pressure acts on, seen from the geometry.
  double east = 0, top = 0;
  for (std::size_t k = 0; k < m0.bs.blocks[b].faces.size(); ++k) {
    const Vec3& n = m0.bs.blocks[b].faces[k].normal;
    if (n.x() > 1 - 1e-12) east = m0.face_area(b, k);
    if (n.z() > 1 - 1e-12) top = m0.face_area(b, k);
  }
  CHECK_THAT(east, WithinRel(pb.area_east, 1e-9));
  CHECK_THAT(top, WithinRel(pb.area_top, 1e-9));
}

TEST_CASE(
    "Hoek & Bray's wedge (3DEC's Sliding Wedge, planes 40/130 and 60/220) slides along "
    "the line of intersection with FoS (c_A A_A + c_B A_B + R_A tan phi_A + R_B tan phi_B) / "
    "(W sin psi)",
    "[tools][stability]") {
  struct Case {
    double phi_a, phi_b, c_a, c_b;
  };
  const auto k = GENERATE(Case{30, 30, 0, 0}, Case{45, 45, 0, 0}, Case{35, 25, 2e4, 1e4});
  CAPTURE(k.phi_a, k.phi_b, k.c_a, k.c_b);
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, wedge_scene(k.phi_a, k.phi_b, k.c_a, k.c_b));
  const std::string free_faces = "-x,+x,-y,+y,+z";
  const auto m = stability_of(tmp, geom, Run{{"--free-faces", free_faces}, free_faces});
  const auto body = movable_blocks(m);
  REQUIRE(body.size() == 1);
  const std::size_t b = body[0];

  // The weight W (0, 0, -1) is carried by normal reactions R_A, R_B on the planes (the wedge's
  // outward normals are -n_A, -n_B) and a force S along the line of intersection t, plunging
  // psi: W (0, 0, -1) = R_A (-n_A) + R_B (-n_B) + S t, S = W sin psi.
  const Vec3 na = upward_normal(40, 130), nb = upward_normal(60, 220);
  Vec3 t = na.cross(nb).normalized();
  if (t.z() > 0) t = -t;
  Eigen::Matrix3d eq;
  eq << -na, -nb, t;
  const Vec3 x = eq.colPivHouseholderQr().solve(Vec3(0, 0, -1));
  REQUIRE(x[0] > 0);
  REQUIRE(x[1] > 0);
  const double psi = std::asin(-t.z()) * 180 / kPi;
  CHECK_THAT(x[2], WithinRel(std::sin(rad(psi)), 1e-12));
  const double area_a = area_on(m, b, 0), area_b = area_on(m, b, 1);
  for (const auto& [j, area] : {std::pair{0, area_a}, std::pair{1, area_b}}) {
    double face = 0;
    for (std::size_t f = 0; f < m.bs.blocks[b].faces.size(); ++f)
      if (m.bs.blocks[b].faces[f].joint == j) face += m.face_area(b, f);
    CHECK_THAT(area, WithinRel(face, 1e-9));  // the rock below covers each face
  }
  const double w = kRho * kG * m.volume(b);
  const double fos =
      (k.c_a * area_a + k.c_b * area_b + w * (x[0] * tand(k.phi_a) + x[1] * tand(k.phi_b))) /
      (w * x[2]);
  CAPTURE(psi, x[0], x[1], area_a, area_b, m.volume(b), fos);
  CHECK(m.st.mode[b] == 5);
  CHECK(m.st.removable[b] == 1);
  check_direction(m.st.direction[b], t);
  CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{0, 1});
  CHECK_THAT(m.st.fos[b], WithinRel(fos, 1e-6));
  CHECK(m.st.generation[b] == (fos < 1 ? 0 : -1));
}

TEST_CASE("a block falls from a roof, from among removed blocks, or hangs by t A >= W",
          "[tools][stability]") {
  SECTION("the pyramid over the opening of roof-pyramid.toml falls with FoS 0") {
    test::TempDir tmp;
    const auto geom = geometry_of(tmp, data_scene("roof-pyramid.toml"));
    const auto m = stability_of(tmp, geom, Run{});
    // The pyramid: base [3, 7]^2 at z = 5, apex 2 tan 60 above; its centroid a quarter up.
    const double h = 2 * std::tan(rad(60));
    std::vector<std::size_t> pyramid;
    for (std::size_t b = 0; b < m.blocks(); ++b)
      if ((m.centroid(b) - Vec3(5, 5, 5 + h / 4)).norm() < 1e-9) pyramid.push_back(b);
    REQUIRE(pyramid.size() == 1);
    const std::size_t b = pyramid[0];
    CHECK_THAT(m.volume(b), WithinRel(16 * h / 3, 1e-9));
    int free = 0, held = 0;
    for (const auto& x : touches(m, b)) (x.free ? free : held) += 1;
    CHECK(free >= 1);  // its base, on the removed blocks of the opening
    CHECK(held == 4);  // its four sides
    CHECK(m.st.mode[b] == 3);
    CHECK(m.st.removable[b] == 1);
    check_direction(m.st.direction[b], Vec3(0, 0, -1));
    CHECK(m.st.fos[b] == 0);
    CHECK(m.st.generation[b] == 0);
  }
  SECTION("the block of island.toml, whose every neighbour is removed, falls") {
    test::TempDir tmp;
    const auto geom = geometry_of(tmp, data_scene("island.toml"));
    const auto m = stability_of(tmp, geom, Run{});
    std::vector<std::size_t> centre;
    for (std::size_t b = 0; b < m.blocks(); ++b)
      if ((m.centroid(b) - Vec3(5, 5, 5)).norm() < 1e-9) centre.push_back(b);
    REQUIRE(centre.size() == 1);
    const std::size_t b = centre[0];
    const auto x = touches(m, b);
    CHECK(x.size() == 6);
    for (const auto& c : x) CHECK(c.free);
    CHECK(m.st.mode[b] == 3);
    CHECK(m.st.removable[b] == 1);
    check_direction(m.st.direction[b], Vec3(0, 0, -1));
    CHECK(m.st.fos[b] == 0);
    CHECK(m.st.generation[b] == 0);
  }
  SECTION("a block hanging by the tension of the joint above it: FoS = t A / W") {
    const double ratio = GENERATE(0.5, 1.6);  // t A / W
    CAPTURE(ratio);
    const double w = kRho * kG * 4 * 4 * 2, area = 16;
    test::TempDir tmp;
    const auto geom = geometry_of(tmp, hanging_scene(ratio * w / area));
    const std::string free_faces = "-x,+x,-y,+y,-z";
    const auto m = stability_of(tmp, geom, Run{{"--free-faces", free_faces}, free_faces});
    const auto body = movable_blocks(m);
    REQUIRE(body.size() == 1);  // the block below; the one above touches the fixed top
    const std::size_t b = body[0];
    CHECK_THAT(m.volume(b), WithinRel(32, 1e-12));
    CHECK(m.st.mode[b] == 3);
    check_direction(m.st.direction[b], Vec3(0, 0, -1));
    CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{-1});
    CHECK_THAT(m.st.fos[b], WithinRel(ratio, 1e-6));
    CHECK(m.st.generation[b] == (ratio < 1 ? 0 : -1));
  }
}

TEST_CASE(
    "over a flat roof only blocks of joint pyramid 101 of Goodman's sets 30/90, 60/45 and "
    "20/330 are removable, and they slide on the 60/45 set",
    "[tools][stability]") {
  // Brady & Brown (Rock Mechanics for Underground Mining, 3rd ed., section 9.2.3, figure 9.8,
  // after Goodman 1989): for these three sets and a horizontal roof, "of the eight JPs, only JP
  // 101 has no intersection with the EP": the blocks removable from the roof lie below joint 1,
  // above joint 2 and below joint 3 (digit 0: the upper half-space of that joint, 1: the lower;
  // their JP 100 is "L1 U2 U3"). The three edges of JP 101 all plunge, so a block of it is finite
  // under the roof; the vertical is not in it (it is in JP 111, whose edges are not all
  // downwards): gravity presses a key block onto its joint-2 face, and it slides on it (mode 4),
  // down the dip of 60/45, FoS tan 35 / tan 60, rather than falling.
  //
  // With regular sets every block above the roof is a cell of the three sets cut by it, and it
  // keeps the cell's highest corner, where its faces below J1, above J2 and below J3 meet: each
  // roof block belongs to JP 101, and is removable when the faces it has beyond those (the cell's
  // opposite ones) leave a direction within JP 101 (a tetrahedron, or a slab between two joints
  // of one set). Each roof block is checked against an independent limit-equilibrium analysis of
  // its faces: in a run where only falling blocks could fail (--fos-target 1e-9), and in one with
  // the default target, where a block that can slide with FoS below 1 fails at once. A block's
  // answer is its first round's where it fails then (generation 0) or where nothing it touches
  // ever fails (its surroundings never change).
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, goodman_scene(Frame{}));
  const auto m = stability_of(tmp, geom, Run{{"--fos-target", "1e-9"}, "", 1e-9}, "slides.h5");
  const auto rounds = stability_of(tmp, geom, Run{});
  const auto& joints = m.bs.joints.joints;
  std::int64_t roof = -1;
  for (std::size_t j = 0; j < joints.size(); ++j)
    if (joints[j].set < 0) roof = std::int64_t(j);
  REQUIRE(roof >= 0);
  const std::array<Vec3, 3> n = {upward_normal(30, 90), upward_normal(60, 45),
                                 upward_normal(20, 330)};
  const std::array<int, 3> jp101 = {-1, +1, -1};  // below J1 (outward +n1), above J2, below J3

  int roof_blocks = 0, compared = 0, movers = 0, key_tetrahedra = 0;
  for (const auto b : movable_blocks(m)) {
    const auto x = touches(m, b);
    const bool exposed = std::any_of(x.begin(), x.end(), [](const Touch& t) { return t.free; });
    const bool roof_only = std::all_of(x.begin(), x.end(), [&](const Touch& t) {
      return !t.free || (t.joint == roof && t.normal.z() < -1 + 1e-12);
    });
    const auto& faces = m.bs.blocks[b].faces;
    const bool on_domain =
        std::any_of(faces.begin(), faces.end(), [](const slice::Face& f) { return f.joint < 0; });
    if (!exposed || !roof_only || on_domain) continue;
    ++roof_blocks;
    CAPTURE(b, m.volume(b), m.centroid(b).transpose());
    // The faces it presses on: all but those wholly on removed blocks.
    std::vector<double> free_area(faces.size(), 0.0);
    for (const auto& t : x)
      if (t.free) free_area[t.face] += t.area;
    std::vector<Bearing> bearing;
    std::array<std::set<int>, 3> sides;  // per set: -1 the block below a joint of it, +1 above
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto& face = faces[f];
      const auto& joint = joints[static_cast<std::size_t>(face.joint)];
      if (joint.set >= 0)
        sides[static_cast<std::size_t>(joint.set)].insert(
            face.normal.dot(joint.plane.normal) > 0 ? -1 : +1);
      if (free_area[f] >= m.face_area(b, f) * (1 - 1e-9)) continue;
      bearing.push_back({face.normal, tand(joint.friction_angle_deg), 0, face.joint});
    }
    // Every roof block has a face on JP 101's side of each set.
    for (std::size_t i = 0; i < 3; ++i) CHECK(sides[i].count(jp101[i]) == 1);

    const auto want = limit_equilibrium(bearing, Vec3(0, 0, -1));
    CHECK(want.found <= 1);
    INFO("expected mode " << want.mode << ", direction " << want.direction.transpose() << ", fos "
                          << want.fos);
    // Whether a run's answer for b is its first round's.
    const auto first_round = [&](const Model& run) {
      if (run.st.generation[b] == 0) return true;
      if (run.st.generation[b] > 0) return false;
      return std::none_of(x.begin(), x.end(), [&](const Touch& t) {
        return t.other >= 0 && run.st.generation[static_cast<std::size_t>(t.other)] >= 0;
      });
    };
    for (const Model* run : {&m, &rounds}) {
      const auto& st = run->st;
      INFO((run == &m ? "--fos-target 1e-9" : "the default target"));
      if (!first_round(*run)) continue;
      ++compared;
      CHECK(st.removable[b] == (want.removable ? 1 : 0));
      CHECK(st.mode[b] == want.mode);
      if (want.mode >= 3) {
        check_direction(st.direction[b], want.direction);
        CHECK(plane_set(st.planes[b]) == want.planes);
        CHECK_THAT(st.fos[b], WithinRel(want.fos, 1e-6));
      }
    }
    // Failing at once: a mode of motion with FoS below 1 (others may fail once a neighbour has
    // gone).
    CHECK((rounds.st.generation[b] == 0) == (want.mode >= 3 && want.fos < 1));
    if (!first_round(m)) continue;
    if (m.st.mode[b] >= 3) {
      ++movers;
      // It moves within JP 101 (closed): away from J1 and J3 below it, from J2 above it.
      const Vec3& d = m.st.direction[b];
      CHECK(d.dot(n[0]) <= 1e-9);
      CHECK(d.dot(n[1]) >= -1e-9);
      CHECK(d.dot(n[2]) <= 1e-9);
      CHECK(d.z() < 0);
      CHECK(m.st.mode[b] != 3);  // the vertical is outside JP 101
    }
    // A key block of JP 101 itself: the tetrahedron of one joint of each set and the roof.
    bool tetrahedron = bearing.size() == 3;
    for (std::size_t i = 0; i < 3; ++i) tetrahedron = tetrahedron && sides[i].size() == 1;
    if (tetrahedron) {
      ++key_tetrahedra;
      std::int64_t j2 = -1;
      for (const auto& f : faces)
        if (f.joint >= 0 && joints[static_cast<std::size_t>(f.joint)].set == 1) j2 = f.joint;
      CHECK(m.st.mode[b] == 4);
      CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{j2, -1});
      check_direction(m.st.direction[b],
                      Vec3(std::cos(rad(60)) * std::sin(rad(45)),
                           std::cos(rad(60)) * std::cos(rad(45)), -std::sin(rad(60))));
      CHECK_THAT(m.st.fos[b], WithinRel(tand(35) / tand(60), 1e-6));
      CHECK(rounds.st.generation[b] == 0);
    }
  }
  CAPTURE(roof_blocks, compared, movers, key_tetrahedra);
  CHECK(roof_blocks >= 10);
  CHECK(compared >= roof_blocks);  // most of them twice
  CHECK(movers >= 1);
  CHECK(key_tetrahedra >= 1);
}

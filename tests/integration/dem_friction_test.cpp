// The YADE export's contact law against closed forms, in Debian's real YADE (yade -n -x): a block
// on a plane made of several fixed blocks holds when tan(phi) > tan(alpha) and slides when below
// (and YADE's volumetric law alone, whose shear force is shared by all contacts, does not hold
// it); the tetrahedral wedge of Itasca's 3DEC "Sliding Wedge" verification (planes 40/130 and
// 60/220) holds or slides across the friction angle where (R_A + R_B) tan(phi) / (W sin(psi)) =
// 1; a block held by cohesion alone, or hanging by tension alone, holds or falls across c A = W
// and t A = W; in a slope of several joint sets only the blocks on a daylighting plane steeper
// than phi move. Every scene goes through the real tools. YADE must be installed (pipelines/setup
// does it): a missing yade fails these tests, it does not skip them.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "slice/contacts.hpp"
#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using test::run_tool;

namespace {

constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * kPi / 180; }

/// joints -> cut + prune -> vertices (tmp/scene.toml, joints.h5, blocks.h5, geom.h5) -> YADE
/// script tmp/model.py of a scene text; returns geom.h5's path.
std::string model_of(const test::TempDir& tmp, const std::string& scene,
                     const std::vector<std::string>& export_args) {
  const std::string geom = test::geometry_of_text(tmp, scene), model = (tmp / "model.py").string();
  std::vector<std::string> args = {geom, "--format", "yade", "-o", model};
  args.insert(args.end(), export_args.begin(), export_args.end());
  const auto e = run_tool("slice-export", args);
  INFO(e.err);
  REQUIRE(e.exit_code == 0);
  return geom;
}

/// Runs model.py for `seconds` in YADE (tests/data/yade_motion.py); the report.
nlohmann::json run_motion(const test::TempDir& tmp, double seconds) {
  const auto model = tmp / "model.py", report = tmp / "motion.json", log = tmp / "yade.log";
  std::ostringstream args;
  args << test::shell_quote(model.string()) << ' ' << test::shell_quote(report.string()) << ' '
       << seconds;
  const int code = test::run_yade(test::test_data_path("yade_motion.py").string(), args.str(), log);
  INFO("yade log (tail): " << test::tail_of(log));
  REQUIRE(code == 0);
  REQUIRE(test::fs::exists(report));
  auto r = nlohmann::json::parse(test::read_bytes(report.string()));
  INFO(r.value("error", std::string()));
  REQUIRE_FALSE(r.contains("error"));
  return r;
}

/// How far each free block moved ([block] -> displacement), blocks in clumps by their clump.
struct Motion {
  std::map<std::size_t, slice::Vec3> of_block;
  std::map<std::size_t, double> speed;  // at the end
};
Motion motion_of(const nlohmann::json& r, const slice::BlockSystem& bs) {
  Motion m;
  for (const auto& [block, body] : r["body_of_block"].items()) {
    const std::size_t b = std::stoul(block);
    if (bs.blocks[b].flags & (slice::kBoundary | slice::kFixed)) continue;
    const auto& d = r["moved"][std::to_string(body.get<long>())];
    for (const auto& x : d) REQUIRE_FALSE(x.is_null());  // no NaN
    m.of_block[b] = slice::Vec3(d[0].get<double>(), d[1].get<double>(), d[2].get<double>());
    const auto& v = r["speed"][std::to_string(body.get<long>())];
    REQUIRE_FALSE(v.is_null());
    m.speed[b] = v.get<double>();
  }
  return m;
}

/// A block on a plane of dip alpha (dipping east) that rests on three fixed blocks: the plane is
/// a rock joint of friction phi; vertical polygon joints below it cut the rock under the plane
/// into three blocks on the base (fixed_faces -z), and cut nothing above it.
std::string plane_scene(double alpha, double phi) {
  std::ostringstream s;
  s << "[scene]\nname = \"plane\"\nseed = 1\n[domain]\nbox = { min = [0, 0, 0], max = [12, 4, 8] "
       "}\n"
    << "[options]\norder = \"as-given\"\nfixed_faces = [\"-z\"]\n"
    << "[[joints]]\ndip = " << alpha << "\ndip_direction = 90\npoint = [6, 2, 4]\n"
    << "friction_angle = " << phi << "\nstage = 1\n";
  for (const double x : {4.0, 8.0})
    s << "[[joints]]\ndip = 90\ndip_direction = 90\npoint = [" << x << ", 2, 1.2]\n"
      << "polygon_uv = [[-1, -1], [1, -1], [1, 1], [-1, 1]]\nfriction_angle = " << phi
      << "\nstage = 2\n";
  return s.str();
}

}  // namespace

TEST_CASE(
    "a block on a plane of several fixed blocks holds above tan(phi) = tan(alpha) and "
    "slides below",
    "[tools][export][yade][physics]") {
  const double alpha = 30;
  struct Case {
    double phi;
    std::string law;
    bool slides;
  };
  // The volumetric law alone lets the block on three contacts creep down even at phi = 40.
  const auto c = GENERATE(Case{40, "mohr-coulomb", false}, Case{34, "mohr-coulomb", false},
                          Case{26, "mohr-coulomb", true}, Case{20, "mohr-coulomb", true},
                          Case{40, "volumetric", true});
  CAPTURE(c.phi, c.law);
  test::TempDir tmp;
  const auto geom = model_of(tmp, plane_scene(alpha, c.phi), {"--yade-law", c.law});
  const auto bs = slice::read_blocks(geom);
  const auto r = run_motion(tmp, 1.0);
  const auto m = motion_of(r, bs);
  REQUIRE(m.of_block.size() == 1);  // the block on the plane; the three under it are fixed
  if (c.law == "mohr-coulomb") CHECK(r["contacts"].get<int>() >= 3);
  const slice::Vec3 down(std::cos(rad(alpha)), 0, -std::sin(rad(alpha)));
  const slice::Vec3 d = m.of_block.begin()->second;
  const double speed = m.speed.begin()->second;
  // Sliding from rest for 1 s: a = g (sin(alpha) - cos(alpha) tan(phi)), less YADE's damping
  // (NewtonIntegrator takes 0.3 of each force component against the motion: a x 0.7).
  const double a = 9.81 * (std::sin(rad(alpha)) - std::cos(rad(alpha)) * std::tan(rad(c.phi)));
  INFO("moved " << d.transpose() << " m; down the dip " << d.dot(down) << " m; speed " << speed
                << " m/s; closed form " << 0.5 * 0.7 * a << " m");
  if (c.law == "volumetric") {
    CHECK(d.dot(down) > 0.05);  // the flaw: phi = 40 > alpha, and the block goes
  } else if (c.slides) {
    CHECK(d.dot(down) > 0.9 * d.norm());
    CHECK_THAT(d.dot(down), Catch::Matchers::WithinRel(0.5 * 0.7 * a, 0.2));
  } else {
    CHECK(d.norm() < 0.01);  // the first touch settles it by millimetres, then it stays
    CHECK(speed < 1e-3);
  }
}

namespace {

/// Itasca's 3DEC "Sliding Wedge" verification: planes A (40/130) and B (60/220) through one
/// point, both boundary joints keeping what lies below them; the wedge above both is the one
/// block that moves.
std::string wedge_scene(double phi) {
  std::ostringstream s;
  s << "[scene]\nname = \"wedge\"\nseed = 1\n[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 20] "
       "}\n"
    << "[options]\norder = \"as-given\"\n";
  int stage = 1;
  for (const auto& [dip, dd] : {std::pair{40, 130}, std::pair{60, 220}})
    s << "[[joints]]\ndip = " << dip << "\ndip_direction = " << dd
      << "\npoint = [10, 10, 12]\nkind = \"boundary\"\nkeep = \"below\"\nfriction_angle = " << phi
      << "\nstage = " << stage++ << "\n";
  return s.str();
}

slice::Vec3 upward_normal(double dip, double dd) {
  return {std::sin(rad(dip)) * std::sin(rad(dd)), std::sin(rad(dip)) * std::cos(rad(dd)),
          std::cos(rad(dip))};
}

/// Hoek & Bray's wedge on two planes of upward normals na, nb: the weight w = W (0, 0, -1) is
/// carried by the normal reactions R_A, R_B and a force s along the line of intersection t
/// (downward): w = -R_A n_A - R_B n_B + s t, s = W sin(psi); the critical friction angle
/// [deg], tan(phi_c) = s / (R_A + R_B), and t.
std::pair<double, slice::Vec3> wedge_limit(const slice::Vec3& na, const slice::Vec3& nb) {
  slice::Vec3 t = na.cross(nb).normalized();
  if (t.z() > 0) t = -t;
  Eigen::Matrix3d m;
  m << -na, -nb, t;
  const slice::Vec3 x = m.colPivHouseholderQr().solve(slice::Vec3(0, 0, -1));
  REQUIRE(x[0] > 0);  // both planes carry the wedge: it slides on both, along t
  REQUIRE(x[1] > 0);
  return {std::atan(x[2] / (x[0] + x[1])) * 180 / kPi, t};
}

}  // namespace

TEST_CASE(
    "the wedge of 3DEC's Sliding Wedge verification holds or slides across "
    "(R_A + R_B) tan(phi) = W sin(psi)",
    "[tools][export][yade][physics]") {
  const auto [phi_c, t] = wedge_limit(upward_normal(40, 130), upward_normal(60, 220));
  CAPTURE(phi_c, t.transpose());
  struct Case {
    double dphi;
    std::string law;
    bool slides;
  };
  const auto c = GENERATE(Case{8, "mohr-coulomb", false}, Case{3, "mohr-coulomb", false},
                          Case{-3, "mohr-coulomb", true}, Case{-8, "mohr-coulomb", true},
                          Case{8, "volumetric", true});
  const double phi = phi_c + c.dphi;
  CAPTURE(phi, c.law);
  test::TempDir tmp;
  const auto geom = model_of(tmp, wedge_scene(phi), {"--yade-law", c.law});
  const auto bs = slice::read_blocks(geom);
  const auto r = run_motion(tmp, 1.0);
  const auto mo = motion_of(r, bs);
  REQUIRE(mo.of_block.size() == 1);  // the wedge; the rock below either plane is boundary
  const slice::Vec3 d = mo.of_block.begin()->second;
  INFO("moved " << d.transpose() << " m; along the line " << d.dot(t) << " m");
  const double speed = mo.speed.begin()->second;
  INFO("speed " << speed << " m/s");
  if (c.law == "volumetric") {
    CHECK(d.dot(t) > 0.05);  // the flaw: above phi_c, and the wedge goes
  } else if (c.slides) {
    CHECK(d.dot(t) > 0.05);
    CHECK(d.dot(t) > 0.95 * d.norm());  // along the line of intersection
  } else {
    CHECK(d.norm() < 0.01);
    CHECK(speed < 1e-3);
  }
}

TEST_CASE(
    "a block held by cohesion alone, or hanging by tension alone, holds or falls across "
    "c A = W sin(alpha) and t A = W",
    "[tools][export][yade][physics]") {
  const double rho = 2650, g = 9.81;
  SECTION("cohesion: the block on the plane with no friction") {
    const double alpha = 30;
    const double ratio = GENERATE(1.6, 0.5);  // c A / (W sin(alpha))
    CAPTURE(ratio);
    // Weight and contact area of the block on the plane, from a first model.
    test::TempDir probe;
    const auto bs0 = slice::read_blocks(model_of(probe, plane_scene(alpha, 0), {}));
    double w = 0;
    for (std::size_t b = 0; b < bs0.blocks.size(); ++b)
      if (!(bs0.blocks[b].flags & (slice::kBoundary | slice::kFixed)))
        w = rho * g * bs0.geometry->volume[b];
    double area = 0;
    for (const auto& c : slice::find_contacts(bs0)) area += c.area;
    REQUIRE(w > 0);
    REQUIRE(area > 0);
    const double cohesion = ratio * w * std::sin(rad(alpha)) / area;
    std::string scene = plane_scene(alpha, 0);
    for (std::size_t at = 0; (at = scene.find("friction_angle = 0\n", at)) != std::string::npos;)
      scene.insert(at += 19, "cohesion = " + std::to_string(cohesion) + "\n");
    test::TempDir tmp;
    const auto bs = slice::read_blocks(model_of(tmp, scene, {}));
    const auto r = run_motion(tmp, 1.0);
    const auto m = motion_of(r, bs);
    REQUIRE(m.of_block.size() == 1);
    const double d = m.of_block.begin()->second.norm();
    INFO("moved " << d << " m; bonds left " << r["bonds_left"]);
    if (ratio > 1) {
      CHECK(d < 0.005);
      CHECK(r["bonds_left"].get<int>() == 3);
    } else {
      CHECK(d > 0.1);
      CHECK(r["bonds_left"].get<int>() == 0);
    }
  }
  SECTION("tension: a block hanging from a fixed block above it") {
    const double ratio = GENERATE(1.6, 0.5);  // t A / W
    CAPTURE(ratio);
    const double area = 16, w = rho * g * 4 * 4 * 2;
    std::ostringstream s;
    s << "[scene]\nname = \"hanging\"\nseed = 1\n[domain]\nbox = { min = [0, 0, 0], max = [4, 4, "
         "4] "
         "}\n[options]\nfixed_faces = [\"+z\"]\n[[joints]]\ndip = 0\ndip_direction = 0\npoint = "
         "[2, 2, 2]\ntension = "
      << ratio * w / area << "\n";
    test::TempDir tmp;
    const auto bs = slice::read_blocks(model_of(tmp, s.str(), {}));
    const auto r = run_motion(tmp, 1.0);
    const auto m = motion_of(r, bs);
    REQUIRE(m.of_block.size() == 1);
    const double dz = m.of_block.begin()->second.z();
    INFO("moved " << dz << " m up; bonds left " << r["bonds_left"]);
    if (ratio > 1) {
      CHECK(std::abs(dz) < 0.001);  // W / (kn A) = 0.1 mm
      CHECK(r["bonds_left"].get<int>() == 1);
    } else {
      // The bond holds while the model settles (BOND_SETTLE, 0.26 s here), then breaks: the
      // block falls for the rest of the second.
      CHECK(dz < -0.5);
      CHECK(r["bonds_left"].get<int>() == 0);
    }
  }
}

namespace {

/// A slope of several joint sets: two planes dipping east at 35 and 20 degrees daylight in the
/// free east face (x = 20), vertical joints across the slope (x = 12, 16) and along it (y = 4)
/// release the blocks; the back (-x) and the base (-z) are held. Every joint has friction phi.
std::string slope_scene(double phi) {
  std::ostringstream s;
  s << "[scene]\nname = \"daylighting\"\nseed = 1\n[domain]\n"
    << "box = { min = [0, 0, 0], max = [20, 8, 16] }\n[options]\norder = \"as-given\"\n"
    << "fixed_faces = [\"-x\", \"-z\"]\n";
  const auto joint = [&](double dip, double dd, slice::Vec3 p) {
    s << "[[joints]]\ndip = " << dip << "\ndip_direction = " << dd << "\npoint = [" << p.x() << ", "
      << p.y() << ", " << p.z() << "]\nfriction_angle = " << phi << "\n";
  };
  joint(35, 90, {20, 4, 8});
  joint(20, 90, {20, 4, 2});
  joint(90, 90, {12, 4, 8});
  joint(90, 90, {16, 4, 8});
  joint(90, 0, {10, 4, 8});
  return s.str();
}

}  // namespace

TEST_CASE(
    "in a slope of several joint sets only the blocks on a daylighting plane steeper than "
    "phi move",
    "[tools][export][yade][physics]") {
  // With --yade-law volumetric every free block moves at phi = 28 and at 40 (seen): this test
  // fails on YADE's law alone.
  const double phi = GENERATE(28.0, 40.0);
  CAPTURE(phi);
  test::TempDir tmp;
  const auto bs = slice::read_blocks(model_of(tmp, slope_scene(phi), {}));
  const auto r = run_motion(tmp, 1.0);
  const auto m = motion_of(r, bs);
  std::size_t steep = 0, moved = 0;
  for (const auto& [b, d] : m.of_block) {
    // The block's base: the face whose outward normal points most downward, and its joint.
    double lowest = 1;
    std::int64_t base = -1;
    for (const auto& f : bs.blocks[b].faces)
      if (f.normal.z() < lowest) lowest = f.normal.z(), base = f.joint;
    REQUIRE(base >= 0);
    const double dip = bs.joints.joints[std::size_t(base)].dip_deg;
    INFO("block " << b << " on a plane of dip " << dip << " (volume " << bs.geometry->volume[b]
                  << ") moved " << d.norm() << " m");
    steep += dip > 30 ? 1 : 0;
    moved += d.norm() > 0.1 ? 1 : 0;
    if (dip > phi) {  // the closed form: a daylighting plane steeper than phi
      // ... slid from rest for 1 s at g (sin - cos tan(phi)), x 0.7 for YADE's damping
      const double a = 9.81 * (std::sin(rad(dip)) - std::cos(rad(dip)) * std::tan(rad(phi)));
      CHECK_THAT(d.norm(), Catch::Matchers::WithinRel(0.5 * 0.7 * a, 0.2));
    } else {
      CHECK(d.norm() < 0.01);
    }
  }
  CHECK(steep >= 4);  // the test must see blocks on the steep plane, and others
  CHECK(m.of_block.size() > steep);
  if (phi > 35) CHECK(moved == 0);
}

namespace {

/// The free block's row of a PotentialBlock script (--format yade-potential-blocks): its
/// friction angle [deg] and its planes' unit outward normals. Exactly one block is free.
std::pair<double, std::vector<slice::Vec3>> free_pb_block(const std::string& model) {
  std::ifstream in(model);
  std::string line;
  bool in_blocks = false;
  std::vector<std::pair<double, std::vector<slice::Vec3>>> free;
  while (std::getline(in, line)) {
    if (line == "BLOCKS = [") {
      in_blocks = true;
    } else if (in_blocks && line == "]") {
      break;
    } else if (in_blocks) {
      // (block, fixed, phi, cluster, volume, inradius, R, (cx, cy, cz), ((a, b, c, d), ...))
      const auto v = test::numbers(line);
      REQUIRE(v.size() >= 10 + 4 * 4);
      if (v[1] != 0) continue;
      std::vector<slice::Vec3> normals;
      for (std::size_t k = 10; k + 3 < v.size(); k += 4)
        normals.emplace_back(v[k], v[k + 1], v[k + 2]);
      free.emplace_back(v[2], normals);
    }
  }
  REQUIRE(free.size() == 1);
  return free[0];
}

/// The plane among `normals` whose outward normal is -n (the block lies on n's side).
bool has_plane(const std::vector<slice::Vec3>& normals, const slice::Vec3& n) {
  for (const auto& m : normals)
    if (m.dot(-n) > 1 - 1e-9) return true;
  return false;
}

}  // namespace

TEST_CASE(
    "the PotentialBlock export's parameters give the plane's and the wedge's closed-form "
    "answers",
    "[tools][export][yade][physics]") {
  // Debian's YADE cannot run PotentialBlock bodies: the script's parameters are checked instead.
  // The free block has the sliding planes among its faces and the joints' friction angle, and
  // limit equilibrium on those gives the answer the Polyhedra model gave in YADE above.
  SECTION("the block on the plane") {
    const double alpha = 30, phi = GENERATE(40.0, 34.0, 26.0, 20.0);
    CAPTURE(phi);
    test::TempDir tmp;
    const auto geom = model_of(tmp, plane_scene(alpha, phi), {});
    const std::string pb = (tmp / "pb.py").string();
    REQUIRE(
        run_tool("slice-export", {geom, "--format", "yade-potential-blocks", "-o", pb}).exit_code ==
        0);
    const auto [phi_pb, normals] = free_pb_block(pb);
    CHECK(phi_pb == phi);
    REQUIRE(has_plane(normals, upward_normal(alpha, 90)));
    CHECK((std::tan(rad(phi_pb)) < std::tan(rad(alpha))) == (phi < alpha));
  }
  SECTION("the wedge") {
    const slice::Vec3 na = upward_normal(40, 130), nb = upward_normal(60, 220);
    const double phi_c = wedge_limit(na, nb).first;
    const double dphi = GENERATE(8.0, 3.0, -3.0, -8.0);
    CAPTURE(dphi);
    test::TempDir tmp;
    const auto geom = model_of(tmp, wedge_scene(phi_c + dphi), {});
    const std::string pb = (tmp / "pb.py").string();
    REQUIRE(
        run_tool("slice-export", {geom, "--format", "yade-potential-blocks", "-o", pb}).exit_code ==
        0);
    const auto [phi_pb, normals] = free_pb_block(pb);
    // The scene's angle (written with 6 digits), the joints' in the file.
    CHECK(phi_pb == slice::read_blocks(geom).joints.joints.at(0).friction_angle_deg);
    REQUIRE(has_plane(normals, na));
    REQUIRE(has_plane(normals, nb));
    CHECK((phi_pb < phi_c) == (dphi < 0));
  }
}

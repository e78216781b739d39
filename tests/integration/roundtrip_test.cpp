// Scene -> joints.h5 -> reader gives back exactly the scene's joints.
#include <catch2/catch.hpp>

#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "support/support.hpp"

namespace {

void check_planes_equal(const std::vector<slice::Plane>& a, const std::vector<slice::Plane>& b) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].normal == b[i].normal);
    CHECK(a[i].d == b[i].d);
  }
}

void check_equal(const slice::JointSystem& a, const slice::JointSystem& b) {
  CHECK(a.name == b.name);
  CHECK(a.seed == b.seed);
  CHECK(a.length_scale == b.length_scale);
  check_planes_equal(a.domain.planes, b.domain.planes);
  CHECK(a.options.order == b.options.order);
  CHECK(a.options.min_inscribed_diameter == b.options.min_inscribed_diameter);
  CHECK(a.options.max_aspect_ratio == b.options.max_aspect_ratio);
  CHECK(a.options.tolerance == b.options.tolerance);
  REQUIRE(a.joints.size() == b.joints.size());
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    CAPTURE(i);
    const auto &x = a.joints[i], &y = b.joints[i];
    CHECK(x.plane.normal == y.plane.normal);
    CHECK(x.plane.d == y.plane.d);
    CHECK(x.centre == y.centre);
    CHECK(x.dip_deg == y.dip_deg);
    CHECK(x.dip_direction_deg == y.dip_direction_deg);
    CHECK(x.kind == y.kind);
    CHECK(x.set == y.set);
    CHECK(x.friction_angle_deg == y.friction_angle_deg);
    CHECK(x.cohesion == y.cohesion);
    CHECK(x.boundary_side == y.boundary_side);
    CHECK(x.polygon_uv == y.polygon_uv);
  }
  REQUIRE(a.sets.size() == b.sets.size());
  for (std::size_t i = 0; i < a.sets.size(); ++i) {
    CHECK(a.sets[i].name == b.sets[i].name);
    CHECK(a.sets[i].dip_deg == b.sets[i].dip_deg);
    CHECK(a.sets[i].dip_direction_deg == b.sets[i].dip_direction_deg);
    CHECK(a.sets[i].spacing == b.sets[i].spacing);
    CHECK(a.sets[i].offset == b.sets[i].offset);
    CHECK(a.sets[i].kind == b.sets[i].kind);
    CHECK(a.sets[i].joint_count == b.sets[i].joint_count);
    const auto &x = a.sets[i], &y = b.sets[i];
    CHECK(x.intensity == y.intensity);
    CHECK(x.fisher_kappa == y.fisher_kappa);
    CHECK(x.density == y.density);
    CHECK(x.count == y.count);
    CHECK(x.p32 == y.p32);
    CHECK(x.p10 == y.p10);
    CHECK(x.scanline_given == y.scanline_given);
    CHECK(x.scanline_from == y.scanline_from);
    CHECK(x.scanline_to == y.scanline_to);
    CHECK(x.size.distribution == y.size.distribution);
    CHECK(x.size.value == y.size.value);
    CHECK(x.size.mean == y.size.mean);
    CHECK(x.size.sd == y.size.sd);
    CHECK(x.size.exponent == y.size.exponent);
    CHECK(x.size.min == y.size.min);
    CHECK(x.size.max == y.size.max);
    CHECK(x.shape == y.shape);
    CHECK(x.aspect == y.aspect);
    CHECK(x.sides == y.sides);
    CHECK(x.fit == y.fit);
    CHECK(x.rotation_fixed == y.rotation_fixed);
    CHECK(x.rotation_deg == y.rotation_deg);
    CHECK(x.stream_seed == y.stream_seed);
    CHECK(x.enlargement == y.enlargement);
    CHECK(x.candidates == y.candidates);
    CHECK(x.achieved_p32 == y.achieved_p32);
    CHECK(x.achieved_p10 == y.achieved_p10);
  }
  REQUIRE(a.zones.size() == b.zones.size());
  for (std::size_t i = 0; i < a.zones.size(); ++i)
    check_planes_equal(a.zones[i].planes, b.zones[i].planes);
}

}  // namespace

TEST_CASE("scene -> joints.h5 -> reader round trip is exact for every example", "[roundtrip]") {
  const auto name = GENERATE("cube-3sets.toml", "table3-persistent.toml", "rock-slope.toml",
                             "table3-lognormal.toml", "genesis-limestone.toml");
  CAPTURE(name);
  test::TempDir tmp;
  const auto js = slice::generate_joints(slice::load_scene(test::data_path(name)));
  slice::Provenance prov{"test", "0", "test", name, "0"};
  slice::write_joints(tmp / "j.h5", js, prov);
  check_equal(js, slice::read_joints(tmp / "j.h5"));
  const auto h = slice::read_header(tmp / "j.h5");
  CHECK(h.kind == slice::FileKind::joints);
  CHECK(h.provenance.tool == "test");
}

TEST_CASE("blocks.h5 carries the joint system unchanged", "[roundtrip]") {
  test::TempDir tmp;
  slice::BlockSystem bs;
  bs.joints = slice::generate_joints(slice::load_scene(test::data_path("rock-slope.toml")));
  slice::Block b;
  b.origin = {1, 2, 3};
  b.faces = {{slice::Vec3::UnitX(), 0.5, -1}, {-slice::Vec3::UnitX(), 0.5, 0}};
  bs.blocks = {b};
  slice::write_blocks(tmp / "b.h5", bs, {"test", "0", "test", "x", "0"});
  const auto back = slice::read_blocks(tmp / "b.h5");
  check_equal(bs.joints, back.joints);
  REQUIRE(back.blocks.size() == 1);
  CHECK(back.blocks[0].origin == b.origin);
  CHECK(back.blocks[0].faces.size() == 2);
}

// Scene -> joints.h5 -> reader gives back exactly the scene's joints.
#include <catch2/catch.hpp>

#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "support/compare.hpp"
#include "support/support.hpp"

TEST_CASE("scene -> joints.h5 -> reader round trip is exact for every example", "[roundtrip]") {
  const auto name = GENERATE("cube-3sets.toml", "table3-persistent.toml", "rock-slope.toml",
                             "table3-lognormal.toml", "genesis-limestone.toml");
  CAPTURE(name);
  test::TempDir tmp;
  const auto js = slice::generate_joints(slice::load_scene(test::data_path(name)));
  slice::Provenance prov{"test", "0", "test", name, "0"};
  slice::write_joints(tmp / "j.h5", js, prov);
  test::check_same(js, slice::read_joints(tmp / "j.h5"));
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
  // A domain face and a face on joint 0 (a face that names a joint lies on its plane).
  const slice::Plane j0 = slice::to_local(bs.joints.joints[0].plane, b.origin);
  b.faces = {{slice::Vec3::UnitX(), 0.5, -1}, {-j0.normal, -j0.d, 0}};
  bs.blocks = {b};
  slice::write_blocks(tmp / "b.h5", bs, {"test", "0", "test", "x", "0"});
  const auto back = slice::read_blocks(tmp / "b.h5");
  test::check_same(bs.joints, back.joints);
  REQUIRE(back.blocks.size() == 1);
  CHECK(back.blocks[0].origin == b.origin);
  CHECK(back.blocks[0].faces.size() == 2);
}

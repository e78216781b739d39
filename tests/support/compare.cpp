#include "support/compare.hpp"

#include <catch2/catch.hpp>

namespace test {

void check_same(const slice::Plane& a, const slice::Plane& b) {
  CHECK(a.normal == b.normal);
  CHECK(a.d == b.d);
}

void check_same(const slice::Region& a, const slice::Region& b) {
  REQUIRE(a.planes.size() == b.planes.size());
  for (std::size_t i = 0; i < a.planes.size(); ++i) check_same(a.planes[i], b.planes[i]);
}

void check_same(const slice::JointSystem& a, const slice::JointSystem& b) {
  CHECK(a.name == b.name);
  CHECK(a.seed == b.seed);
  check_same(a.domain, b.domain);
  CHECK(a.length_scale == b.length_scale);
  CHECK(a.options.order == b.options.order);
  CHECK(a.options.min_inscribed_diameter == b.options.min_inscribed_diameter);
  CHECK(a.options.max_aspect_ratio == b.options.max_aspect_ratio);
  CHECK(a.options.tolerance == b.options.tolerance);
  CHECK(a.options.max_blocks == b.options.max_blocks);
  CHECK(a.options.fixed_faces == b.options.fixed_faces);
  REQUIRE(a.joints.size() == b.joints.size());
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    CAPTURE(i);
    const auto& x = a.joints[i];
    const auto& y = b.joints[i];
    check_same(x.plane, y.plane);
    CHECK(x.centre == y.centre);
    CHECK(x.dip_deg == y.dip_deg);
    CHECK(x.dip_direction_deg == y.dip_direction_deg);
    CHECK(x.kind == y.kind);
    CHECK(x.set == y.set);
    CHECK(x.friction_angle_deg == y.friction_angle_deg);
    CHECK(x.cohesion == y.cohesion);
    CHECK(x.boundary_side == y.boundary_side);
    CHECK(x.limits == y.limits);
    CHECK(x.polygon_uv == y.polygon_uv);
  }
  REQUIRE(a.sets.size() == b.sets.size());
  for (std::size_t i = 0; i < a.sets.size(); ++i) {
    CAPTURE(i);
    const auto& x = a.sets[i];
    const auto& y = b.sets[i];
    CHECK(x.name == y.name);
    CHECK(x.dip_deg == y.dip_deg);
    CHECK(x.dip_direction_deg == y.dip_direction_deg);
    CHECK(x.spacing == y.spacing);
    CHECK(x.offset == y.offset);
    CHECK(x.friction_angle_deg == y.friction_angle_deg);
    CHECK(x.cohesion == y.cohesion);
    CHECK(x.kind == y.kind);
    CHECK(x.boundary_side == y.boundary_side);
    CHECK(x.limits == y.limits);
    CHECK(x.joint_count == y.joint_count);
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
  for (std::size_t i = 0; i < a.zones.size(); ++i) check_same(a.zones[i], b.zones[i]);
}

void check_same(const slice::BlockSystem& a, const slice::BlockSystem& b) {
  check_same(a.joints, b.joints);
  CHECK(a.pruned == b.pruned);
  REQUIRE(a.blocks.size() == b.blocks.size());
  for (std::size_t i = 0; i < a.blocks.size(); ++i) {
    CAPTURE(i);
    const auto& x = a.blocks[i];
    const auto& y = b.blocks[i];
    CHECK(x.origin == y.origin);
    REQUIRE(x.faces.size() == y.faces.size());
    for (std::size_t k = 0; k < x.faces.size(); ++k) {
      CHECK(x.faces[k].normal == y.faces[k].normal);
      CHECK(x.faces[k].d == y.faces[k].d);
      CHECK(x.faces[k].joint == y.faces[k].joint);
    }
    CHECK(x.inradius == y.inradius);
    CHECK(x.bsphere == y.bsphere);
    CHECK(x.flags == y.flags);
    CHECK(x.cluster == y.cluster);
  }
}

}  // namespace test

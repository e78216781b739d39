// libFuzzer target: the scene parser and the joint generator (slice-joints without the file
// output). Any input is text that slice::parse_scene reads; if it parses, slice::generate_joints
// expands its sets. slice::Error (bad input, exit 1 in the tools) is the expected answer to most
// inputs; any other exception, a crash, a sanitizer report, a timeout or running out of memory
// is a finding.
//
// Work is bounded the way a user bounds it, with the scene's own limits turned down: a
// stochastic set may draw at most kMaxJoints joints (max_joints, default 1e7) and a regular set
// may have at most kMaxPlanes planes (the generator allows 1e6). Scenes past these are valid and
// merely big; their run time is the mutation harness's business (tests/fuzz/mutate_scenes.py),
// not the fuzzer's, which would otherwise spend its time drawing joints.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"

namespace {

constexpr std::int64_t kMaxJoints = 20'000;
constexpr double kMaxPlanes = 20'000;

// Planes a regular set has across the domain (its extent along the normal over the spacing),
// summed over the regular sets; the domain is bounded and has vertices once the scene parsed.
double regular_planes(const slice::Scene& scene) {
  const auto info = slice::analyse_polytope(scene.domain.planes, 0);
  double planes = 0;
  for (const slice::JointSetSpec& s : scene.sets) {
    if (s.intensity != slice::SetIntensity::spacing || !(s.spacing > 0)) continue;
    const slice::Vec3 n = slice::normal_from_dip(s.dip_deg, s.dip_direction_deg);
    double lo = 0, hi = 0;
    for (std::size_t i = 0; i < info.vertices.size(); ++i) {
      const double x = n.dot(info.vertices[i]);
      lo = i == 0 ? x : std::min(lo, x);
      hi = i == 0 ? x : std::max(hi, x);
    }
    planes += (hi - lo) / s.spacing;
  }
  return planes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    slice::Scene scene = slice::parse_scene(text, "fuzz.toml");
    scene.max_joints = std::min(scene.max_joints, kMaxJoints);
    if (!(regular_planes(scene) <= kMaxPlanes)) return 0;
    const slice::JointSystem js = slice::generate_joints(scene);
    (void)js;
  } catch (const slice::Error&) {
    // Refused with a message: the promised answer to bad input.
  }
  return 0;
}

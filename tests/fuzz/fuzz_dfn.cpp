// libFuzzer targets: the DFN readers of [[dfn]] (dfn.hpp, docs/dfn.md). One source, two
// targets, by the file name the input is given (SLICE_FUZZ_DFN_EXT):
//   fuzz_fab  the input as "net.fab": the FAB reader (FRACTURE and TESSFRACTURE);
//   fuzz_csv  the input as "net.csv": the CSV reader of discs.
// As slice-joints reads it: a fixed scene (a 10 m box, one [[dfn]] entry naming the input)
// through slice::load_scene, which reads the file and makes each fracture a joint (plane fit,
// convex outline, the tiling of a tessellated fracture, a disc's polygon). slice::Error (bad
// input, exit 1 in the tools) is the expected answer; any other exception, a crash, a sanitizer
// report, a timeout or running out of memory is a finding, and so is a scene that is accepted
// but breaks what scene.hpp promises of a joint: a unit, finite normal, a finite centre, a
// polygon of at least 3 finite corners, convex and counter-clockwise, and a set name that is
// UTF-8 text without control characters (what the outputs and Python take).
// Each input goes to the reader itself first (slice::read_fab, slice::read_dfn_csv, called as
// the scene's [[dfn]] entry calls it: the same file, the default CSV options, the file's stem as
// the set name), and only a file the reader accepts goes on through load_scene. The reader is
// where most inputs end, refused, and the scene around it (its TOML, the domain's analysis) cost
// most of each run: reading a refused file a second time inside load_scene could only refuse it
// again. So each input meets the same checks as before, at several times the runs per second.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "fuzz_input.hpp"
#include "slice/dfn.hpp"
#include "slice/error.hpp"
#include "slice/scene.hpp"
#include "slice/utf8.hpp"

#ifndef SLICE_FUZZ_DFN_EXT
#error "SLICE_FUZZ_DFN_EXT (\".fab\" or \".csv\") names the reader"
#endif

namespace {

const char* const kTarget = "fuzz_dfn (" SLICE_FUZZ_DFN_EXT ")";

std::filesystem::path& scene_path() {
  static std::filesystem::path path;
  return path;
}

void remove_scene() {
  std::error_code ec;
  std::filesystem::remove(scene_path(), ec);
}

void check_name(const std::string& name) {
  for (std::size_t i = 0; i < name.size();) {
    const auto [c, len] = slice::decode_utf8(name, i);
    if (len == 0 || c < 0x20 || c == 0x7f)
      fuzz::finding(kTarget, "a set name that is no UTF-8 text or holds a control character");
    i += len;
  }
}

void check_joint(const slice::Joint& j) {
  if (!j.plane.normal.allFinite() || std::abs(j.plane.normal.norm() - 1) > 1e-9 ||
      !std::isfinite(j.plane.d) || !j.centre.allFinite())
    fuzz::finding(kTarget, "a joint with a normal that is not a finite unit vector, or no centre");
  const std::size_t n = j.polygon_uv.size();
  if (n < 3) fuzz::finding(kTarget, "a joint polygon of fewer than 3 corners");
  for (std::size_t i = 0; i < n; ++i) {
    const slice::Vec2 &a = j.polygon_uv[(i + n - 1) % n], &b = j.polygon_uv[i],
                      &c = j.polygon_uv[(i + 1) % n];
    if (!b.allFinite()) fuzz::finding(kTarget, "a joint polygon with a corner not finite");
    const slice::Vec2 e1 = b - a, e2 = c - b;
    if (!(e1.x() * e2.y() - e1.y() * e2.x() > 0))
      fuzz::finding(kTarget, "a joint polygon that is not convex and counter-clockwise");
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  fuzz::set_input_name("net" SLICE_FUZZ_DFN_EXT);
  scene_path() = fuzz::scratch_path("dfn-scene.toml");
  std::atexit(remove_scene);
  std::ofstream s(scene_path());
  s << "[domain]\nbox = { min = [0, 0, 0], max = [10, 10, 10] }\n[[dfn]]\nfile = \""
    << fuzz::input_path().string() << "\"\n";
  if (!s.flush()) std::abort();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& input = fuzz::write_input(data, size);
  try {
    if (std::string_view(SLICE_FUZZ_DFN_EXT) == ".fab")
      (void)slice::read_fab(input);
    else
      (void)slice::read_dfn_csv(input, slice::DfnCsvOptions{}, input.stem().string());
  } catch (const slice::Error&) {
    return 0;  // refused by the reader: load_scene would refuse it the same way
  }
  try {
    const slice::Scene scene = slice::load_scene(scene_path());
    for (const slice::Joint& j : scene.joints) check_joint(j);
    for (const slice::JointSetSpec& s : scene.sets) check_name(s.name);
  } catch (const slice::Error&) {
    // Refused with a message: the promised answer to bad input.
  }
  return 0;
}

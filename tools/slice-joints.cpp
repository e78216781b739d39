// slice-joints: scene file (TOML, docs/scenes.md) -> joints.h5 (docs/formats.md; docs/design.md,
// "Architecture and data flow").
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/tool.hpp"
#include "info/zones.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/scene.hpp"

namespace {

// --seed as [scene] seed: an integer from 0 to 2^63 - 1. Converted here, not by CLI11, which
// clamps a larger integer (9223372036854775808, 2^64, 1e23) to 2^63 - 1: a sweep would get one
// realization under two names.
std::uint64_t parse_seed(const std::string& given) {
  const std::string s = given.rfind('+', 0) == 0 ? given.substr(1) : given;
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec == std::errc() && end == s.data() + s.size() && v >= 0) return std::uint64_t(v);
  char* dend = nullptr;
  const double d = std::strtod(s.c_str(), &dend);
  const bool number = !s.empty() && *dend == '\0';
  const char* why = ec == std::errc::result_out_of_range || (number && !(std::abs(d) < 0x1p63))
                        ? " is out of range"
                    : number && d < 0 ? " is negative"
                                      : " is not an integer";
  throw slice::Error("--seed", given + why,
                     "give an integer from 0 to 9223372036854775807 (2^63 - 1), as [scene] seed");
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

// A set's traces on its mapping window, beside the trace lengths mapped there (to calibrate the
// set's size).
std::string trace_line(const slice::JointSetSpec& s) {
  const slice::TraceStats& t = s.traces;
  std::string line = "set \"" + s.name + "\": " + std::to_string(t.count) +
                     " traces on its mapping window, length mean " + num(t.mean) + ", sd " +
                     num(t.sd);
  if (s.mapping.field_mean > 0)
    line += " (mapped: mean " + num(s.mapping.field_mean) +
            (s.mapping.field_sd > 0 ? ", sd " + num(s.mapping.field_sd) : std::string()) + ")";
  return line + "; 0/1/2 ends censored: " + std::to_string(t.censored[0]) + "/" +
         std::to_string(t.censored[1]) + "/" + std::to_string(t.censored[2]) + ", P21 " +
         num(t.p21);
}

}  // namespace

int main(int argc, char** argv) {
  tool::Tool t{"slice-joints",
               "Read a scene file, generate its joints and write them to an HDF5 file."};
  std::string scene_file;
  std::string out = "joints.h5";
  t.cli.add_option("scene", scene_file, "scene file (TOML, see docs/scenes.md)")->required();
  t.cli.add_option("-o,--output", out, "output file")->capture_default_str();
  std::optional<std::string> seed;  // parse_seed
  t.cli
      .add_option("--seed", seed,
                  "seed of the random joint sets, in place of the scene's [scene] seed (for "
                  "realization sweeps: joints.h5 records the seed used)")
      ->type_name("INT");
  t.add_compress_option();
  return t.run(argc, argv, [&] {
    const std::uint64_t seed_value = seed ? parse_seed(*seed) : 0;
    tool::check_distinct_paths({{"scene", scene_file, false}, {"-o", out}});
    slice::Scene scene = slice::load_scene(scene_file);
    // The files the scene names (mesh zones, DFN files) are inputs too: -o on one would
    // destroy it; the provenance hashes them beside the scene.
    std::vector<tool::PathArg> paths{{"scene", scene_file, false}, {"-o", out}};
    std::vector<std::string> named;
    for (const auto& [what, file] : slice::scene_files(scene)) {
      paths.push_back({what, file.string(), false});
      named.push_back(file.string());
    }
    tool::check_distinct_paths(paths);
    if (seed) scene.seed = seed_value;
    const slice::JointSystem js = slice::generate_joints(scene);
    slice::write_joints(out, js, t.provenance(scene_file, named), t.write_options());
    std::size_t persistent = 0;
    for (const auto& j : js.joints) persistent += j.persistent() ? 1 : 0;
    t.say(std::to_string(js.joints.size()) + " joints (" + std::to_string(persistent) +
          " persistent, " + std::to_string(js.joints.size() - persistent) +
          (js.dimension == 2 ? " segments) in " : " polygons) in ") +
          std::to_string(js.sets.size()) + " sets, seed " + std::to_string(js.seed) + " -> " + out);
    // A section of 3-D sets: each set's trace, as worked out (docs/2d.md).
    for (std::size_t i = 0; i < scene.set_traces.size(); ++i) {
      const slice::SectionTrace& tr = scene.set_traces[i];
      const slice::JointSetSpec& s = js.sets.at(i);
      std::string line = "set \"" + slice::escape_control(s.name) + "\" (dip " +
                         tool::sig(tr.dip_deg, 6) + ", dip direction " +
                         tool::sig(tr.dip_direction_deg, 6) + ") in the section (strike " +
                         tool::sig(scene.section->strike_deg, 6) + "): apparent dip " +
                         tool::fixed(tr.apparent_dip_deg, 2) + " towards " +
                         tool::sig(tr.apparent_dip_direction_deg, 3);
      if (s.intensity == slice::SetIntensity::spacing) {
        line +=
            ", spacing " + tool::sig(s.spacing, 6) + ", " + std::to_string(s.candidates) + " lines";
      } else {  // a stochastic set: the traces of its 3-D joints (achieved_p32: their P21)
        line += " (the mean plane's), " + std::to_string(s.joint_count) + " traces of " +
                std::to_string(s.candidates) + " joints drawn in 3-D, P21 " +
                tool::sig(s.achieved_p32, 6);
        const std::string p21 =
            "p32 x sin theta of the mean plane: " + tool::sig(s.p32 * tr.sin_angle, 6) + ")";
        if (s.intensity == slice::SetIntensity::p32) line += " (" + p21;
        if (s.intensity == slice::SetIntensity::p10)  // drawn as p32 = p10 / E|cos| (docs/2d.md)
          line += " (p32 = p10 / E|cos| = " + tool::sig(s.p32, 6) + "; " + p21;
      }
      t.say(line);
    }
    for (const auto& s : js.sets)
      if (s.mapping.given) t.say(trace_line(s));
    // A zone above the ground removes air, not rock (issue 43): said even with -q, exit 0.
    for (const std::string& w : info::ground_warnings(js))
      std::cerr << "slice-joints: warning: " << slice::escape_control(w) << '\n';
  });
}

// slice-stability: geom.h5 -> stab.h5, the contacts of every kept block (/contacts) and which
// blocks fall, how and with what margin (/stability): removability, failure mode and factor of
// safety by limit equilibrium, with successive failure (docs/stability.md).
#include <optional>
#include <string>

#include "common/tool.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/stability.hpp"

int main(int argc, char** argv) {
  tool::Tool t{"slice-stability",
               "Which blocks can fall or slide: removability, failure mode, factor of safety and "
               "successive failure of every exposed block (/contacts, /stability)."};
  std::string in, out = "stab.h5", free_faces;
  slice::StabilityOptions opt;
  std::optional<double> water_table;
  t.cli.add_option("geometry", in, "geom.h5 from slice-vertices")->required();
  t.cli.add_option("-o,--output", out, "output file: the input plus /contacts and /stability")
      ->capture_default_str();
  t.cli.add_option("--free-faces", free_faces,
                   "faces of the domain's bounding box that are free surfaces, e.g. +z,-x "
                   "(names as fixed_faces: -x +x -y +y -z +z); removed blocks make free faces too");
  t.cli.add_option("--density", opt.density, "density of the rock, kg/m3")->capture_default_str();
  t.cli
      .add_option("--seismic", opt.seismic,
                  "pseudo-static seismic coefficient k: a horizontal load k W on every block")
      ->capture_default_str();
  t.cli
      .add_option("--seismic-azimuth", opt.seismic_azimuth_deg,
                  "azimuth the seismic load points to, degrees clockwise from North (+y)")
      ->capture_default_str();
  t.cli.add_option("--water-table", water_table,
                   "z of a horizontal water table: hydrostatic water pressure on the contact "
                   "faces below it (water 1000 kg/m3)");
  t.cli
      .add_option("--support-pressure", opt.support_pressure,
                  "support pressure on the free faces a block has at the start, Pa")
      ->capture_default_str();
  t.cli
      .add_option("--fos-target", opt.fos_target,
                  "a block that can move with a factor of safety below this fails and is taken "
                  "out; the blocks it exposes are analysed again")
      ->capture_default_str();
  t.cli
      .add_option("--max-group", opt.max_group,
                  "most bodies in a group that fails together: a body that holds alone is "
                  "analysed again with the neighbours in its way as one rigid body (1: one body "
                  "at a time)")
      ->capture_default_str();
  t.add_threads_option();
  t.add_compress_option();
  return t.run(argc, argv, [&] {
    tool::check_distinct_paths({{"geometry", in, false}, {"-o", out}});
    opt.water_table = water_table;
    if (!free_faces.empty()) opt.free_faces = slice::parse_free_faces(free_faces);
    slice::check_stability_options(opt);
    slice::BlockSystem bs = slice::read_blocks(in);
    slice::geometry_of(bs, in);
    if (bs.joints.dimension != 3)
      throw slice::Error(in, "is a 2-D section (dimension 2): slice-stability analyses 3-D models",
                         "slice the scene in 3-D");
    slice::StabilityStats s;
    bs.stability = slice::analyse_stability(bs, opt, &s);
    slice::write_blocks(out, bs, t.provenance(in), t.write_options());
    t.say(std::to_string(s.bodies) + " bodies, " + std::to_string(s.contacts) + " contacts: " +
          std::to_string(s.exposed) + " exposed, " + std::to_string(s.removable) + " removable, " +
          std::to_string(s.failing) + " fail (FoS < " + tool::sig(opt.fos_target, 3) + "; " +
          std::to_string(s.groups) + " group" + (s.groups == 1 ? "" : "s") +
          " failing together) in " + std::to_string(s.rounds) + " round" +
          (s.rounds == 1 ? "" : "s") + " (" + tool::fixed(s.seconds, 3) + " s) -> " + out);
    t.say("time: contacts " + tool::fixed(s.contacts_seconds, 3) + " s, bodies " +
          tool::fixed(s.bodies_seconds, 3) + " s, analysis of the exposed bodies " +
          tool::fixed(s.analysis_seconds, 3) + " s");
    t.exit_now();
  });
}

// slice-export: geom.h5 (blocks with /geometry) -> blocks.vtu for ParaView, or a YADE script.
#include <map>
#include <string>

#include "common/tool.hpp"
#include "slice/error.hpp"
#include "slice/export_vtu.hpp"
#include "slice/export_yade.hpp"
#include "slice/h5io.hpp"

int main(int argc, char** argv) {
  tool::Tool t{"slice-export",
               "Export blocks with vertices (slice-vertices) to VTU for ParaView or to YADE."};
  std::string in, out, format = "vtu", joints;
  slice::YadeOptions yade;  // defaults live in the library
  t.cli.add_option("geometry", in, "geom.h5 from slice-vertices")->required();
  t.cli.add_option("-o,--output", out, "output file (blocks.vtu, model.py)")->required();
  t.cli.add_option("--format", format, "vtu | yade | yade-potential-blocks")->capture_default_str();
  t.cli.add_option("--joints", joints, "vtu: also write the joints inside the domain to this VTU");
  std::string compressor = "lz4";
  t.cli
      .add_option("--vtu-compressor", compressor,
                  "vtu: lz4 (fast) | zlib (about half the size, 3.5x slower) | none")
      ->capture_default_str();
  t.cli.add_option("--yade-steps", yade.steps, "yade: run this many steps at the end (0: none)")
      ->capture_default_str();
  t.cli.add_option("--yade-density", yade.density, "yade: rock density [kg/m3]")
      ->capture_default_str();
  t.cli.add_option("--yade-young", yade.young, "yade: contact stiffness (PolyhedraMat.young)")
      ->capture_default_str();
  t.cli.add_option("--yade-poisson", yade.poisson, "yade: shear / normal contact stiffness")
      ->capture_default_str();
  t.cli
      .add_option("--yade-friction", yade.default_friction_deg,
                  "yade: friction angle [deg] of blocks without rock or boundary joint faces")
      ->capture_default_str();
  t.cli.add_option("--yade-damping", yade.damping, "yade: NewtonIntegrator damping")
      ->capture_default_str();
  t.cli
      .add_option("--yade-timestep-factor", yade.timestep_factor,
                  "yade: time step as a fraction of the critical one")
      ->capture_default_str();
  t.cli
      .add_option("--pb-rounding", yade.pb_rounding,
                  "yade-potential-blocks: rounding radius / inscribed radius")
      ->capture_default_str();
  t.add_threads_option();
  return t.run(argc, argv, [&] {
    tool::check_distinct_paths({{"geometry", in, false}, {"-o", out}, {"--joints", joints}});
    if (format != "vtu" && format != "yade" && format != "yade-potential-blocks")
      throw slice::Error("--format " + format, "unknown format",
                         "use vtu, yade or yade-potential-blocks");
    if (!joints.empty() && format != "vtu")
      throw slice::Error("--joints", "is for --format vtu", "drop it or export VTU");
    yade.validate();
    const auto vtu_compressor = slice::parse_vtu_compressor(compressor, "--vtu-compressor");
    const slice::BlockSystem bs = slice::read_blocks(in);
    if (!bs.geometry)
      throw slice::Error(in, "the blocks have no vertices (no /geometry)",
                         "run slice-vertices on it first");
    if (format == "vtu") {
      const auto st = slice::write_blocks_vtu(out, bs, vtu_compressor, t.threads);
      t.say(std::to_string(st.cells) + " blocks (" + std::to_string(st.skipped) +
            " removed left out), " + std::to_string(st.points) + " points -> " + out);
      if (!joints.empty()) {
        const auto js = slice::write_joints_vtu(joints, bs.joints, vtu_compressor);
        t.say(std::to_string(js.cells) + " joints (" + std::to_string(js.skipped) +
              " outside the domain left out) -> " + joints);
      }
      return;
    }
    yade.shape =
        format == "yade" ? slice::YadeShape::polyhedra : slice::YadeShape::potential_blocks;
    yade.source = in;
    const auto st = slice::write_yade_script(out, bs, yade);
    t.say(std::to_string(st.bodies) + " bodies (" + std::to_string(st.fixed) + " fixed, " +
          std::to_string(st.clumps) + " clumps; " + std::to_string(st.removed) +
          " removed blocks left out) -> " + out);
  });
}

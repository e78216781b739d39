// slice-export: geom.h5 (blocks with /geometry) -> blocks.vtu for ParaView, a YADE script, or a
// 3DEC grid with the command file that imports it; or the joints of joints.h5 (or of blocks) as a
// FracMan FAB file (--format fab), so that FracMan and PorePy open a DFN rockslice made.
#include <filesystem>
#include <map>
#include <string>
#include <tuple>

#include "common/tool.hpp"
#include "slice/dfn.hpp"
#include "slice/error.hpp"
#include "slice/export_3dec.hpp"
#include "slice/export_udec.hpp"
#include "slice/export_vtu.hpp"
#include "slice/export_yade.hpp"
#include "slice/h5io.hpp"

int main(int argc, char** argv) {
  tool::Tool t{
      "slice-export",
      "Export blocks with vertices (slice-vertices) to VTU for ParaView, YADE, 3DEC or UDEC."};
  std::string in, out, format = "vtu", joints;
  slice::YadeOptions yade;  // defaults live in the library
  t.cli
      .add_option("geometry", in, "geom.h5 from slice-vertices (fab: joints.h5 or any later file)")
      ->required();
  t.cli
      .add_option("-o,--output", out,
                  "output file (blocks.vtu, model.py, model.3dgrid, section.dat, dfn.fab)")
      ->required();
  t.cli.add_option("--format", format, "vtu | yade | yade-potential-blocks | 3dec | udec | fab")
      ->capture_default_str();
  std::string commands;
  t.cli.add_option("--3dec-commands", commands,
                   "3dec: the command file that imports the grid (default: -o with .dat)");
  slice::ThreeDecOptions tdec;  // defaults live in the library
  for (const auto& [name, value, help] :
       {std::tuple{"--3dec-density", &tdec.density, "3dec: rock density [kg/m3]"},
        std::tuple{"--3dec-jkn", &tdec.jkn, "3dec: joint normal stiffness [Pa/m]"},
        std::tuple{"--3dec-jks", &tdec.jks, "3dec: joint shear stiffness [Pa/m]"},
        std::tuple{"--3dec-friction", &tdec.friction_deg,
                   "3dec: friction angle [deg] of contacts on no JS line (joint set 0)"}})
    t.cli.add_option(name, *value, help)->capture_default_str();
  t.cli.add_option("--joints", joints, "vtu: also write the joints inside the domain to this VTU");
  std::string compressor = "lz4";
  t.cli
      .add_option("--vtu-compressor", compressor,
                  "vtu: lz4 (fast) | zlib (0.6x the size of lz4, 3-4x its time) | none")
      ->capture_default_str();
  t.cli.add_option("--yade-steps", yade.steps, "yade: run this many steps at the end (0: none)")
      ->capture_default_str();
  tool::add_yade_timestep_options(t.cli, yade);
  t.cli.add_option("--yade-poisson", yade.poisson, "yade: shear / normal contact stiffness")
      ->capture_default_str();
  t.cli
      .add_option("--yade-friction", yade.default_friction_deg,
                  "yade: friction angle [deg] of blocks without rock or boundary joint faces")
      ->capture_default_str();
  t.cli.add_option("--yade-damping", yade.damping, "yade: NewtonIntegrator damping")
      ->capture_default_str();
  std::string law = "mohr-coulomb";
  t.cli
      .add_option("--yade-law", law,
                  "yade: contact law, mohr-coulomb (each contact its joint's strength and own "
                  "shear) | volumetric (YADE's own: shear shared by all contacts)")
      ->capture_default_str();
  t.cli
      .add_option("--pb-rounding", yade.pb_rounding,
                  "yade-potential-blocks: rounding radius / inscribed radius")
      ->capture_default_str();
  t.add_threads_option();
  return t.run(argc, argv, [&] {
    if (format != "vtu" && format != "yade" && format != "yade-potential-blocks" &&
        format != "3dec" && format != "udec" && format != "fab")
      throw slice::Error("--format " + format, "unknown format",
                         "use vtu, yade, yade-potential-blocks, 3dec, udec or fab");
    if (format == "fab") {  // the joints: of joints.h5, or of the blocks' file
      if (!joints.empty() || !commands.empty())
        throw slice::Error(joints.empty() ? "--3dec-commands" : "--joints",
                           "does not apply to --format fab", "drop it");
      tool::check_distinct_paths({{"geometry", in, false}, {"-o", out}});
      const bool joints_file = slice::read_header(in).kind == slice::FileKind::joints;
      const slice::JointSystem js =
          joints_file ? slice::read_joints(in) : slice::read_blocks(in).joints;
      if (js.dimension != 3)  // the input is 2-D, not the output
        throw slice::Error(
            in, "is a 2-D section (dimension 2): its joints are lines, and FAB holds 3-D polygons",
            "export the joints of the 3-D scene (without [section])");
      const slice::FabStats st = slice::write_fab(out, js);
      t.say_when_written(
          std::to_string(st.fractures) + " fractures (" + std::to_string(st.persistent) +
          " persistent joints clipped to the domain, " + std::to_string(st.left_out) +
          " missing it left out), " + std::to_string(st.nodes) + " nodes, " +
          std::to_string(st.sets) + " sets -> " + out);
      t.exit_now();
      return;
    }
    if (!joints.empty() && format != "vtu")
      throw slice::Error("--joints", "is for --format vtu", "drop it or export VTU");
    if (!commands.empty() && format != "3dec")
      throw slice::Error("--3dec-commands", "is for --format 3dec", "drop it or export 3DEC");
    if (format == "3dec" && commands.empty())
      commands = std::filesystem::path(out).replace_extension(".dat").string();
    tool::check_distinct_paths({{"geometry", in, false},
                                {"-o", out},
                                {"--joints", joints},
                                {"--3dec-commands", commands}});
    yade.law = slice::parse_yade_law(law);
    yade.validate();
    tdec.validate();
    const auto vtu_compressor = slice::parse_vtu_compressor(compressor, "--vtu-compressor");
    if (format == "vtu") {  // from the file: /geometry is not held (the same checks and bytes)
      slice::JointSystem js;
      const auto st = slice::export_blocks_vtu(in, out, vtu_compressor, t.threads,
                                               slice::VtuIds::narrowest, &js);
      t.say_when_written(std::to_string(st.cells) + " blocks (" + std::to_string(st.skipped) +
                         " removed left out), " + std::to_string(st.points) + " points -> " + out);
      if (!joints.empty()) {
        const auto jst = slice::write_joints_vtu(joints, js, vtu_compressor);
        t.say_when_written(std::to_string(jst.cells) + " joints (" + std::to_string(jst.skipped) +
                           " outside the domain left out) -> " + joints);
      }
      t.exit_now();
      return;
    }
    const slice::BlockSystem bs = slice::read_blocks(in);
    slice::geometry_of(bs, in);
    if (bs.joints.dimension == 2 && format == "3dec")  // the input is 2-D, not the output
      throw slice::Error(in, "is a 2-D section (dimension 2): the 3DEC export is 3-D only",
                         "export it with --format yade (Polyhedra prisms) or --format vtu");
    if (bs.joints.dimension != 2 && format == "udec")
      throw slice::Error(in, "is 3-D (dimension 3): the UDEC export is for 2-D sections",
                         "export it with --format 3dec, or slice a section (dimension = 2)");
    if (format == "udec") {
      const auto st = slice::write_udec(out, bs);
      t.say_when_written(std::to_string(st.blocks) + " blocks (" + std::to_string(st.removed) +
                         " removed left out), " + std::to_string(st.vertices) + " corners -> " +
                         out);
      t.exit_now();
      return;
    }
    if (format == "3dec") {
      const auto st = slice::write_3dec(out, commands, bs, tdec);
      t.say_when_written(std::to_string(st.blocks) + " blocks (" + std::to_string(st.removed) +
                         " removed left out), " + std::to_string(st.faces) + " faces, " +
                         std::to_string(st.contacts) + " joint contacts (" +
                         std::to_string(st.bridge_contacts) + " rock bridges), TOL " +
                         tool::sig(st.tol, 3) + " -> " + out);
      t.say_when_written(std::to_string(st.fixed) + " blocks in group boundary (fixed), " +
                         std::to_string(st.clusters) + " clusters joined, " +
                         std::to_string(st.joint_sets) + " joint sets with properties -> " +
                         commands);
      t.say_when_written(tool::smallest_bodies_line(st.dem) + " -> 3DEC critical time step " +
                         tool::sig(st.critical_timestep, 4) + " s (0.1 x 2 sqrt(m / k): m " +
                         tool::sig(st.min_mass, 4) + " kg at density " +
                         tool::sig(tdec.density, 6) + ", k = jkn x largest contact " +
                         tool::sig(st.max_contact_stiffness, 4) + " N/m)");
      t.exit_now();
      return;
    }
    yade.shape =
        format == "yade" ? slice::YadeShape::polyhedra : slice::YadeShape::potential_blocks;
    yade.source = in;
    const auto st = slice::write_yade_script(out, bs, yade);
    t.say_when_written(std::to_string(st.bodies) + " bodies (" + std::to_string(st.fixed) +
                       " fixed, " + std::to_string(st.clumps) + " clumps; " +
                       std::to_string(st.removed) + " removed blocks left out) -> " + out);
    if (yade.shape == slice::YadeShape::polyhedra)
      t.say_when_written(
          yade.law == slice::YadeLaw::volumetric
              ? std::string("contact law: YADE's volumetric law alone, one friction angle per "
                            "block; WARNING: in YADE 2023.02a its shear force is shared by all "
                            "contacts, so friction is wrong for a body with two or more")
              : "contact law: mohr-coulomb per contact (" + std::to_string(st.contacts) +
                    " joint contacts, " + std::to_string(st.bridges) +
                    " rock bridges, each its joint's friction, cohesion and tension)");
    else
      t.say_when_written(
          "contact law: PotentialBlock's KnKsPB law (per interaction), one friction angle per "
          "block");
    t.say_when_written(tool::smallest_bodies_line(st.dem) +
                       " -> O.dt = " + tool::sig(st.timestep, 4) + " s (" +
                       tool::sig(yade.timestep_factor, 3) + " x the critical step, density " +
                       tool::sig(yade.density, 6) + ", young " + tool::sig(yade.young, 6) + ")");
    t.exit_now();
  });
}

// slice-export: geom.h5 (blocks with /geometry) -> blocks.vtu for ParaView, or a YADE script.
#include <string>

#include "common/tool.hpp"
#include "slice/error.hpp"
#include "slice/export_vtu.hpp"
#include "slice/h5io.hpp"

int main(int argc, char** argv) {
  tool::Tool t{"slice-export",
               "Export blocks with vertices (slice-vertices) to VTU for ParaView or to YADE."};
  std::string in, out, format = "vtu", joints;
  t.cli.add_option("geometry", in, "geom.h5 from slice-vertices")->required();
  t.cli.add_option("-o,--output", out, "output file (blocks.vtu, model.py, ...)")->required();
  t.cli.add_option("--format", format, "vtu")->capture_default_str();
  t.cli.add_option("--joints", joints, "vtu: also write the joints, clipped to the domain");
  return t.run(argc, argv, [&] {
    tool::check_output_differs(in, out);
    if (format != "vtu") throw slice::Error("--format " + format, "unknown format", "use vtu");
    const slice::BlockSystem bs = slice::read_blocks(in);
    if (!bs.geometry)
      throw slice::Error(in, "the blocks have no vertices (no /geometry)",
                         "run slice-vertices on it first");
    const auto st = slice::write_blocks_vtu(out, bs);
    t.say(std::to_string(st.cells) + " blocks (" + std::to_string(st.skipped) +
          " removed left out), " + std::to_string(st.points) + " points -> " + out);
    if (!joints.empty()) {
      tool::check_output_differs(in, joints);
      const auto js = slice::write_joints_vtu(joints, bs.joints);
      t.say(std::to_string(js.cells) + " joints (" + std::to_string(js.skipped) +
            " outside the domain left out) -> " + joints);
    }
  });
}

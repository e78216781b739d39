// slice-vertices: blocks.h5 -> geom.h5, the blocks' vertices, face loops, volumes, centroids,
// inertia, face areas and rock-bridge fractions (/geometry; docs/design.md, "Files and schema").
#include <cstdio>
#include <future>
#include <string>
#include <utility>

#include "common/tool.hpp"
#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/vertices.hpp"

int main(int argc, char** argv) {
  tool::Tool t{"slice-vertices",
               "Compute the vertices, face loops and mass properties of every block (/geometry)."};
  std::string in, out = "geom.h5", backend = "native";
  bool prune = false;
  t.cli.add_option("blocks", in, "pruned blocks.h5 from slice-cut --prune or slice-prune")
      ->required();
  t.cli.add_option("-o,--output", out, "output file: the blocks plus /geometry")
      ->capture_default_str();
  t.cli.add_flag("--prune", prune, "prune the blocks first if they are not (as slice-prune does)");
  t.cli.add_option("--lp", backend, "LP backend for --prune: native | ipopt | exact")
      ->capture_default_str();
  t.add_threads_option();
  t.add_compress_option();
  return t.run(argc, argv, [&] {
    tool::check_distinct_paths({{"blocks", in, false}, {"-o", out}});
    // The input's hash is taken while it is read; /blocks and then /geometry, run by run, are
    // written while /geometry is computed.
    auto provenance = std::async(std::launch::async, [&] { return t.provenance(in); });
    slice::BlockSystem bs = slice::read_blocks(in);
    if (!bs.pruned && !prune)
      throw slice::Error(in, "the blocks are not pruned (/blocks attribute pruned is 0)",
                         "run slice-prune on it first, or pass --prune");
    const bool pruned_here = !bs.pruned;
    if (pruned_here) {
      const auto ps =
          slice::prune_blocks(bs, slice::parse_lp_backend(backend), t.progress(), false, t.threads);
      t.say("pruned: faces " + std::to_string(ps.faces_before) + " -> " +
            std::to_string(ps.faces_after) + " (" + tool::fixed(ps.seconds, 3) + " s)");
    }
    // Blocks pruned here are checked again as they are written; read ones were when read.
    slice::BlocksFileWriter writer(out, bs, provenance.get(), t.write_options(),
                                   pruned_here ? slice::BlocksFileWriter::Blocks::made
                                               : slice::BlocksFileWriter::Blocks::read);
    const slice::GeometryStats s =
        slice::compute_geometry(std::as_const(bs), writer.geometry_sink(), t.progress(), t.threads);
    writer.finish();
    const double us = s.blocks ? 1e6 * s.seconds / double(s.blocks) : 0;
    t.say(std::to_string(s.blocks) + " blocks, " + std::to_string(s.vertices) + " vertices, " +
          std::to_string(s.faces) + " faces -> " + out);
    t.say("time: vertices " + tool::fixed(s.seconds, 3) + " s (" + tool::fixed(us, 1) +
          " us per block)");
    t.exit_now();
  });
}

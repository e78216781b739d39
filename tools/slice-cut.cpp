// slice-cut: joints.h5 -> blocks.h5 by sequential subdivision (docs/design.md, "The linear
// programs").
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "common/tool.hpp"
#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/output.hpp"

int main(int argc, char** argv) {
  tool::Tool t{"slice-cut",
               "Cut the domain of a joints.h5 file into convex blocks, one LP per decision."};
  std::string in, out = "blocks.h5", backend = "native";
  std::string stats_file;
  bool prune = false, no_index = false, no_shortcuts = false, certify = false;
  t.cli.add_option("joints", in, "joints.h5 from slice-joints")->required();
  t.cli.add_option("-o,--output", out, "output file")->capture_default_str();
  t.cli.add_option("--lp", backend, "LP backend: native | ipopt | exact")->capture_default_str();
  t.cli.add_flag("--prune", prune, "also drop redundant faces (as slice-prune does)");
  t.cli.add_flag("--no-index", no_index,
                 "test every block against every joint (no bounding spheres or grid)");
  t.cli.add_flag("--no-shortcuts", no_shortcuts,
                 "give every joint-block pair the index passes to the cut LP (no geometric "
                 "rejection first; the same blocks)");
  t.cli.add_option("--stats", stats_file, "also write the run's figures as JSON to this file");
  t.cli.add_flag("--certify", certify,
                 "decide again with the exact backend every cut, size/shape limit, contact and "
                 "redundancy decision that lies within the tolerance of its threshold");
  std::int64_t max_blocks = 0;
  t.cli
      .add_option("--max-blocks", max_blocks,
                  "refuse to make more blocks than this (default: the scene's [options] "
                  "max_blocks, itself 2,000,000 by default)")
      ->check(CLI::PositiveNumber);
  t.add_threads_option();
  t.add_compress_option();
  return t.run(argc, argv, [&] {
    tool::check_distinct_paths({{"joints", in, false}, {"-o", out}, {"--stats", stats_file}});
    slice::CutOptions opt;
    opt.backend = slice::parse_lp_backend(backend);
    opt.use_index = !no_index;
    opt.use_shortcuts = !no_shortcuts;
    opt.max_blocks = max_blocks;
    opt.certify = certify;
    opt.threads = t.threads;
    const slice::JointSystem js = slice::read_joints(in);
    slice::CutResult r = slice::cut_blocks(js, opt, t.progress());
    const auto& s = r.stats;
    slice::PruneStats ps;
    // The cut's own blocks are solids by construction: no solid check.
    if (prune)
      ps = slice::prune_blocks(r.blocks, opt.backend, t.progress(), certify, t.threads, false);
    slice::DecisionCounts d = s.decisions;
    d += ps.decisions;
    slice::write_blocks(out, r.blocks, t.provenance(in), t.write_options());
    if (!stats_file.empty()) {
      std::size_t faces = 0;
      for (const auto& b : r.blocks.blocks) faces += b.faces.size();
      const nlohmann::ordered_json j = {{"joints", s.joints},
                                        {"blocks", s.blocks},
                                        {"splits", s.splits},
                                        {"splits_undone", s.splits_undone},
                                        {"pairs_skipped", s.pairs_skipped},
                                        {"pairs_rejected_plane", s.rejected_plane},
                                        {"pairs_rejected_box", s.rejected_box},
                                        {"pairs_rejected_faces", s.rejected_faces},
                                        {"pairs_settled_by_limit", s.settled_by_limit},
                                        {"pairs_cut_without_lp", s.cut_without_lp},
                                        {"slivers_removed", s.slivers_removed},
                                        {"slivers_joined", s.slivers_joined},
                                        {"slivers_left", s.slivers_left},
                                        {"lps_cut_test", s.lps.cut_test},
                                        {"lps_extents", s.lps.extents},
                                        {"lps_chebyshev", s.lps.chebyshev},
                                        {"extremes_at_vertices", s.lps.vertex_extremes},
                                        {"lps_contact", s.lps.contact},
                                        {"lps_redundancy", ps.lps},
                                        {"faces_kept_without_lp", ps.certified},
                                        {"lps_failed", s.lps.failed + ps.failed},
                                        {"lps_solved", s.lps.total() + ps.lps},
                                        {"lps_resolved_exactly", d.resolved},
                                        {"decisions_checked", d.checked},
                                        {"decisions_changed", d.changed},
                                        {"seconds_cut", s.seconds_cut},
                                        {"seconds_finish", s.seconds_finish},
                                        {"seconds_prune", ps.seconds},
                                        {"faces", faces}};
      slice::write_text_file(stats_file, j.dump(2) + "\n");
    }
    t.say(std::to_string(s.joints) + " joints (" + std::to_string(s.joints_missing) +
          " cut nothing) -> " + std::to_string(s.blocks) + " blocks (" +
          std::to_string(s.boundary) + " boundary, " +
          (s.fixed ? std::to_string(s.fixed) + " fixed, " : std::string()) +
          std::to_string(s.removed) + " removed, " + std::to_string(s.clusters) + " clusters) -> " +
          out);
    t.say("splits " + std::to_string(s.splits) + ", undone by size/shape limits " +
          std::to_string(s.splits_undone) + "; joint-block pairs skipped by the index " +
          std::to_string(s.pairs_skipped) + ", settled without an LP " +
          std::to_string(s.rejected_plane + s.rejected_box + s.rejected_faces + s.settled_by_limit +
                         s.cut_without_lp) +
          " (plane " + std::to_string(s.rejected_plane) + ", polygon box " +
          std::to_string(s.rejected_box) + ", faces " + std::to_string(s.rejected_faces) +
          ", size limit " + std::to_string(s.settled_by_limit) + ", cut " +
          std::to_string(s.cut_without_lp) + ")");
    if (s.slivers_removed + s.slivers_joined + s.slivers_left > 0)
      t.say("slivers (free blocks under the size/shape limits, left by exempt cuts): " +
            std::to_string(s.slivers_removed) + " removed with the excavation they touch, " +
            std::to_string(s.slivers_joined) + " joined to a neighbour's cluster" +
            (s.slivers_left ? ", " + std::to_string(s.slivers_left) + " with no neighbour (left)"
                            : std::string()));
    t.say("LPs (" + slice::to_string(opt.backend) + "): cut tests " +
          std::to_string(s.lps.cut_test) + ", extents " + std::to_string(s.lps.extents) +
          ", Chebyshev " + std::to_string(s.lps.chebyshev) + " (" +
          std::to_string(s.lps.vertex_extremes) + " extremes found at vertices without one)" +
          ", contacts " + std::to_string(s.lps.contact) +
          (prune ? ", redundancy " + std::to_string(ps.lps) + " (" + std::to_string(ps.certified) +
                       " faces kept without one)"
                 : "") +
          ", failed " + std::to_string(s.lps.failed + ps.failed) + "; solved again exactly " +
          std::to_string(d.resolved));
    t.say(std::string(certify ? "certify: " : "near-threshold: ") + std::to_string(d.checked) +
          " decisions within " + (certify ? "the tolerance" : "rounding") +
          " of their threshold decided again exactly, " + std::to_string(d.changed) + " changed");
    t.say("time: cut " + tool::fixed(s.seconds_cut, 3) + " s, finish " +
          tool::fixed(s.seconds_finish, 3) + " s" +
          (prune ? ", prune " + tool::fixed(ps.seconds, 3) + " s" : "") +
          (prune ? "; faces " + std::to_string(ps.faces_before) + " -> " +
                       std::to_string(ps.faces_after)
                 : ""));
    t.exit_now();
  });
}

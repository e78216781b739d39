// slice-prune: drop the faces that no longer touch their block (paper eq. 8).
#include <cstdio>
#include <string>

#include "common/tool.hpp"
#include "slice/cut.hpp"
#include "slice/h5io.hpp"

int main(int argc, char** argv) {
  tool::Tool t{"slice-prune", "Drop redundant faces from every block of a blocks.h5 file."};
  std::string in, out, backend = "native";
  bool certify = false;
  t.cli.add_option("blocks", in, "blocks.h5 from slice-cut")->required();
  t.cli.add_option("-o,--output", out, "output file (default: replace the input)");
  t.cli.add_option("--lp", backend, "LP backend: native | ipopt | exact")->capture_default_str();
  t.cli.add_flag("--certify", certify,
                 "decide again with the exact backend every redundancy decision that lies within "
                 "the tolerance of its threshold");
  t.add_threads_option();
  t.add_compress_option();
  return t.run(argc, argv, [&] {
    // Without -o the input is replaced (atomically); -o naming the input is refused like every
    // other clash, so a script's typo is caught.
    tool::check_distinct_paths({{"blocks", in, false}, {"-o", out}});
    const auto lp = slice::parse_lp_backend(backend);
    slice::BlockSystem bs = slice::read_blocks(in);
    const slice::PruneStats s = slice::prune_blocks(bs, lp, t.progress(), certify, t.threads);
    const std::string target = out.empty() ? in : out;
    slice::write_blocks(target, bs, t.provenance(in), t.write_options());
    t.say(std::to_string(bs.blocks.size()) + " blocks: faces " + std::to_string(s.faces_before) +
          " -> " + std::to_string(s.faces_after) + " (" + std::to_string(s.lps) + " LPs, " +
          std::to_string(s.certified) + " faces kept without one, " + std::to_string(s.failed) +
          " failed, " + std::to_string(s.decisions.resolved) + " solved again exactly, " +
          tool::fixed(s.seconds, 3) + " s) -> " + target);
    t.say(std::string(certify ? "certify: " : "near-threshold: ") +
          std::to_string(s.decisions.checked) + " decisions within " +
          (certify ? "the tolerance" : "rounding") + " of their threshold decided again exactly, " +
          std::to_string(s.decisions.changed) + " changed");
    t.exit_now();
  });
}

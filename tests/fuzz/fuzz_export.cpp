// libFuzzer target: the 3DEC and YADE writers fed from a (fuzzed) geom.h5. The input is written
// to a file that slice::read_blocks reads, as slice-export does; blocks with /geometry are then
// written as a 3DEC grid and command file (slice::write_3dec) and as YADE scripts of both
// shapes (slice::write_yade_script), each to a file in the temporary directory. slice::Error
// (bad input, exit 1 in the tools) is the expected answer; any other exception, a crash, a
// sanitizer report, a timeout or running out of memory is a finding. So is an output that is
// written but is not what 3DEC or YADE can read (checked cheaply, below):
//   3DEC grid: each line one record ("* comment", TOL, G, F, B, JS) with finite numbers and IDs
//     that count up and refer to records above them, the counts the stats report;
//   3DEC commands: each line a comment (";") or one of the commands the writer writes, without
//     "nan" or "inf" outside comments;
//   YADE script: UTF-8, no control character but newline (Python ends a line at "\r", and NUL
//     is no source), Python's strings, comments and brackets closed, no nan or inf names, and
//     one BLOCKS row per body.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "export_check.hpp"
#include "fuzz_input.hpp"
#include "slice/error.hpp"
#include "slice/export_3dec.hpp"
#include "slice/export_yade.hpp"
#include "slice/h5io.hpp"

namespace {

struct Outputs {
  std::filesystem::path grid, commands, yade, pb;
};

Outputs& outputs() {
  static Outputs o;
  return o;
}

void remove_outputs() {
  std::error_code ec;
  for (const auto& p : {outputs().grid, outputs().commands, outputs().yade, outputs().pb})
    std::filesystem::remove(p, ec);
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string s(std::filesystem::file_size(p), '\0');
  in.read(s.data(), std::streamsize(s.size()));
  if (!in) fuzz::finding("fuzz_export", "cannot read back " + p.string());
  return s;
}

void export_all(const slice::BlockSystem& bs) {
  const Outputs& o = outputs();
  try {
    const slice::ThreeDecStats st = slice::write_3dec(o.grid, o.commands, bs);
    fuzz::check_grid(read_file(o.grid), st);
    fuzz::check_commands(read_file(o.commands));
  } catch (const slice::Error&) {
  }
  for (const auto shape : {slice::YadeShape::polyhedra, slice::YadeShape::potential_blocks}) {
    slice::YadeOptions opt;
    opt.shape = shape;
    opt.source = fuzz::input_path().string();
    const auto& out = shape == slice::YadeShape::polyhedra ? o.yade : o.pb;
    try {
      const slice::YadeStats st = slice::write_yade_script(out, bs, opt);
      if (st.bodies + st.removed != bs.blocks.size())
        fuzz::finding("fuzz_export", "YADE bodies + removed is not the block count");
      fuzz::check_python(read_file(out), st.bodies, out.filename().string());
    } catch (const slice::Error&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  fuzz::set_input_name("geom.h5");
  outputs() = {fuzz::scratch_path("m.3dgrid"), fuzz::scratch_path("m.dat"),
               fuzz::scratch_path("m.py"), fuzz::scratch_path("m-pb.py")};
  std::atexit(remove_outputs);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = fuzz::write_input(data, size);
  try {
    const slice::BlockSystem bs = slice::read_blocks(path);
    if (bs.geometry) export_all(bs);
  } catch (const slice::Error&) {
    // refused as any reader refuses it (fuzz_h5's business)
  }
  return 0;
}

#pragma once
// What every rockslice tool shares: argument parsing, exit codes, error lines, the progress bar,
// provenance. A tool parses, calls the library, reports.
//   exit 0: done (also --help, --version)   1: bad input   2: internal error (a bug)
#include <CLI/CLI.hpp>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "slice/dem.hpp"
#include "slice/export_yade.hpp"
#include "slice/h5io.hpp"
#include "slice/progress.hpp"

namespace tool {

class ProgressBar;

class Tool {
 public:
  Tool(std::string name, const std::string& description);
  ~Tool();

  CLI::App cli;
  bool quiet = false;
  bool verbose = false;
  int threads = 0;  // --threads, where the tool offers it (add_threads_option); 0: all cores

  bool compress = false;  // --compress, where the tool writes HDF5 (add_compress_option)

  /// Adds --compress: the HDF5 output's datasets deflated (WriteOptions::compress).
  void add_compress_option();
  slice::WriteOptions write_options() const { return {compress}; }

  /// Adds --threads N. It changes no result, so the command line stored in the output's
  /// provenance leaves it out: the file is the same bytes for every thread count.
  void add_threads_option();

  /// Parses argv, then runs body; maps exceptions to exit codes and one line on stderr. A
  /// parse error is that line too ("<tool>: error: <CLI11's message>; run <tool> --help ...").
  /// What the body wrote to stdout is checked once it ends: a write the system refused (a full
  /// disk, /dev/full, a closed stdout) is exit 1, its outputs discarded.
  int run(int argc, char** argv, const std::function<void()>& body);
  /// A progress callback drawing a bar on stderr (nothing if quiet or stderr is no terminal).
  slice::Progress progress();
  /// Provenance for an output made from `input` (hash of its content). `also`: the files
  /// `input` names (a scene's meshes and DFN files): `input` and `input_sha256` then list each
  /// file after the input, separated by "; " (docs/formats.md).
  slice::Provenance provenance(const std::string& input,
                               const std::vector<std::string>& also = {}) const;
  /// A line for people on stderr (suppressed by -q); control characters escaped.
  void say(const std::string& line) const;
  /// A line said as say() does, but only once every output of the run is in place (when run()
  /// or exit_now() has renamed them): a run that fails after it ("--joints" after the VTU) never
  /// claims an output it did not write.
  void say_when_written(const std::string& line);
  const std::string& name() const { return name_; }
  /// Ends a run that succeeded at once, exit code 0: call it last in the body, once every output
  /// is written (it checks stdout and renames them into place, as run() does after the body).
  /// Freeing a million blocks one allocation at a time took 0.2-0.3 s per tool; the system takes
  /// the memory back whole. Sanitizer builds return instead, so that LeakSanitizer still checks the
  /// tools.
  void exit_now();

 private:
  std::string name_;
  std::string command_line_;
  std::unique_ptr<ProgressBar> bar_;
  std::vector<std::string> said_when_written_;

  void commit_outputs();  // checks stdout, renames the outputs, says said_when_written_
};

/// x with `digits` decimals ("0.125"), for the figures tools report.
std::string fixed(double x, int digits);
/// x with `digits` significant digits ("1.18e-05", "0.0312").
std::string sig(double x, int digits);

/// The options that set the YADE model's time step (--yade-density, --yade-young,
/// --yade-timestep-factor), for slice-export and slice-info alike.
void add_yade_timestep_options(CLI::App& cli, slice::YadeOptions& yade);

/// What sets a DEM model's time step, in one line: the smallest free block (id, volume,
/// inradius) and the smallest body that moves (a cluster's volume summed).
std::string smallest_bodies_line(const slice::DemBodies& d);

/// A file a tool reads or writes, named as the user gave it, with the option that named it.
struct PathArg {
  std::string option;  // "-o", "--joints", "geometry" (a positional argument)
  std::string path;    // empty: not given (ignored)
  bool output = true;
};

/// Refuses (Error, before anything is read or written) any two of `paths`, one of them an
/// output, that are the same file: the same name, a name through `..` or a symlink, or a hard
/// link. Two outputs on one file would leave only the last; an output on an input destroys it.
/// Also refuses an output whose directory does not exist or that names a directory, so that a
/// tool with several outputs never writes one and then fails on the next.
void check_distinct_paths(const std::vector<PathArg>& paths);

}  // namespace tool

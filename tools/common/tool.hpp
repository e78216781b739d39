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

  /// Parses argv, then runs body; maps exceptions to exit codes and one line on stderr.
  int run(int argc, char** argv, const std::function<void()>& body);
  /// A progress callback drawing a bar on stderr (nothing if quiet or stderr is no terminal).
  slice::Progress progress();
  /// Provenance for an output made from `input` (hash of its content).
  slice::Provenance provenance(const std::string& input) const;
  /// A line for people on stderr (suppressed by -q).
  void say(const std::string& line) const;
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  std::string command_line_;
  std::unique_ptr<ProgressBar> bar_;
};

/// x with `digits` decimals ("0.125"), for the figures tools report.
std::string fixed(double x, int digits);

/// Refuses to write an output over an input (a common slip that would destroy data).
void check_output_differs(const std::string& input, const std::string& output);

}  // namespace tool

#include "common/tool.hpp"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "common/progress.hpp"
#include "slice/error.hpp"
#include "slice/hash.hpp"
#include "slice/version.hpp"

namespace tool {

Tool::Tool(std::string name, const std::string& description)
    : cli(description, name), name_(std::move(name)) {
  cli.set_version_flag("--version", name_ + " (rockslice) " + slice::version());
  cli.add_flag("-q,--quiet", quiet, "no progress bar, no summary on stderr");
  cli.add_flag("-v,--verbose", verbose, "say more on stderr");
}

Tool::~Tool() = default;

int Tool::run(int argc, char** argv, const std::function<void()>& body) {
  for (int i = 0; i < argc; ++i) command_line_ += (i ? " " : "") + std::string(argv[i]);
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0 in CLI11; everything else is bad
    // input (CLI11 uses 100+ codes: map them to 1).
    const int code = cli.exit(e);
    return code == 0 ? 0 : 1;
  }
  bar_ = std::make_unique<ProgressBar>(!quiet);
  try {
    body();
    bar_->finish();
    return 0;
  } catch (const slice::Error& e) {
    bar_->finish();
    std::cerr << name_ << ": error: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    bar_->finish();
    std::cerr << name_ << ": internal error: " << e.what()
              << " (this is a bug in rockslice; please report it with the input)\n";
    return 2;
  }
}

slice::Progress Tool::progress() {
  return [this](std::string_view stage, std::size_t done, std::size_t total) {
    if (bar_) bar_->update(stage, done, total);
  };
}

slice::Provenance Tool::provenance(const std::string& input) const {
  return {name_, slice::version(), command_line_, input, slice::sha256_file(input)};
}

void Tool::say(const std::string& line) const {
  if (!quiet) std::cerr << name_ << ": " << line << '\n';
}

std::string fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

void check_output_differs(const std::string& input, const std::string& output) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(output, ec) && fs::equivalent(input, output, ec))
    throw slice::Error(output, "the output would overwrite the input", "give a different -o path");
}

}  // namespace tool

#include "common/tool.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <new>
#include <regex>
#include <streambuf>
#include <vector>

#include "common/progress.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/hash.hpp"
#include "slice/output.hpp"
#include "slice/threads.hpp"
#include "slice/version.hpp"

namespace tool {
namespace {

// SIGINT (Ctrl-C), SIGTERM (kill, a scheduler's time limit) and SIGHUP (a closed terminal):
// delete the .partial being written, then die of the same signal, as the caller expects.
extern "C" void on_signal(int sig) {
  slice::remove_partial_files();
  std::raise(sig);  // SA_RESETHAND restored the default action: the process ends by `sig`
}

// The tool's name for the crash handler's message (set once, before the handler is installed).
char g_name[64];

void write_stderr(const char* s, bool escape) {
  for (; *s; ++s) {
    const char c = escape && static_cast<unsigned char>(*s) < 0x20 ? '?' : *s;
    while (write(STDERR_FILENO, &c, 1) < 0 && errno == EINTR) {
    }
  }
}

// SIGSEGV or SIGBUS. HDF5 1.10.8 crashes on some damaged files (tests/fuzz/README.md): while a
// reader has one open, that is bad input, answered like any other (exit 1, one line, the
// .partial files gone). Any other crash is a bug and ends the process by the same signal.
extern "C" void on_crash(int sig) {
  slice::remove_partial_files();
  if (const char* file = slice::hdf5_input_being_read()) {
    write_stderr(g_name, true);
    write_stderr(": error: ", false);
    write_stderr(file, true);
    write_stderr(
        ": HDF5 crashed reading this file: it is damaged (h5dump shows where); "
        "regenerate it with the rockslice tool that made it\n",
        false);
    _exit(1);
  }
  std::raise(sig);  // SA_RESETHAND: the default action, a core dump for the bug report
}

// A failed run ends here, without the exit handlers: HDF5's own (H5_term_library) closes the
// files still open, and one a write had failed on (a full disk) crashed it (SIGSEGV in
// H5F__close_cb) after the error line. The writing driver (io/h5/write_driver.hpp) now keeps
// such failures from HDF5, so none is left open; this stays as a guard against any other.
// Every .partial is gone by now; nothing is left to flush but our streams. Sanitizer builds
// return, so that LeakSanitizer still checks.
int end_failed(int code) {
#ifndef __SANITIZE_ADDRESS__
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  std::_Exit(code);
#endif
  return code;
}

// std::cout's buffer: writes to descriptor 1 and keeps the system's reason for the first write
// it refused (std::cout's own keeps only a flag), so that slice-info --json on a full disk or on
// /dev/full ends with exit 1 and "No space left on device", not exit 0 and a truncated file.
class StdoutBuffer : public std::streambuf {
 public:
  StdoutBuffer() { setp(buf_.data(), buf_.data() + buf_.size()); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (write_out() != 0) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return write_out(); }

 private:
  // Writes what is buffered; after a refused write, what follows is dropped (the output is
  // incomplete whatever comes next) and every call fails.
  int write_out() {
    for (const char* p = pbase(); error_ == 0 && p < pptr();) {
      const ssize_t n = ::write(STDOUT_FILENO, p, std::size_t(pptr() - p));
      if (n > 0)
        p += n;
      else if (n == 0)
        error_ = EIO;
      else if (errno != EINTR)
        error_ = errno;
    }
    setp(buf_.data(), buf_.data() + buf_.size());
    return error_ == 0 ? 0 : -1;
  }

  std::array<char, 1 << 16> buf_{};
  int error_ = 0;
};

// Set once by route_stdout: the buffer (never freed: std::cout may be flushed at exit) and
// whether the tool was started with descriptor 1 closed (">&-").
StdoutBuffer* g_stdout = nullptr;
bool g_stdout_closed = false;

// A closed descriptor 0, 1 or 2 would be taken by the next file opened (an output's .partial
// as descriptor 1 would receive what is printed): each is opened on /dev/null first, 1 read-only
// so that a write to stdout fails (EBADF) and is reported. Then std::cout writes through
// StdoutBuffer.
void route_stdout() {
  if (g_stdout) return;
  for (const int fd : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO}) {
    if (::fcntl(fd, F_GETFD) >= 0 || errno != EBADF) continue;
    const int opened = ::open("/dev/null", fd == STDERR_FILENO ? O_WRONLY : O_RDONLY);
    if (opened >= 0 && opened != fd) {  // not the lowest free one: cannot happen, but be sure
      ::dup2(opened, fd);
      ::close(opened);
    }
    if (fd == STDOUT_FILENO) g_stdout_closed = true;
  }
  g_stdout = new StdoutBuffer;
  std::cout.rdbuf(g_stdout);
}

// Throws Error if a write to stdout was refused (flushing what is left first).
void check_stdout() {
  std::cout.flush();
  if (!g_stdout || (g_stdout->error() == 0 && std::cout)) return;
  if (g_stdout_closed)
    throw slice::Error("stdout", "cannot write to it: it is closed (the tool was started with >&-)",
                       "give the tool a stdout (>/dev/null to drop what it prints)");
  // The fix for the system's reason: under ulimit -f (EFBIG) more room on the disk would not help.
  const int e = g_stdout->error();
  throw slice::Error(
      "stdout",
      "cannot write to it" + (e != 0 ? " (" + std::string(std::strerror(e)) + ")" : std::string()),
      (e != 0 ? slice::write_error_fix(e) : std::string("send it elsewhere")) +
          "; what was written there is incomplete");
}

// CLI11's message for a parse error as one line: control characters escaped, at most 300
// characters, and CLI11's ranges of positive numbers ("Value 0 not in range 0.000000 to
// 1797...(309 digits).000000") said in words.
std::string parse_error_line(const std::string& what) {
  static const std::regex huge_range("Value (.*) not in range \\S+ to [0-9]{30,}\\.[0-9]+");
  std::string line =
      std::regex_replace(slice::escape_control(what), huge_range, "$1 is not a positive number");
  if (line.size() > 300) line = line.substr(0, 297) + "...";
  if (line.size() > 1 && std::isupper(static_cast<unsigned char>(line[0])) &&
      std::islower(static_cast<unsigned char>(line[1])))
    line[0] = char(std::tolower(static_cast<unsigned char>(line[0])));
  return line;
}

void install_signal_handlers(const std::string& name) {
  std::snprintf(g_name, sizeof g_name, "%s", name.c_str());
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
  // The crash handler runs on its own stack, so that it also runs when the stack is the fault.
  static std::vector<char> alt(std::max<std::size_t>(SIGSTKSZ, 64 * 1024));
  stack_t ss{};
  ss.ss_sp = alt.data();
  ss.ss_size = alt.size();
  sigaltstack(&ss, nullptr);
  sa.sa_handler = on_crash;
  sa.sa_flags = SA_RESETHAND | SA_ONSTACK;
  for (const int sig : {SIGSEGV, SIGBUS}) sigaction(sig, &sa, nullptr);
  // A file size limit (ulimit -f) kills a process writing past it by SIGXFSZ, with no word and
  // the .partial left: ignored, the write fails with EFBIG ("File too large") and the writer
  // reports it with the fix for that reason (slice::write_error_fix: raise the limit).
  std::signal(SIGXFSZ, SIG_IGN);
}

}  // namespace

Tool::Tool(std::string name, const std::string& description)
    : cli(description, name), name_(std::move(name)) {
  cli.set_version_flag("--version", name_ + " (rockslice) " + slice::version());
  cli.add_flag("-q,--quiet", quiet, "no progress bar, no summary on stderr");
  cli.add_flag("-v,--verbose", verbose, "say more on stderr");
}

Tool::~Tool() = default;

void Tool::add_compress_option() {
  cli.add_flag("--compress", compress,
               "deflate the output's datasets (with shuffle): about 2-3x smaller, slower to write; "
               "any HDF5 reader reads it");
}

void Tool::add_threads_option() {
  cli.add_option("--threads", threads, "threads to run on (default: all cores)")
      ->check(CLI::PositiveNumber);
}

int Tool::run(int argc, char** argv, const std::function<void()>& body) {
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads" && i + 1 < argc) {  // not provenance: see add_threads_option
      ++i;
      continue;
    }
    if (a.rfind("--threads=", 0) == 0) continue;
    command_line_ += (command_line_.empty() ? "" : " ") + a;
  }
  route_stdout();
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with exit code 0 in CLI11; everything else is bad
    // input (CLI11 uses 100+ codes, and prints two lines without the tool's name): one line.
    if (e.get_exit_code() != 0) {
      std::cerr << name_ << ": error: " << parse_error_line(e.what()) << "; run " << name_
                << " --help for the options\n";
      return 1;
    }
    cli.exit(e);
    try {
      check_stdout();
    } catch (const slice::Error& error) {
      std::cerr << name_ << ": error: " << error.what() << '\n';
      return 1;
    }
    return 0;
  }
  install_signal_handlers(name_);
  bar_ = std::make_unique<ProgressBar>(!quiet);
  // Every output of the run is renamed into place together, once all are complete: a failure
  // (a full disk on the second output) leaves every existing output as it was.
  slice::hold_commits();
  try {
    slice::with_threads(threads, body);  // --threads bounds the readers' checks too
    commit_outputs();
    return 0;
  } catch (const slice::Error& e) {
    slice::discard_held_outputs();
    bar_->finish();
    std::cerr << name_ << ": error: " << e.what() << '\n';
    return end_failed(1);
  } catch (const std::bad_alloc&) {
    // Not a bug: the input asks for more than this machine has (the outputs' .partial files are
    // gone, an existing output is untouched).
    slice::discard_held_outputs();
    bar_->finish();
    std::cerr << name_
              << ": error: out of memory: the input needs more memory than this machine has; "
                 "make the job smaller (fewer joints, a smaller domain or a larger spacing, a "
                 "lower max_blocks) or run it on a machine with more memory\n";
    return end_failed(1);
  } catch (const std::exception& e) {
    slice::discard_held_outputs();
    bar_->finish();
    std::cerr << name_ << ": internal error: " << slice::escape_control(e.what())
              << " (this is a bug in rockslice; please report it with the input)\n";
    return end_failed(2);
  }
}

slice::Progress Tool::progress() {
  return [this](std::string_view stage, std::size_t done, std::size_t total) {
    if (bar_) bar_->update(stage, done, total);
  };
}

slice::Provenance Tool::provenance(const std::string& input,
                                   const std::vector<std::string>& also) const {
  slice::Provenance p{name_, slice::version(), command_line_, input, slice::sha256_file(input)};
  for (const std::string& file : also) slice::add_input(p, file);
  return p;
}

void Tool::commit_outputs() {
  check_stdout();                // a refused write to stdout fails the run, as a refused file
  slice::commit_held_outputs();  // may throw Error: the run then fails as any other
  bar_->finish();
  for (const std::string& line : said_when_written_) say(line);
  said_when_written_.clear();
}

void Tool::exit_now() {
  commit_outputs();
#ifndef __SANITIZE_ADDRESS__
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  std::_Exit(0);
#endif
}

void Tool::say(const std::string& line) const {
  if (!quiet) std::cerr << name_ << ": " << slice::escape_control(line) << '\n';
}

void Tool::say_when_written(const std::string& line) { said_when_written_.push_back(line); }

std::string fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

std::string sig(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

void add_yade_timestep_options(CLI::App& cli, slice::YadeOptions& yade) {
  cli.add_option("--yade-density", yade.density, "yade: rock density [kg/m3]")
      ->capture_default_str();
  cli.add_option("--yade-young", yade.young, "yade: contact stiffness (PolyhedraMat.young)")
      ->capture_default_str();
  cli.add_option("--yade-timestep-factor", yade.timestep_factor,
                 "yade: time step as a fraction of the critical one")
      ->capture_default_str();
}

std::string smallest_bodies_line(const slice::DemBodies& d) {
  std::string s = std::to_string(d.bodies) + " rigid bodies (" + std::to_string(d.clumps) +
                  " clumps, " + std::to_string(d.fixed) + " fixed); smallest free block: ";
  s += d.free_block < 0 ? std::string("none")
                        : std::to_string(d.free_block) + " (volume " + sig(d.free_volume, 4) +
                              ", inradius " + sig(d.free_inradius, 4) + ")";
  s += "; smallest moving body: ";
  if (d.moving_block < 0) return s + "none";
  s += d.moving_cluster < 0 ? "block " + std::to_string(d.moving_block)
                            : "cluster " + std::to_string(d.moving_cluster) + " (first block " +
                                  std::to_string(d.moving_block) + ")";
  return s + ", volume " + sig(d.moving_volume, 4);
}

void check_distinct_paths(const std::vector<PathArg>& paths) {
  namespace fs = std::filesystem;
  // The file a name stands for: its own symlinks followed even when they dangle (an output
  // that does not exist yet), then the directories' symlinks and "..".
  const auto resolved = [](const std::string& name) {
    std::error_code ec;
    fs::path p = fs::absolute(name);
    for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
      const fs::path target = fs::read_symlink(p, ec);
      if (ec) break;
      p = target.is_absolute() ? target : p.parent_path() / target;
    }
    const fs::path r = fs::weakly_canonical(p, ec);
    return ec ? p.lexically_normal() : r;
  };
  for (const PathArg& p : paths) {
    if (p.path.empty() || !p.output) continue;
    // Every output's place is checked before any is written: a tool with two outputs must not
    // write the first and then fail on the second.
    slice::check_output_place(p.path, p.option);
  }
  for (std::size_t i = 0; i < paths.size(); ++i) {
    for (std::size_t k = i + 1; k < paths.size(); ++k) {
      const PathArg& a = paths[i];
      const PathArg& b = paths[k];
      if (a.path.empty() || b.path.empty() || (!a.output && !b.output)) continue;
      std::error_code ec;
      const bool same = resolved(a.path) == resolved(b.path) || fs::equivalent(a.path, b.path, ec);
      if (!same) continue;
      const PathArg& out = b.output ? b : a;
      const PathArg& other = b.output ? a : b;
      throw slice::Error(out.path,
                         out.option + " and " + other.option + " (" + other.path +
                             ") are the same file: " +
                             (other.output ? "the second output would replace the first"
                                           : "the output would overwrite the input"),
                         "give " + out.option + " a different path; nothing was written");
    }
  }
}

}  // namespace tool

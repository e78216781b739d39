#pragma once
// The fuzz targets whose code under test reads a file (fuzz_h5, fuzz_obj, fuzz_stl, fuzz_fab,
// fuzz_csv, fuzz_asc, fuzz_export): the input is written to one file per process in the
// temporary directory ($TMPDIR; libFuzzer's -jobs and -fork run several processes), removed at
// exit.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace fuzz {

/// A file name of this process: "<tmp>/rockslice-fuzz-<pid>-<name>", removed at exit.
inline std::filesystem::path scratch_path(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("rockslice-fuzz-" + std::to_string(::getpid()) + "-" + name);
}

/// The file the input goes to; set once by LLVMFuzzerInitialize (set_input_name).
inline std::filesystem::path& input_path() {
  static std::filesystem::path path;
  return path;
}

inline void remove_input() {
  std::error_code ec;
  std::filesystem::remove(input_path(), ec);
}

/// Names the input file `name` (its extension matters to read_mesh) and removes it at exit.
inline void set_input_name(const std::string& name) {
  input_path() = scratch_path(name);
  std::atexit(remove_input);
}

/// Writes the input to input_path(); the harness stops loudly if it cannot.
inline const std::filesystem::path& write_input(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = input_path();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  if (std::fclose(f) != 0) std::abort();
  return path;
}

/// Stops the run as a finding: `what` on stderr, then abort (libFuzzer saves the input).
[[noreturn]] inline void finding(const std::string& target, const std::string& what) {
  std::fprintf(stderr, "%s: %s\n", target.c_str(), what.c_str());
  std::abort();
}

}  // namespace fuzz

// libFuzzer target: the HDF5 readers. The input is written to a temporary file, which
// slice::read_header, slice::read_joints and slice::read_blocks then read (each tool reads its
// input with one of them). slice::Error (bad input, exit 1 in the tools) is the expected answer
// to a damaged file; any other exception, a crash, a sanitizer report, a timeout or running out
// of memory is a finding.
//
// The HDF5 library itself is not instrumented (Debian's build): coverage guides the fuzzer
// through our readers' checks, and a crash inside libhdf5 shows as a plain SEGV with HDF5
// frames on the stack. HDF5 1.10.8 leaks a few bytes on some damaged files (e.g. 56 bytes per
// H5Fopen of a file whose root object header is corrupt, under H5G_mkroot); .ci/fuzz
// suppresses leaks allocated inside libhdf5 (tests/fuzz/lsan.supp). Ours would not show there
// anyway: an identifier we forget to close keeps its memory reachable from HDF5's tables. So
// after each input the harness checks that no HDF5 object is left open.
#include <hdf5.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "slice/error.hpp"
#include "slice/h5io.hpp"

namespace {

std::filesystem::path& input_path() {
  static std::filesystem::path path;
  return path;
}

void remove_input() {
  std::error_code ec;
  std::filesystem::remove(input_path(), ec);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  // One file per process (libFuzzer's -jobs/-fork run several), removed at exit.
  input_path() = std::filesystem::temp_directory_path() /
                 ("rockslice-fuzz-h5-" + std::to_string(::getpid()) + ".h5");
  std::atexit(remove_input);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = input_path();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();  // the harness cannot work: stop loudly
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  if (std::fclose(f) != 0) std::abort();
  try {
    (void)slice::read_header(path);
  } catch (const slice::Error&) {
  }
  try {
    (void)slice::read_joints(path);
  } catch (const slice::Error&) {
  }
  try {
    (void)slice::read_blocks(path);
  } catch (const slice::Error&) {
  }
  const ssize_t open = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
  if (open != 0) {
    std::fprintf(stderr, "fuzz_h5: %zd HDF5 objects left open after reading the input\n", open);
    std::abort();
  }
  return 0;
}

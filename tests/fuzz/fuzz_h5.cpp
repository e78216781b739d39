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

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  fuzz::set_input_name("h5.h5");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = fuzz::write_input(data, size);
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
  if (open != 0)
    fuzz::finding("fuzz_h5", std::to_string(open) + " HDF5 objects left open after reading");
  return 0;
}

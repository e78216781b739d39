#pragma once
// The HDF5 file driver (VFD) every rockslice file is written with: HDF5's default (sec2) driver
// in behaviour and in the bytes it writes, but for one thing: a write the system refuses (a full
// disk: ENOSPC; a quota; an I/O error) is not reported to HDF5. The driver records the first
// such failure in a WriteFailure, skips every write after it, and tells HDF5 each write went
// well; the h5 wrapper (h5.cpp) checks the record after its writes and when it closes the file,
// and throws the system's error.
//
// Why: HDF5 1.10 cannot close a file whose final flush failed. H5Fclose then fails and leaves the
// file open in HDF5's table, and HDF5's clean-up at exit (H5_term_library) crashes on it
// (SIGSEGV in H5F__close_cb): a Python script that caught the error of a save to a full disk
// ended with a segmentation fault. With nothing failing under HDF5, the file closes as any other;
// its content no longer matters, since the .partial it was written to is removed.
//
// Only io/h5/h5.cpp uses it (File::create). No <hdf5.h> here.
#include <cstdint>

namespace slice::h5 {

/// What the writing driver saw of one file: the errno of the first write or truncation the
/// system refused (0: none).
struct WriteFailure {
  int error = 0;
};

/// A new file access property list (the caller closes it) that selects the writing driver,
/// recording failures in *failure, which must outlive the file. Negative on failure. The driver
/// is registered with HDF5 on the first call.
std::int64_t writing_fapl(WriteFailure* failure);

}  // namespace slice::h5

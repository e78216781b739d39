#pragma once
// A read-only HDF5 file driver (VFD) that checks, before HDF5 trusts them, the parts of a file
// on which HDF5 1.10 can be made to loop without end.
//
// HDF5 reads a local heap (the name store of an old-style group) by walking the heap's list of
// free blocks, allocating a node per block, until the list ends. Nothing there stops a list that
// loops: a damaged file then makes any name lookup allocate until the machine runs out of memory
// (found by fuzz_h5: 16.9 GB in one H5Lexists, tests/fuzz/regressions/hdf5-hang/). This driver
// reads the file with pread like HDF5's default (sec2) driver, and when HDF5 reads a local heap
// it first walks that heap's free list itself, bounded by the heap's size: a list with more
// blocks than the heap can hold (a loop, or blocks that overlap) fails the read, which HDF5 then
// reports as an error of the call that wanted the heap.
//
// Only io/h5/h5.cpp uses it (File::open without writable). No <hdf5.h> here.
#include <cstdint>

namespace slice::h5 {

/// A file access property list that selects the checked driver; owned by the driver (do not
/// close it). The driver is registered with HDF5 on the first call.
std::int64_t checked_read_fapl();

}  // namespace slice::h5

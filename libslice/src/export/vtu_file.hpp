#pragma once
// A VTK XML unstructured-grid file written as it is made (VTK 9's file format, version 1.0):
// the XML header first, with every array's offset left blank, then the arrays' data one after
// the other in the appended section, each compressed in blocks of 32 KiB as they come (blocks
// compressed in parallel, batch by batch, while the caller makes the next batch), then the
// offsets filled in. Memory: two batches, not the grid. The same values give the same bytes, on
// any number of threads.
#include <oneapi/tbb/task_group.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "slice/export_vtu.hpp"

namespace slice::vtu {

/// A DataArray of the header: VTK type name ("Int64", "Float64", "UInt8", "Int32"), name,
/// components; the range is optional (ParaView shows it before reading the data).
struct ArraySpec {
  ArraySpec(const char* type_, std::string name_, int components_ = 1, bool id_type_ = false,
            std::string range_min_ = {}, std::string range_max_ = {})
      : type(type_),
        name(std::move(name_)),
        components(components_),
        id_type(id_type_),
        range_min(std::move(range_min_)),
        range_max(std::move(range_max_)) {}
  const char* type;
  std::string name;
  int components;
  bool id_type;  // IdType="1": the faces / faceoffsets arrays of polyhedra
  std::string range_min, range_max;
};

class File {
 public:
  /// Opens `path` for writing (the caller's .partial); `what` names the output in errors.
  File(const std::filesystem::path& path, std::string what, VtuCompressor compressor);
  ~File();
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  /// The header: points and cells of the piece, then its sections (CellData, Points, Cells),
  /// each a list of arrays whose data must then come in that order. `scalars`: the active
  /// cell scalars ("" for none).
  struct Section {
    std::string tag;  // "CellData", "Points", "Cells"
    std::vector<ArraySpec> arrays;
  };
  void header(std::size_t points, std::size_t cells, const std::vector<Section>& sections,
              const std::string& scalars);

  /// The next array's data: begin with its size in bytes, put exactly that many, end.
  void begin_array(std::size_t bytes);
  void put(const void* data, std::size_t bytes);
  void end_array();

  /// Writes the footer and the offsets, closes the file. Throws Error if any write failed.
  void finish();

 private:
  void write(const void* data, std::size_t bytes);
  void flush_blocks(bool last);
  void land();
  void seek_write(std::int64_t at, const void* data, std::size_t bytes);

  // The FILE's buffer, ours: glibc's setvbuf with a null buffer keeps its 4 KiB one (33,000
  // write calls for a 300 MB VTU), whatever the size asked. Closed before it goes (~File,
  // finish).
  std::unique_ptr<char[]> buffer_;
  std::FILE* f_ = nullptr;
  std::string what_;
  VtuCompressor compressor_;
  std::vector<std::int64_t> offset_slots_;  // file positions of each array's offset="..."
  std::vector<std::uint64_t> offsets_;      // each array's offset in the appended data
  std::int64_t appended_start_ = 0;         // file position after the '_'
  // The array being written.
  std::size_t array_ = 0, expected_ = 0, received_ = 0;
  std::int64_t array_header_at_ = 0;
  std::vector<std::uint64_t> block_sizes_;  // compressed size of each block written so far
  std::vector<unsigned char> pending_;      // raw bytes not yet compressed
  // A batch being compressed (a task of `compressing_`, on the caller's arena) while the caller
  // makes the next one, and the batch before it, compressed, being written meanwhile: raw bytes
  // and compressed blocks of each, alternating.
  struct Batch {
    std::vector<unsigned char> raw;
    std::vector<std::vector<unsigned char>> blocks;
  };
  Batch batches_[2];
  void write_batch(const Batch& b);
  std::size_t flying_ = 0;  // batches_[flying_ - 1]: the one in flight (0: none)
  tbb::task_group compressing_;
};

}  // namespace slice::vtu

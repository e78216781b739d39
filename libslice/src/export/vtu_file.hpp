#pragma once
// A VTK XML unstructured-grid file written as it is made (VTK 9's file format, version 1.0):
// each array's data inline, in its DataArray element, base64-encoded (format="binary"), so the
// file is well-formed XML from end to end. Raw appended data is not: the expat of an up-to-date
// Debian 12 (2.5.0-1+deb12u5, with expat 2.6's reparse deferral) stops VTK 9.1's and ParaView
// 5.11's reader at it (VTK issue 19258), and base64 appended data fails there the same way (the
// reader stops feeding expat at <AppendedData>); inline data reads with every expat. The data
// are compressed in blocks of 32 KiB as they come (blocks compressed in parallel, batch by
// batch, while the caller makes the next batch); a compressed array's header (its block sizes)
// is base64 of its own before the blocks' base64, left blank and filled in when the array ends.
// Memory: two batches, not the grid. The same values give the same bytes, on any number of
// threads.
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

  /// The layout: points and cells of the piece, then its sections (CellData, Points, Cells),
  /// each a list of arrays whose data must then come in that order. `scalars`: the active
  /// cell scalars ("" for none). The XML is written around the data as they come.
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
  std::vector<std::string> opening_;  // the XML before each array's data
  std::string closing_;               // the XML after the last array's data
  // The array being written.
  std::size_t array_ = 0, expected_ = 0, received_ = 0;
  std::int64_t array_header_at_ = 0;  // file position of a compressed array's header
  // Base64 of the array's bytes as they go to the file: 0-2 bytes waiting for a triplet.
  unsigned char carry_[2] = {};
  std::size_t carried_ = 0;
  std::string encoded_;  // reused buffer of the encoded text
  void write_encoded(const unsigned char* data, std::size_t bytes);
  void end_encoded();
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

#pragma once
// A thin RAII wrapper over the HDF5 C API (1.10): the only code in rockslice that calls H5*.
// Every identifier is owned by a Handle and closed on destruction; every call is checked and a
// failure becomes slice::Error("<file>", "<what> (HDF5: <reason>)", "<fix>"). HDF5's own error
// printing is switched off. This header does not include <hdf5.h>, so code using the wrapper
// (io/*_file.cpp, tests that craft bad files) needs no HDF5 include path.
//
// Files are reproducible: no time stamps (obj_track_times off on every group and dataset),
// contiguous storage (chunked where a dataset grows) and no filters (unless Context::compress),
// the library's default format bounds. On disk, floats are IEEE little-endian 64-bit, integers
// little-endian of the C++ type's width, strings fixed-length null-terminated UTF-8.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "write_driver.hpp"

namespace slice::h5 {

namespace fs = std::filesystem;

/// HDF5 prints its error stack to stderr unless told not to, once per thread: a thread other
/// than the one that opened the file calls this before its first HDF5 call.
void silence_thread();

/// The HDF5 objects (files, groups, datasets, ...) open in this process: 0 once every file is
/// closed, also after a write that failed (tests).
std::size_t open_objects();

/// hid_t of HDF5 1.10 (h5.cpp checks they agree).
using Id = std::int64_t;

/// Which file a handle belongs to and what to tell the user when something fails.
struct Context {
  std::string file;  // the name in messages (the user's output path, not the .partial)
  std::string fix;   // the fix in messages
  /// Writing: datasets chunked, shuffled and deflated (level 4), not contiguous and plain.
  bool compress = false;
  /// Writing: what the file's driver saw (write_driver.hpp), shared by every handle of the file;
  /// a write the system refused is reported by the wrapper's next write or by File::close.
  std::shared_ptr<WriteFailure> written = nullptr;
};

/// Owns one HDF5 identifier and closes it with the matching H5*close.
class Handle {
 public:
  enum class Type { file, group, dataset, dataspace, attribute, datatype, plist };
  Handle() = default;
  Handle(Id id, Type type) : id_(id), type_(type) {}
  ~Handle() { reset(); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), type_(o.type_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept;
  Id id() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Closes now; returns false if HDF5 reported an error.
  bool reset() noexcept;

 private:
  Id id_ = -1;
  Type type_ = Type::file;
};

/// A dataset written in consecutive runs of rows, so that a writer never holds the whole of it:
/// of known shape (Group::create_rows; every row must be written before finish()), or growing
/// by whole chunks as rows come (Group::create_growing_rows).
template <class T>
class RowWriter {
 public:
  /// Writes the next rows: data.size() must be a multiple of the columns. A growing dataset
  /// keeps the rows short of a whole chunk until more come or finish().
  void append(std::span<const T> data);
  /// Checks that every row was written (writes a growing dataset's last rows) and closes it.
  void finish();

 private:
  friend class Group;
  RowWriter(Handle ds, std::size_t rows, std::size_t cols, int rank, std::string path, Context ctx,
            std::size_t chunk_rows = 0)
      : ds_(std::move(ds)),
        rows_(rows),
        cols_(cols),
        rank_(rank),
        chunk_rows_(chunk_rows),
        path_(std::move(path)),
        ctx_(std::move(ctx)) {}
  void write_rows(const T* data, std::size_t rows);
  Handle ds_;
  std::size_t rows_, cols_;
  int rank_;
  std::size_t chunk_rows_;  // growing: rows per chunk; 0: known shape
  std::size_t next_ = 0;
  std::vector<T> pending_;  // growing: rows short of a whole chunk
  std::string path_;
  Context ctx_;
};

/// A dataset read in runs of rows (Group::open_rows), into the caller's memory: a reader need
/// not hold a copy of the whole of it. Its type, shape and stored size are checked on opening.
template <class T>
class RowReader {
 public:
  std::size_t rows() const { return rows_; }
  /// Reads rows [first, first + count) into `out` (count times the columns of T).
  void read(std::size_t first, std::size_t count, T* out) const;

 private:
  friend class Group;
  RowReader(Handle ds, std::size_t rows, std::size_t cols, int rank, std::string path, Context ctx)
      : ds_(std::move(ds)),
        rows_(rows),
        cols_(cols),
        rank_(rank),
        path_(std::move(path)),
        ctx_(std::move(ctx)) {}
  Handle ds_;
  std::size_t rows_, cols_;
  int rank_;
  std::string path_;
  Context ctx_;
};

/// A group (or the root group of a file). Member names are relative ("normal"); messages use
/// full paths ("/joints/normal").
class Group {
 public:
  const std::string& path() const { return path_; }
  /// Full path of a member, e.g. "/joints/normal".
  std::string member_path(const std::string& name) const;
  const Context& context() const { return ctx_; }

  Group create_group(const std::string& name) const;
  /// Throws Error ("missing group /sets/003") if there is no such group.
  Group open_group(const std::string& name) const;
  bool exists(const std::string& name) const;
  bool has_attribute(const std::string& name) const;
  /// Number of links (groups and datasets) in this group.
  std::size_t member_count() const;
  /// Unlinks a member (tests use it to craft bad files).
  void remove(const std::string& name) const;
  void remove_attribute(const std::string& name) const;

  /// Writes a 1-D dataset (n) of T. T: double, int64, int32, uint8, int8.
  template <class T>
  void write(const std::string& name, std::span<const T> data) const;
  /// Writes a 2-D dataset (data.size() / cols, cols), row-major. An empty span gives (0, cols).
  template <class T>
  void write(const std::string& name, std::span<const T> data, std::size_t cols) const;
  /// Creates a dataset of `rows` rows to be written by RowWriter::append: 1-D if cols is 0,
  /// else (rows, cols).
  template <class T>
  RowWriter<T> create_rows(const std::string& name, std::size_t rows, std::size_t cols) const;
  /// Creates a dataset of unknown length (chunked, extendible: 1-D if cols is 0) that grows by
  /// whole chunks as RowWriter::append gives rows, its chunks sized for about `expected_rows`
  /// rows (at most 4 MiB each, 256 kB if compressed). Chunks are written whole, in order, as rows
  /// complete them.
  template <class T>
  RowWriter<T> create_growing_rows(const std::string& name, std::size_t cols,
                                   std::size_t expected_rows) const;
  /// Reads a 1-D dataset, checking that it exists, has rank 1 and a type that converts to T
  /// without loss (float for double, an integer that fits for integers).
  template <class T>
  std::vector<T> read(const std::string& name) const;
  /// Reads a 2-D dataset that must have `cols` columns; rows = size() / cols.
  template <class T>
  std::vector<T> read(const std::string& name, std::size_t cols) const;
  /// Opens a dataset to be read by RowReader::read, with the checks of read(): 1-D if cols is
  /// 0, else (rows, cols).
  template <class T>
  RowReader<T> open_rows(const std::string& name, std::size_t cols) const;

  /// Scalar attributes. T: std::string, std::int64_t, std::uint64_t, double. Writing an
  /// attribute that exists is an error (remove it first); a string must not contain '\0'.
  template <class T>
  void write_attribute(const std::string& name, const T& value) const;
  /// Reads a scalar attribute, checking that it exists and has a matching type class (string,
  /// integer that fits, float). Strings must be fixed-length.
  template <class T>
  T read_attribute(const std::string& name) const;

  /// "root attribute kind" or "/options attribute order", for messages.
  std::string attribute_label(const std::string& name) const;

 private:
  friend class File;
  Group(Handle h, std::string path, Context ctx)
      : handle_(std::move(h)), path_(std::move(path)), ctx_(std::move(ctx)) {}
  [[noreturn]] void fail(const std::string& what) const;
  Handle handle_;
  std::string path_;
  Context ctx_;
};

// Marks `path` as the HDF5 file being read (slice::hdf5_input_being_read) while alive.
class ReadingMark {
 public:
  ReadingMark() = default;
  explicit ReadingMark(const std::string& path);
  ReadingMark(ReadingMark&& other) noexcept : path_(std::move(other.path_)) {}
  ReadingMark& operator=(ReadingMark&&) = delete;
  ~ReadingMark();

 private:
  std::unique_ptr<char[]> path_;  // not a std::string: its characters must not move with it
};

/// An open HDF5 file. Closing it explicitly (close()) reports errors of the final flush; the
/// destructor closes silently.
class File {
 public:
  /// Creates (truncates) `path`; messages name `ctx.file`.
  static File create(const fs::path& path, Context ctx);
  /// Opens an existing file read-only (or read-write, for tests that craft bad files). Throws
  /// Error if it does not exist or is not an HDF5 file.
  static File open(const fs::path& path, Context ctx, bool writable = false);

  const Group& root() const { return root_; }
  /// Closes the file, throwing Error if HDF5 fails to flush or close it.
  void close();

 private:
  File(Handle file, Group root, ReadingMark mark = {})
      : mark_(std::move(mark)),
        written_(root.ctx_.written),
        file_(std::move(file)),
        root_(std::move(root)) {}
  ReadingMark mark_;                       // destroyed last: HDF5 reads until the file is closed
  std::shared_ptr<WriteFailure> written_;  // outlives file_: its driver writes to it
  Handle file_;
  Group root_;  // closed before file_ (members are destroyed in reverse order)
};

}  // namespace slice::h5

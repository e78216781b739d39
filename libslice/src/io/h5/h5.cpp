#include "h5.hpp"

#include <hdf5.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <system_error>
#include <type_traits>

#include "checked_driver.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/output.hpp"
#include "write_driver.hpp"

namespace slice::h5 {

static_assert(std::is_same_v<Id, hid_t>, "h5::Id must be HDF5's hid_t");

namespace {

// --- errors ----------------------------------------------------------------------------------

// HDF5's own printing goes to stderr, which the library never writes to. Idempotent; per thread
// in a thread-safe HDF5 (Debian's), so a thread that calls HDF5 calls it too (silence_thread).
void silence() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// Called by HDF5's C code: nothing may be thrown through it (out of memory ends the walk).
herr_t collect(unsigned /*n*/, const H5E_error2_t* e, void* data) noexcept {
  try {
    auto& descs = *static_cast<std::vector<std::string>*>(data);
    if (e != nullptr && e->desc != nullptr && e->desc[0] != '\0') descs.emplace_back(e->desc);
    return 0;
  } catch (...) {
    return -1;
  }
}

// The outermost and innermost descriptions on HDF5's error stack, e.g. " (HDF5: unable to open
// file: file signature not found)"; empty if the stack is empty. Clears the stack.
std::string reason() {
  std::vector<std::string> descs;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect, &descs);
  H5Eclear2(H5E_DEFAULT);
  if (descs.empty()) return {};
  // A failed write or read carries the system's error (errno, its message, buffers, a time
  // stamp): say just what the system said.
  for (const std::string& d : descs)
    if (const auto at = d.find("error message = '"); at != std::string::npos) {
      const auto from = at + 17, to = d.find('\'', from);
      if (to != std::string::npos) return " (" + d.substr(from, to - from) + ")";
    }
  std::string r = descs.front();
  if (descs.size() > 1 && descs.back() != descs.front()) r += ": " + descs.back();
  return " (HDF5: " + r + ")";
}

[[noreturn]] void fail(const Context& ctx, const std::string& what) {
  throw Error(ctx.file, what, ctx.fix);
}

// A failed HDF5 call: the message carries HDF5's reason.
[[noreturn]] void fail_h5(const Context& ctx, const std::string& what) {
  throw Error(ctx.file, what + reason(), ctx.fix);
}

// A write the system refused since the file was created (write_driver.hpp): HDF5 was told it went
// well, so the call that made it (or a later one, where HDF5 wrote from its caches) succeeded.
void check_written(const Context& ctx, const std::string& what) {
  if (ctx.written && ctx.written->error != 0)  // the fix for that reason: ulimit -f, a full disk
    throw Error(ctx.file, what + " (" + std::strerror(ctx.written->error) + ")",
                write_error_fix(ctx.written->error) + "; nothing was written");
}

// Checks the result of an H5* call: ids and herr_t/htri_t are negative on failure.
template <class R>
R check(R r, const Context& ctx, const std::string& what) {
  if (r < 0) fail_h5(ctx, what);
  return r;
}

Handle own(hid_t id, Handle::Type type, const Context& ctx, const std::string& what) {
  return Handle(check(id, ctx, what), type);
}

// --- types -----------------------------------------------------------------------------------

// On-disk (little-endian, fixed width) and in-memory types of each element type.
template <class T>
struct Traits;
template <>
struct Traits<double> {
  static hid_t file() { return H5T_IEEE_F64LE; }
  static hid_t mem() { return H5T_NATIVE_DOUBLE; }
};
template <>
struct Traits<std::int64_t> {
  static hid_t file() { return H5T_STD_I64LE; }
  static hid_t mem() { return H5T_NATIVE_INT64; }
};
template <>
struct Traits<std::uint64_t> {
  static hid_t file() { return H5T_STD_U64LE; }
  static hid_t mem() { return H5T_NATIVE_UINT64; }
};
template <>
struct Traits<std::int32_t> {
  static hid_t file() { return H5T_STD_I32LE; }
  static hid_t mem() { return H5T_NATIVE_INT32; }
};
template <>
struct Traits<std::uint8_t> {
  static hid_t file() { return H5T_STD_U8LE; }
  static hid_t mem() { return H5T_NATIVE_UINT8; }
};
template <>
struct Traits<std::int8_t> {
  static hid_t file() { return H5T_STD_I8LE; }
  static hid_t mem() { return H5T_NATIVE_INT8; }
};

template <class T>
std::string expected_type() {
  if constexpr (std::is_same_v<T, std::string>) {
    return "a string";
  } else if constexpr (std::is_floating_point_v<T>) {
    return "floats of at most 128 bits";
  } else {
    return std::string(std::is_signed_v<T> ? "signed " : "unsigned ") +
           std::to_string(8 * sizeof(T)) + "-bit integers";
  }
}

// "unsigned 8-bit integers", "64-bit floats", "strings", ...
std::string describe(hid_t type) {
  const std::string bits = std::to_string(8 * H5Tget_size(type)) + "-bit ";
  switch (H5Tget_class(type)) {
    case H5T_INTEGER:
      return (H5Tget_sign(type) == H5T_SGN_2 ? "signed " : "unsigned ") + bits + "integers";
    case H5T_FLOAT:
      return bits + "floats";
    case H5T_STRING:
      return "strings";
    case H5T_COMPOUND:
      return "compound values";
    case H5T_ENUM:
      return "enumeration values";
    default:
      return "values of an unexpected type";
  }
}

// Whether a stored type converts to T without loss: any float for double; for integers, the
// stored range must fit in T (HDF5 would otherwise clip silently).
template <class T>
bool converts(hid_t type) {
  const H5T_class_t c = H5Tget_class(type);
  if constexpr (std::is_same_v<T, std::string>) {
    return c == H5T_STRING;
  } else if constexpr (std::is_floating_point_v<T>) {
    // Up to quadruple precision; a damaged type of 4 GB per value would make H5Dread allocate
    // a conversion buffer of that many GB (a fuzz finding).
    return c == H5T_FLOAT && H5Tget_size(type) <= 16;
  } else {
    if (c != H5T_INTEGER) return false;
    const std::size_t size = H5Tget_size(type);
    const bool is_signed = H5Tget_sign(type) == H5T_SGN_2;
    if (is_signed == std::is_signed_v<T>) return size <= sizeof(T);
    return !is_signed && size < sizeof(T);
  }
}

// A fixed-length, null-terminated UTF-8 string type holding `chars` characters.
Handle string_type(std::size_t chars, const Context& ctx) {
  Handle t = own(H5Tcopy(H5T_C_S1), Handle::Type::datatype, ctx, "cannot make a string type");
  check(H5Tset_size(t.id(), chars + 1), ctx, "cannot size a string type");
  check(H5Tset_strpad(t.id(), H5T_STR_NULLTERM), ctx, "cannot make a string type");
  check(H5Tset_cset(t.id(), H5T_CSET_UTF8), ctx, "cannot make a string type");
  return t;
}

std::string shape_string(int rank, const hsize_t* dims) {
  std::string s = "(";
  for (int i = 0; i < rank; ++i) s += (i ? ", " : "") + std::to_string(dims[i]);
  return s + ")";
}

}  // namespace

void silence_thread() { silence(); }

// --- Handle ----------------------------------------------------------------------------------

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    type_ = o.type_;
    o.id_ = -1;
  }
  return *this;
}

bool Handle::reset() noexcept {
  if (id_ < 0) return true;
  herr_t r = -1;
  switch (type_) {
    case Type::file:
      r = H5Fclose(id_);
      break;
    case Type::group:
      r = H5Gclose(id_);
      break;
    case Type::dataset:
      r = H5Dclose(id_);
      break;
    case Type::dataspace:
      r = H5Sclose(id_);
      break;
    case Type::attribute:
      r = H5Aclose(id_);
      break;
    case Type::datatype:
      r = H5Tclose(id_);
      break;
    case Type::plist:
      r = H5Pclose(id_);
      break;
  }
  id_ = -1;
  return r >= 0;
}

// --- Group -----------------------------------------------------------------------------------

std::string Group::member_path(const std::string& name) const {
  return path_ == "/" ? "/" + name : path_ + "/" + name;
}

std::string Group::attribute_label(const std::string& name) const {
  return path_ == "/" ? "root attribute " + name : path_ + " attribute " + name;
}

void Group::fail(const std::string& what) const { h5::fail(ctx_, what); }

Group Group::create_group(const std::string& name) const {
  const std::string p = member_path(name);
  Handle gcpl = own(H5Pcreate(H5P_GROUP_CREATE), Handle::Type::plist, ctx_, "cannot create " + p);
  check(H5Pset_obj_track_times(gcpl.id(), false), ctx_, "cannot create " + p);
  Handle g = own(H5Gcreate2(handle_.id(), name.c_str(), H5P_DEFAULT, gcpl.id(), H5P_DEFAULT),
                 Handle::Type::group, ctx_, "cannot create group " + p);
  return Group(std::move(g), p, ctx_);
}

Group Group::open_group(const std::string& name) const {
  const std::string p = member_path(name);
  if (!exists(name)) fail("missing group " + p);
  Handle g = own(H5Gopen2(handle_.id(), name.c_str(), H5P_DEFAULT), Handle::Type::group, ctx_,
                 "cannot open " + p + " as a group");
  return Group(std::move(g), p, ctx_);
}

bool Group::exists(const std::string& name) const {
  return check(H5Lexists(handle_.id(), name.c_str(), H5P_DEFAULT), ctx_,
               "cannot look up " + member_path(name)) > 0;
}

bool Group::has_attribute(const std::string& name) const {
  return check(H5Aexists(handle_.id(), name.c_str()), ctx_,
               "cannot look up " + attribute_label(name)) > 0;
}

std::size_t Group::member_count() const {
  H5G_info_t info;
  check(H5Gget_info(handle_.id(), &info), ctx_, "cannot list " + path_);
  return std::size_t(info.nlinks);
}

void Group::remove(const std::string& name) const {
  check(H5Ldelete(handle_.id(), name.c_str(), H5P_DEFAULT), ctx_,
        "cannot remove " + member_path(name));
}

void Group::remove_attribute(const std::string& name) const {
  check(H5Adelete(handle_.id(), name.c_str()), ctx_, "cannot remove " + attribute_label(name));
}

namespace {

// Rows per chunk of a compressed dataset: about 256 kB; shuffle groups the bytes of equal weight,
// which deflate packs better (the figures in docs/benchmarks.md).
hsize_t compressed_chunk_rows(hsize_t row_bytes) {
  return std::max<hsize_t>(1, (256 << 10) / row_bytes);
}

// A dataset of `rows` rows, or (chunk_rows > 0) of none yet, growing by chunks of chunk_rows.
template <class T>
Handle create_dataset(hid_t loc, const std::string& name, const std::string& p, std::size_t rows,
                      int rank, std::size_t cols, const Context& ctx, std::size_t chunk_rows = 0) {
  SLICE_ASSERT(rank == 1 || cols > 0);
  const hsize_t dims[2] = {rows, rank == 1 ? 1 : cols};
  const hsize_t max_dims[2] = {chunk_rows > 0 ? H5S_UNLIMITED : dims[0], dims[1]};
  Handle space = own(H5Screate_simple(rank, dims, max_dims), Handle::Type::dataspace, ctx,
                     "cannot create the dataspace of " + p);
  Handle dcpl = own(H5Pcreate(H5P_DATASET_CREATE), Handle::Type::plist, ctx, "cannot create " + p);
  check(H5Pset_obj_track_times(dcpl.id(), false), ctx, "cannot create " + p);
  // Every element is written: no fill pass.
  check(H5Pset_fill_time(dcpl.id(), H5D_FILL_TIME_NEVER), ctx, "cannot create " + p);
  if (chunk_rows == 0 && ctx.compress && rows > 0)
    chunk_rows = std::min<hsize_t>(rows, compressed_chunk_rows(dims[1] * sizeof(T)));
  if (chunk_rows > 0) {
    const hsize_t chunk[2] = {chunk_rows, dims[1]};
    check(H5Pset_chunk(dcpl.id(), rank, chunk), ctx, "cannot create " + p);
  }
  if (ctx.compress && chunk_rows > 0) {
    check(H5Pset_shuffle(dcpl.id()), ctx, "cannot create " + p);
    check(H5Pset_deflate(dcpl.id(), 4), ctx, "cannot create " + p);
  }
  return own(H5Dcreate2(loc, name.c_str(), Traits<T>::file(), space.id(), H5P_DEFAULT, dcpl.id(),
                        H5P_DEFAULT),
             Handle::Type::dataset, ctx, "cannot create dataset " + p);
}

}  // namespace

namespace {

// Rows [first, first + count) of a dataset in its file space, and memory for them.
struct RowSelection {
  Handle file, memory;
};
RowSelection select_rows(const Handle& ds, std::size_t first, std::size_t count, int rank,
                         std::size_t width, const Context& ctx, const std::string& what) {
  const hsize_t start[2] = {first, 0}, rows[2] = {count, width};
  RowSelection sel;
  sel.file = own(H5Dget_space(ds.id()), Handle::Type::dataspace, ctx, what);
  check(H5Sselect_hyperslab(sel.file.id(), H5S_SELECT_SET, start, nullptr, rows, nullptr), ctx,
        what);
  sel.memory = own(H5Screate_simple(rank, rows, nullptr), Handle::Type::dataspace, ctx, what);
  return sel;
}

}  // namespace

template <class T>
void RowWriter<T>::write_rows(const T* data, std::size_t rows) {
  const std::size_t width = rank_ == 1 ? 1 : cols_;
  if (chunk_rows_ > 0) {
    const hsize_t size[2] = {next_ + rows, width};
    check(H5Dset_extent(ds_.id(), size), ctx_, "cannot write " + path_);
  }
  const RowSelection sel =
      select_rows(ds_, next_, rows, rank_, width, ctx_, "cannot write " + path_);
  check(H5Dwrite(ds_.id(), Traits<T>::mem(), sel.memory.id(), sel.file.id(), H5P_DEFAULT, data),
        ctx_, "cannot write " + path_);
  check_written(ctx_, "cannot write " + path_);
  next_ += rows;
}

template <class T>
void RowWriter<T>::append(std::span<const T> data) {
  const std::size_t width = rank_ == 1 ? 1 : cols_;
  SLICE_ASSERT(data.size() % width == 0);
  const std::size_t rows = data.size() / width;
  if (chunk_rows_ == 0) {
    SLICE_ASSERT(next_ + rows <= rows_);
    if (rows > 0) write_rows(data.data(), rows);
    return;
  }
  // Growing: whole chunks only, the pending rows first.
  std::size_t used = 0;
  if (!pending_.empty()) {
    used = std::min(rows, chunk_rows_ - pending_.size() / width);
    pending_.insert(pending_.end(), data.begin(), data.begin() + std::ptrdiff_t(used * width));
    if (pending_.size() / width < chunk_rows_) return;
    write_rows(pending_.data(), chunk_rows_);
    pending_.clear();
  }
  const std::size_t whole = (rows - used) / chunk_rows_ * chunk_rows_;
  if (whole > 0) write_rows(data.data() + used * width, whole);
  pending_.assign(data.begin() + std::ptrdiff_t((used + whole) * width), data.end());
}

template <class T>
void RowWriter<T>::finish() {
  if (chunk_rows_ > 0) {
    const std::size_t width = rank_ == 1 ? 1 : cols_;
    if (!pending_.empty()) write_rows(pending_.data(), pending_.size() / width);
    pending_ = {};
  } else {
    SLICE_ASSERT(next_ == rows_);
  }
  if (!ds_.reset()) fail_h5(ctx_, "cannot write " + path_);
  check_written(ctx_, "cannot write " + path_);
}

template <class T>
RowWriter<T> Group::create_rows(const std::string& name, std::size_t rows, std::size_t cols) const {
  const int rank = cols == 0 ? 1 : 2;
  Handle ds = create_dataset<T>(handle_.id(), name, member_path(name), rows, rank, cols, ctx_);
  return RowWriter<T>(std::move(ds), rows, cols, rank, member_path(name), ctx_);
}

template <class T>
RowWriter<T> Group::create_growing_rows(const std::string& name, std::size_t cols,
                                        std::size_t expected_rows) const {
  const int rank = cols == 0 ? 1 : 2;
  const hsize_t row_bytes = (cols == 0 ? 1 : cols) * sizeof(T);
  // Uncompressed chunks larger than HDF5's 1 MiB chunk cache go to the file directly.
  const hsize_t most = ctx_.compress ? compressed_chunk_rows(row_bytes) : (4 << 20) / row_bytes;
  const std::size_t chunk = std::max<hsize_t>(1, std::min<hsize_t>(expected_rows, most));
  Handle ds = create_dataset<T>(handle_.id(), name, member_path(name), 0, rank, cols, ctx_, chunk);
  return RowWriter<T>(std::move(ds), 0, cols, rank, member_path(name), ctx_, chunk);
}

namespace {

template <class T>
void write_dataset(const Group& g, const std::string& name, std::span<const T> data,
                   std::size_t cols) {
  const std::size_t rows = cols == 0 ? data.size() : data.size() / cols;
  SLICE_ASSERT(cols == 0 || data.size() % cols == 0);
  RowWriter<T> w = g.create_rows<T>(name, rows, cols);
  w.append(data);
  w.finish();
}

// A byte count that may exceed every integer type (a damaged shape), e.g. "7.9e+19".
std::string bytes_string(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, bytes < 1e15 ? "%.0f" : "%.2g", bytes);
  return buf;
}

// Deflate packs at most about 1032:1; no filter pipeline we accept packs tighter.
constexpr double kMaxCompression = 1100;

// The element count of a dataset, checked against the bytes the file really holds for it before
// anything is allocated: a crafted or damaged file can claim 4e9 rows in a few kB (a sparse
// chunked dataset), which would otherwise end in bad_alloc.
std::size_t checked_size(hid_t ds, hid_t type, int rank, const hsize_t* dims, const std::string& p,
                         const Context& ctx) {
  double count = 1;
  for (int i = 0; i < rank; ++i) count *= double(dims[i]);
  if (count == 0) return 0;
  const std::size_t element = H5Tget_size(type);
  if (element == 0) fail_h5(ctx, "cannot read " + p);
  const double bytes = count * double(element);
  Handle dcpl = own(H5Dget_create_plist(ds), Handle::Type::plist, ctx, "cannot read " + p);
  const int filters = check(H5Pget_nfilters(dcpl.id()), ctx, "cannot read " + p);
  // A filter this build lacks (LZF, Blosc, ...: HDF5 looks for a plugin) would fail the read
  // with HDF5's "can't open directory" of its plugin folder; say what is missing instead.
  for (int i = 0; i < filters; ++i) {
    char name[64] = {};
    unsigned flags = 0, config = 0;
    std::size_t nvalues = 0;
    const H5Z_filter_t id = H5Pget_filter2(dcpl.id(), unsigned(i), &flags, &nvalues, nullptr,
                                           sizeof name, name, &config);
    const htri_t avail = id < 0 ? 0 : H5Zfilter_avail(id);
    H5Eclear2(H5E_DEFAULT);
    if (avail <= 0)
      throw Error(ctx.file,
                  p + " uses the HDF5 compression filter " +
                      (name[0] ? "\"" + std::string(name) + "\" " : std::string()) + "(id " +
                      std::to_string(id) + "), which this build of rockslice cannot read",
                  "rewrite it without that filter (h5repack -f NONE, where the filter is "
                  "installed), or " +
                      ctx.fix);
  }
  const double stored = double(H5Dget_storage_size(ds));
  const double can_hold = filters > 0 ? stored * kMaxCompression : stored;
  if (bytes > can_hold)
    fail(ctx, p + " claims shape " + shape_string(rank, dims) + " (" + bytes_string(bytes) +
                  " bytes) but the file holds " + bytes_string(stored) +
                  " bytes of it: it is damaged or was not written in full");
  return std::size_t(count);
}

struct OpenedDataset {
  Handle ds;
  std::size_t rows;
  std::string path;
};

// Opens a dataset for reading, checking its type, its shape and that the file holds its bytes.
template <class T>
OpenedDataset open_dataset(const Group& g, hid_t loc, const std::string& name, int rank,
                           std::size_t cols) {
  const Context& ctx = g.context();
  std::string p = g.member_path(name);
  if (!g.exists(name)) fail(ctx, "missing dataset " + p);
  Handle ds = own(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), Handle::Type::dataset, ctx,
                  "cannot open " + p + " as a dataset");
  Handle type = own(H5Dget_type(ds.id()), Handle::Type::datatype, ctx, "cannot read " + p);
  if (!converts<T>(type.id()))
    fail(ctx, p + " holds " + describe(type.id()) + "; expected " + expected_type<T>());
  Handle space = own(H5Dget_space(ds.id()), Handle::Type::dataspace, ctx, "cannot read " + p);
  const int nd = check(H5Sget_simple_extent_ndims(space.id()), ctx, "cannot read " + p);
  hsize_t dims[H5S_MAX_RANK] = {};
  check(H5Sget_simple_extent_dims(space.id(), dims, nullptr), ctx, "cannot read " + p);
  if (nd != rank || (rank == 2 && dims[1] != cols))
    fail(ctx, p + " has shape " + shape_string(nd, dims) + "; expected " +
                  (rank == 1 ? std::string("(n)") : "(n, " + std::to_string(cols) + ")"));
  const std::size_t n = checked_size(ds.id(), type.id(), nd, dims, p, ctx);
  return {std::move(ds), rank == 1 ? n : n / cols, std::move(p)};
}

}  // namespace

template <class T>
void RowReader<T>::read(std::size_t first, std::size_t count, T* out) const {
  SLICE_ASSERT(first + count <= rows_);
  if (count == 0) return;
  if (first == 0 && count == rows_) {
    check(H5Dread(ds_.id(), Traits<T>::mem(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out), ctx_,
          "cannot read " + path_);
    return;
  }
  const RowSelection sel =
      select_rows(ds_, first, count, rank_, rank_ == 1 ? 1 : cols_, ctx_, "cannot read " + path_);
  check(H5Dread(ds_.id(), Traits<T>::mem(), sel.memory.id(), sel.file.id(), H5P_DEFAULT, out), ctx_,
        "cannot read " + path_);
}

template <class T>
RowReader<T> Group::open_rows(const std::string& name, std::size_t cols) const {
  const int rank = cols == 0 ? 1 : 2;
  OpenedDataset d = open_dataset<T>(*this, handle_.id(), name, rank, cols);
  return RowReader<T>(std::move(d.ds), d.rows, cols, rank, std::move(d.path), ctx_);
}

namespace {

template <class T>
std::vector<T> read_dataset(const Group& g, const std::string& name, std::size_t cols) {
  const RowReader<T> r = g.open_rows<T>(name, cols);
  std::vector<T> v(r.rows() * (cols == 0 ? 1 : cols));
  r.read(0, r.rows(), v.data());
  return v;
}

}  // namespace

template <class T>
void Group::write(const std::string& name, std::span<const T> data) const {
  write_dataset<T>(*this, name, data, 0);
}

template <class T>
void Group::write(const std::string& name, std::span<const T> data, std::size_t cols) const {
  SLICE_ASSERT(cols > 0);
  write_dataset<T>(*this, name, data, cols);
}

template <class T>
std::vector<T> Group::read(const std::string& name) const {
  return read_dataset<T>(*this, name, 0);
}

template <class T>
std::vector<T> Group::read(const std::string& name, std::size_t cols) const {
  SLICE_ASSERT(cols > 0);
  return read_dataset<T>(*this, name, cols);
}

template <class T>
void Group::write_attribute(const std::string& name, const T& value) const {
  const std::string label = attribute_label(name);
  const std::string what = "cannot write " + label;
  Handle space = own(H5Screate(H5S_SCALAR), Handle::Type::dataspace, ctx_, what);
  if constexpr (std::is_same_v<T, std::string>) {
    if (value.find('\0') != std::string::npos)
      fail(label + " contains a NUL character, which HDF5 strings cannot hold");
    Handle type = string_type(value.size(), ctx_);
    Handle a =
        own(H5Acreate2(handle_.id(), name.c_str(), type.id(), space.id(), H5P_DEFAULT, H5P_DEFAULT),
            Handle::Type::attribute, ctx_, what);
    check(H5Awrite(a.id(), type.id(), value.c_str()), ctx_, what);
    if (!a.reset()) fail_h5(ctx_, what);
    check_written(ctx_, what);
  } else {
    Handle a = own(H5Acreate2(handle_.id(), name.c_str(), Traits<T>::file(), space.id(),
                              H5P_DEFAULT, H5P_DEFAULT),
                   Handle::Type::attribute, ctx_, what);
    check(H5Awrite(a.id(), Traits<T>::mem(), &value), ctx_, what);
    if (!a.reset()) fail_h5(ctx_, what);
    check_written(ctx_, what);
  }
}

template <class T>
T Group::read_attribute(const std::string& name) const {
  const std::string label = attribute_label(name);
  const std::string what = "cannot read " + label;
  if (!has_attribute(name)) fail("missing " + label);
  Handle a =
      own(H5Aopen(handle_.id(), name.c_str(), H5P_DEFAULT), Handle::Type::attribute, ctx_, what);
  Handle type = own(H5Aget_type(a.id()), Handle::Type::datatype, ctx_, what);
  if (!converts<T>(type.id()))
    fail(label + " holds " + describe(type.id()) + "; expected " + expected_type<T>());
  Handle space = own(H5Aget_space(a.id()), Handle::Type::dataspace, ctx_, what);
  const hssize_t points = check(H5Sget_simple_extent_npoints(space.id()), ctx_, what);
  if (points != 1) fail(label + " holds " + std::to_string(points) + " values; expected one");
  T value{};
  if constexpr (std::is_same_v<T, std::string>) {
    // One string layout, the one we write (h5.hpp): h5py's variable-length strings are refused.
    if (check(H5Tis_variable_str(type.id()), ctx_, what) > 0)
      fail(label + " is a variable-length string; expected a fixed-length string");
    // Read as null-terminated whatever the stored padding; HDF5 converts.
    const std::size_t n = H5Tget_size(type.id());
    if (n == 0) fail_h5(ctx_, what);
    Handle mem = string_type(n, ctx_);
    check(H5Tset_cset(mem.id(), H5Tget_cset(type.id())), ctx_, what);
    std::string buf(n + 1, '\0');
    check(H5Aread(a.id(), mem.id(), buf.data()), ctx_, what);
    value = buf.substr(0, buf.find('\0'));
  } else {
    check(H5Aread(a.id(), Traits<T>::mem(), &value), ctx_, what);
  }
  return value;
}

#define SLICE_H5_DATASET(T)                                                                        \
  template class RowWriter<T>;                                                                     \
  template class RowReader<T>;                                                                     \
  template RowReader<T> Group::open_rows<T>(const std::string&, std::size_t) const;                \
  template RowWriter<T> Group::create_rows<T>(const std::string&, std::size_t, std::size_t) const; \
  template RowWriter<T> Group::create_growing_rows<T>(const std::string&, std::size_t,             \
                                                      std::size_t) const;                          \
  template void Group::write<T>(const std::string&, std::span<const T>) const;                     \
  template void Group::write<T>(const std::string&, std::span<const T>, std::size_t) const;        \
  template std::vector<T> Group::read<T>(const std::string&) const;                                \
  template std::vector<T> Group::read<T>(const std::string&, std::size_t) const;
SLICE_H5_DATASET(double)
SLICE_H5_DATASET(std::int64_t)
SLICE_H5_DATASET(std::int32_t)
SLICE_H5_DATASET(std::uint8_t)
SLICE_H5_DATASET(std::int8_t)
#undef SLICE_H5_DATASET

#define SLICE_H5_ATTRIBUTE(T)                                                  \
  template void Group::write_attribute<T>(const std::string&, const T&) const; \
  template T Group::read_attribute<T>(const std::string&) const;
SLICE_H5_ATTRIBUTE(std::string)
SLICE_H5_ATTRIBUTE(std::int64_t)
SLICE_H5_ATTRIBUTE(std::uint64_t)
SLICE_H5_ATTRIBUTE(double)
#undef SLICE_H5_ATTRIBUTE

// --- File ------------------------------------------------------------------------------------

std::size_t open_objects() {
  const ssize_t n = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
  return n < 0 ? 0 : static_cast<std::size_t>(n);
}

File File::create(const fs::path& path, Context ctx) {
  silence();
  const std::string what = "cannot create the file " + path.string();
  // The root group is made with the file: no time stamps there either.
  Handle fcpl = own(H5Pcreate(H5P_FILE_CREATE), Handle::Type::plist, ctx, what);
  check(H5Pset_obj_track_times(fcpl.id(), false), ctx, what);
  // Through the writing driver (write_driver.hpp): a full disk must not leave HDF5 unable to
  // close the file.
  ctx.written = std::make_shared<WriteFailure>();
  Handle fapl = own(writing_fapl(ctx.written.get()), Handle::Type::plist, ctx, what);
  Handle f = own(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.id(), fapl.id()), Handle::Type::file,
                 ctx, what);
  settle_truncation(path);
  Handle root = own(H5Gopen2(f.id(), "/", H5P_DEFAULT), Handle::Type::group, ctx, what);
  return File(std::move(f), Group(std::move(root), "/", std::move(ctx)));
}

namespace {
std::atomic<const char*> g_reading{nullptr};
}  // namespace

ReadingMark::ReadingMark(const std::string& path) : path_(new char[path.size() + 1]) {
  std::copy(path.begin(), path.end(), path_.get());
  path_[path.size()] = '\0';
  g_reading.store(path_.get());
}

ReadingMark::~ReadingMark() {
  if (!path_) return;
  const char* mine = path_.get();
  g_reading.compare_exchange_strong(mine, nullptr);
}

File File::open(const fs::path& path, Context ctx, bool writable) {
  silence();
  ReadingMark mark(ctx.file);
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (!fs::exists(status)) throw Error(ctx.file, "no such file", "check the path");
  if (fs::is_directory(status))
    throw Error(ctx.file, "is a directory, not a file", "check the path");
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
  if (is_hdf5 < 0) fail_h5(ctx, "cannot read the file");
  if (is_hdf5 == 0)
    throw Error(ctx.file, "not an HDF5 file", "give a .h5 file written by a rockslice tool");
  // Read-only files go through the checked driver (checked_driver.hpp): HDF5 alone can be made
  // to allocate without end by a damaged local heap.
  const hid_t fapl =
      writable ? H5P_DEFAULT : check(checked_read_fapl(), ctx, "cannot open the file");
  Handle f = own(H5Fopen(path.c_str(), writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, fapl),
                 Handle::Type::file, ctx, "cannot open the file");
  Handle root = own(H5Gopen2(f.id(), "/", H5P_DEFAULT), Handle::Type::group, ctx,
                    "cannot open the root group");
  return File(std::move(f), Group(std::move(root), "/", std::move(ctx)), std::move(mark));
}

void File::close() {
  const Context ctx = root_.ctx_;
  root_.handle_.reset();
  if (!file_.reset()) fail_h5(ctx, "cannot close the file (flushing its content failed)");
  check_written(ctx, "cannot write the file");
}

}  // namespace slice::h5

namespace slice {
const char* hdf5_input_being_read() noexcept { return h5::g_reading.load(); }
}  // namespace slice

#include "vtu_file.hpp"

#include <lz4.h>
#include <oneapi/tbb/parallel_for.h>
#include <sys/types.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>

#include "../threads.hpp"
#include "slice/error.hpp"
#include "slice/output.hpp"

namespace slice::vtu {
namespace {

static_assert(std::endian::native == std::endian::little, "the files say byte_order=LittleEndian");

constexpr std::size_t kBlock = 32768;     // uncompressed bytes per block (VTK's default)
constexpr std::size_t kBatchBlocks = 64;  // blocks compressed together (2 MiB)
constexpr int kZlibLevel = 5;

const char* compressor_name(VtuCompressor c) {
  switch (c) {
    case VtuCompressor::lz4:
      return "vtkLZ4DataCompressor";
    case VtuCompressor::zlib:
      return "vtkZLibDataCompressor";
    case VtuCompressor::none:
      break;
  }
  return nullptr;
}

/// One block compressed into `out` (resized to the compressed size).
void compress_block(VtuCompressor c, const unsigned char* in, std::size_t n,
                    std::vector<unsigned char>& out) {
  if (c == VtuCompressor::lz4) {
    out.resize(std::size_t(LZ4_compressBound(int(n))));
    const int k =
        LZ4_compress_default(reinterpret_cast<const char*>(in), reinterpret_cast<char*>(out.data()),
                             int(n), int(out.size()));
    if (k <= 0) throw Error("VTU writer", "LZ4 could not compress a block", "report this bug");
    out.resize(std::size_t(k));
    return;
  }
  uLongf k = compressBound(uLong(n));
  out.resize(k);
  if (compress2(out.data(), &k, in, uLong(n), kZlibLevel) != Z_OK)
    throw Error("VTU writer", "zlib could not compress a block", "report this bug");
  out.resize(k);
}

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Appends the base64 of the whole triplets of `in` (n / 3 of them) to `out`.
void encode_triplets(const unsigned char* in, std::size_t n, std::string& out) {
  const std::size_t at = out.size();
  out.resize(at + n / 3 * 4);
  char* o = out.data() + at;
  for (std::size_t k = 0; k + 3 <= n; k += 3) {
    const std::uint32_t v = std::uint32_t(in[k]) << 16 | std::uint32_t(in[k + 1]) << 8 | in[k + 2];
    *o++ = kBase64[v >> 18];
    *o++ = kBase64[v >> 12 & 63];
    *o++ = kBase64[v >> 6 & 63];
    *o++ = kBase64[v & 63];
  }
}

/// Appends the base64 of the last 0-2 bytes, padded with '='.
void encode_tail(const unsigned char* in, std::size_t n, std::string& out) {
  if (n == 0) return;
  const std::uint32_t v = std::uint32_t(in[0]) << 16 | (n == 2 ? std::uint32_t(in[1]) << 8 : 0);
  out += kBase64[v >> 18];
  out += kBase64[v >> 12 & 63];
  out += n == 2 ? kBase64[v >> 6 & 63] : '=';
  out += '=';
}

/// The length of the base64 of `bytes` bytes.
std::size_t encoded_size(std::size_t bytes) { return (bytes + 2) / 3 * 4; }

}  // namespace

File::File(const std::filesystem::path& path, std::string what, VtuCompressor compressor)
    : what_(std::move(what)), compressor_(compressor) {
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_) {
    const int e = errno;
    throw Error(what_, std::string("cannot be written (") + std::strerror(e) + ")",
                write_error_fix(e));
  }
  settle_truncation(path);
  constexpr std::size_t kFileBuffer = std::size_t(1) << 20;
  buffer_ = std::make_unique<char[]>(kFileBuffer);
  std::setvbuf(f_, buffer_.get(), _IOFBF, kFileBuffer);
}

File::~File() {
  abandon(compressing_);  // after an error elsewhere: the task ends before its buffers go
  if (f_) std::fclose(f_);
}

void File::write(const void* data, std::size_t bytes) {
  if (bytes && std::fwrite(data, 1, bytes, f_) != bytes) {
    const int e = errno;
    throw Error(what_, std::string("could not be written (") + std::strerror(e) + ")",
                write_error_fix(e));
  }
}

void File::seek_write(std::int64_t at, const void* data, std::size_t bytes) {
  // A seek writes out the buffer first: its failure is a failed write (errno says why).
  const auto seek = [&](off_t to, int whence) {
    errno = 0;
    if (fseeko(f_, to, whence) != 0) {
      const int e = errno;
      throw Error(
          what_,
          std::string("could not be written (") + (e ? std::strerror(e) : "seek failed") + ")",
          write_error_fix(e));
    }
  };
  seek(off_t(at), SEEK_SET);
  write(data, bytes);
  seek(0, SEEK_END);
}

void File::header(std::size_t points, std::size_t cells, const std::vector<Section>& sections,
                  const std::string& scalars) {
  std::string x =
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\"";
  if (const char* c = compressor_name(compressor_)) x += std::string(" compressor=\"") + c + "\"";
  x += ">\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" + std::to_string(points) +
       "\" NumberOfCells=\"" + std::to_string(cells) +
       "\">\n      <PointData>\n      </PointData>\n";
  const bool has_cell_data = std::any_of(sections.begin(), sections.end(),
                                         [](const Section& s) { return s.tag == "CellData"; });
  if (!has_cell_data) x += "      <CellData>\n      </CellData>\n";
  for (const Section& s : sections) {
    x += "      <" + s.tag;
    if (s.tag == "CellData" && !scalars.empty()) x += " Scalars=\"" + scalars + "\"";
    x += ">\n";
    for (const ArraySpec& a : s.arrays) {
      x += std::string("        <DataArray type=\"") + a.type + "\"";
      if (a.id_type) x += " IdType=\"1\"";
      x += " Name=\"" + a.name + "\"";
      if (a.components != 1) x += " NumberOfComponents=\"" + std::to_string(a.components) + "\"";
      x += " format=\"binary\"";
      if (!a.range_min.empty())
        x += " RangeMin=\"" + a.range_min + "\" RangeMax=\"" + a.range_max + "\"";
      x += ">\n          ";
      opening_.push_back(std::move(x));
      x = "\n        </DataArray>\n";
    }
    x += "      </" + s.tag + ">\n";
  }
  closing_ = std::move(x) + "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
}

void File::begin_array(std::size_t bytes) {
  SLICE_ASSERT(array_ < opening_.size() && received_ == expected_);
  write(opening_[array_].data(), opening_[array_].size());
  expected_ = bytes;
  received_ = 0;
  block_sizes_.clear();
  pending_.clear();
  carried_ = 0;
  if (compressor_ == VtuCompressor::none) {
    // The byte count and the bytes: one base64 text.
    const std::uint64_t n = bytes;
    write_encoded(reinterpret_cast<const unsigned char*>(&n), sizeof n);
    return;
  }
  // Room for the block header's base64: count, block size, last block size, compressed sizes.
  const std::size_t blocks = (bytes + kBlock - 1) / kBlock;
  array_header_at_ = ftello(f_);
  const std::string room(encoded_size((3 + blocks) * sizeof(std::uint64_t)), 'A');
  write(room.data(), room.size());
}

void File::put(const void* data, std::size_t bytes) {
  received_ += bytes;
  SLICE_ASSERT(received_ <= expected_);
  const auto* p = static_cast<const unsigned char*>(data);
  if (compressor_ == VtuCompressor::none) {
    write_encoded(p, bytes);
    return;
  }
  pending_.insert(pending_.end(), p, p + bytes);
  if (pending_.size() >= kBatchBlocks * kBlock) flush_blocks(false);
}

/// Hands the pending full blocks (and, if `last`, the partial one) to a task that compresses
/// them in parallel, then writes the batch before (compressed meanwhile), in order; `last`
/// waits for this one too.
void File::flush_blocks(bool last) {
  const std::size_t full = pending_.size() / kBlock;
  const std::size_t count = full + (last && pending_.size() % kBlock ? 1 : 0);
  if (count == 0) {
    land();
    return;
  }
  const Batch* before = nullptr;
  if (flying_) {
    compressing_.wait();  // rethrows its error
    before = &batches_[flying_ - 1];
  }
  // This batch goes to the other buffers; the rest of a block stays pending.
  const std::size_t slot = flying_ == 1 ? 1 : 0;
  Batch& b = batches_[slot];
  const std::size_t bytes = std::min(pending_.size(), count * kBlock);
  b.raw.swap(pending_);
  pending_.assign(b.raw.begin() + std::ptrdiff_t(bytes), b.raw.end());
  b.raw.resize(bytes);
  b.blocks.resize(count);
  flying_ = slot + 1;
  compressing_.run([this, &b, count] {
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t k) {
      const std::size_t lo = k * kBlock, n = std::min(kBlock, b.raw.size() - lo);
      compress_block(compressor_, b.raw.data() + lo, n, b.blocks[k]);
    });
  });
  if (before) write_batch(*before);
  if (last) land();
}

/// Waits for the batch in flight (rethrowing its error) and writes its blocks.
void File::land() {
  if (!flying_) return;
  const Batch& b = batches_[flying_ - 1];
  flying_ = 0;
  compressing_.wait();
  write_batch(b);
}

void File::write_batch(const Batch& b) {
  for (const auto& o : b.blocks) {
    write_encoded(o.data(), o.size());
    block_sizes_.push_back(o.size());
  }
}

/// Writes the base64 of `bytes` bytes that follow those written since the array began: the
/// whole triplets, keeping the rest for the next call or end_encoded.
void File::write_encoded(const unsigned char* data, std::size_t bytes) {
  encoded_.clear();
  if (carried_ && carried_ + bytes >= 3) {
    unsigned char t[3];
    std::memcpy(t, carry_, carried_);
    const std::size_t take = 3 - carried_;
    std::memcpy(t + carried_, data, take);
    encode_triplets(t, 3, encoded_);
    data += take;
    bytes -= take;
    carried_ = 0;
  }
  if (carried_) {  // still short of a triplet
    std::memcpy(carry_ + carried_, data, bytes);
    carried_ += bytes;
    return;
  }
  const std::size_t whole = bytes / 3 * 3;
  encode_triplets(data, whole, encoded_);
  carried_ = bytes - whole;
  std::memcpy(carry_, data + whole, carried_);
  write(encoded_.data(), encoded_.size());
}

/// Writes the base64 of the bytes carried over, padded: the array's base64 text ends.
void File::end_encoded() {
  encoded_.clear();
  encode_tail(carry_, carried_, encoded_);
  carried_ = 0;
  write(encoded_.data(), encoded_.size());
}

void File::end_array() {
  SLICE_ASSERT(received_ == expected_);
  ++array_;
  if (compressor_ == VtuCompressor::none) {
    end_encoded();
    return;
  }
  flush_blocks(true);
  end_encoded();
  std::vector<std::uint64_t> h{block_sizes_.size(), kBlock, expected_ % kBlock};
  h.insert(h.end(), block_sizes_.begin(), block_sizes_.end());
  SLICE_ASSERT(h.size() == 3 + (expected_ + kBlock - 1) / kBlock);
  // The header's base64 of its own (padded), as VTK's reader reads it, in the room left.
  const auto* bytes = reinterpret_cast<const unsigned char*>(h.data());
  const std::size_t n = h.size() * sizeof(std::uint64_t);
  std::string text;
  encode_triplets(bytes, n, text);
  encode_tail(bytes + n / 3 * 3, n % 3, text);
  SLICE_ASSERT(text.size() == encoded_size(n));
  seek_write(array_header_at_, text.data(), text.size());
}

void File::finish() {
  SLICE_ASSERT(array_ == opening_.size());
  write(closing_.data(), closing_.size());
  const bool bad = std::fflush(f_) != 0 || std::ferror(f_);
  const int closed = std::fclose(f_);
  f_ = nullptr;
  if (bad || closed != 0) {
    const int e = errno;
    throw Error(what_, std::string("could not be written (") + std::strerror(e) + ")",
                write_error_fix(e));
  }
}

}  // namespace slice::vtu

#include "checked_driver.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "posix_io.hpp"

namespace slice::h5 {

namespace {

// The end of a local heap's free list (H5HL_FREE_NULL in HDF5's H5HLprivate.h).
constexpr std::uint64_t kFreeNull = 1;

struct CheckedFile : PosixFile {
  unsigned offsets = 0;  // bytes of an address and of a length in this file (its superblock);
  unsigned lengths = 0;  // 0: not known, nothing is checked
  std::vector<haddr_t> heaps_checked;
};

CheckedFile* cast(H5FD_t* f) { return static_cast<CheckedFile*>(posix(f)); }

herr_t fail(const char* func, const std::string& msg) {
  return push_error(func, H5E_READERROR, msg);
}

// A little-endian unsigned field of n bytes; all ones if it does not fit 64 bits.
std::uint64_t decode(const unsigned char* p, unsigned n) {
  std::uint64_t v = 0;
  for (unsigned i = 0; i < n; ++i) {
    if (i >= 8) {
      if (p[i] != 0) return ~std::uint64_t{0};
      continue;
    }
    v |= std::uint64_t{p[i]} << (8 * i);
  }
  return v;
}

// The sizes of addresses and lengths, from the superblock: at byte 0, 512, 1024, 2048, ...
void read_superblock_sizes(CheckedFile& cf) {
  static const unsigned char kSignature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  for (haddr_t at = 0; at + 16 <= cf.eof; at = at == 0 ? 512 : 2 * at) {
    unsigned char b[16];
    if (!read_at(cf.fd, at, sizeof b, b)) return;
    if (std::memcmp(b, kSignature, sizeof kSignature) != 0) continue;
    const unsigned version = b[8];
    if (version <= 1) {
      cf.offsets = b[13];
      cf.lengths = b[14];
    } else if (version <= 3) {
      cf.offsets = b[9];
      cf.lengths = b[10];
    }
    if (cf.offsets == 0 || cf.offsets > 32 || cf.lengths == 0 || cf.lengths > 32)
      cf.offsets = cf.lengths = 0;
    return;
  }
}

// Walks the free list of the local heap whose prefix ("HEAP", version, sizes, addresses) HDF5
// has just read at addr (image: the n bytes read). Returns an empty string if HDF5 may go on: the
// list ends, or HDF5's own checks stop it (an offset or block past the heap, a zero link). A list
// with more blocks than the heap's bytes can hold apart loops or overlaps: that is refused, as is
// a block whose two fields run past the heap (HDF5 would read them past its buffer).
std::string check_local_heap(CheckedFile& cf, haddr_t addr, const unsigned char* image,
                             std::size_t n) {
  const unsigned L = cf.lengths, O = cf.offsets;
  if (L == 0 || n < 8 + 2 * std::size_t{L} + O || image[4] != 0) return {};
  if (std::find(cf.heaps_checked.begin(), cf.heaps_checked.end(), addr) != cf.heaps_checked.end())
    return {};
  const std::uint64_t dblk_size = decode(image + 8, L);
  const std::uint64_t free_head = decode(image + 8 + L, L);
  const std::uint64_t dblk_addr = decode(image + 8 + 2 * L, O);
  const haddr_t start = dblk_addr + cf.pub.base_addr;
  if (free_head == kFreeNull || start < dblk_addr || start >= cf.eof) return {};

  // The heap's bytes in the file (HDF5 reads zeros past its end, where every list stops).
  const std::uint64_t visible = std::min<std::uint64_t>(dblk_size, cf.eof - start);
  std::vector<unsigned char> data(visible + 2 * std::size_t{L}, 0);
  if (!read_at(cf.fd, start, visible, data.data())) return {};

  const std::string where = "the local heap at byte " + std::to_string(addr);
  const std::uint64_t most = visible / (2 * L) + 1;
  std::uint64_t count = 0;
  for (std::uint64_t at = free_head; at != kFreeNull;) {
    if (at >= dblk_size) return {};
    if (dblk_size - at < 2 * L) return where + " has a free block past its end (damaged file)";
    const std::uint64_t next = at < visible ? decode(data.data() + at, L) : 0;
    const std::uint64_t size = at < visible ? decode(data.data() + at + L, L) : 0;
    if (next == 0 || size > dblk_size - at) return {};
    if (++count > most) return where + " has a list of free blocks that loops (damaged file)";
    at = next;
  }
  cf.heaps_checked.push_back(addr);
  return {};
}

// --- the driver's callbacks ------------------------------------------------------------------

H5FD_t* open_file(const char* name, unsigned flags, hid_t /*fapl*/, haddr_t maxaddr) {
  if ((flags & (H5F_ACC_RDWR | H5F_ACC_CREAT | H5F_ACC_TRUNC)) != 0) {
    fail("open_file", "this driver only reads files");
    return nullptr;
  }
  PosixFile opened;
  if (!open_posix(name, O_RDONLY, maxaddr, opened)) return nullptr;
  auto* cf = adopt<CheckedFile>(opened);
  if (cf == nullptr) return nullptr;
  read_superblock_sizes(*cf);
  return &cf->pub;
}

herr_t close_file(H5FD_t* f) {
  CheckedFile* cf = cast(f);
  const int r = ::close(cf->fd);
  delete cf;
  return r == 0 ? 0 : fail("close_file", "cannot close the file");
}

// No metadata accumulation: each metadata read reaches read_file as HDF5 asked for it, with its
// type, so a local heap's prefix arrives at the start of a buffer.
herr_t query(const H5FD_t* /*f*/, unsigned long* flags) {
  if (flags != nullptr) *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_DATA_SIEVE;
  return 0;
}

herr_t read_file(H5FD_t* f, H5FD_mem_t type, hid_t /*dxpl*/, haddr_t addr, std::size_t size,
                 void* buffer) {
  CheckedFile* cf = cast(f);
  if (!allocated(*cf, addr, size))
    return fail("read_file", "address past the end of the file's allocation");
  auto* out = static_cast<unsigned char*>(buffer);
  if (!read_at(cf->fd, addr, size, out))
    return fail("read_file", std::string("read failed: ") + std::strerror(errno));
  if (type == H5FD_MEM_LHEAP && size >= 4 && std::memcmp(out, "HEAP", 4) == 0) {
    const std::string damage = check_local_heap(*cf, addr, out, size);
    if (!damage.empty()) return fail("read_file", damage);
  }
  return 0;
}

herr_t write_file(H5FD_t* /*f*/, H5FD_mem_t /*type*/, hid_t /*dxpl*/, haddr_t /*addr*/,
                  std::size_t /*size*/, const void* /*buffer*/) {
  return fail("write_file", "this driver only reads files");
}

herr_t nothing_to_do(H5FD_t* /*f*/, hid_t /*dxpl*/, hbool_t /*closing*/) { return 0; }

H5FD_class_t make_class() {
  H5FD_class_t c = posix_class("rockslice-checked");
  c.open = open_file;
  c.close = close_file;
  c.query = query;
  c.read = read_file;
  c.write = write_file;
  c.flush = nothing_to_do;
  c.truncate = nothing_to_do;
  return c;
}

}  // namespace

std::int64_t checked_read_fapl() {
  static const H5FD_class_t cls = make_class();
  static const hid_t fapl = [] {
    const hid_t driver = H5FDregister(&cls);
    if (driver < 0) return hid_t{-1};
    const hid_t p = H5Pcreate(H5P_FILE_ACCESS);
    if (p < 0) return hid_t{-1};
    if (H5Pset_driver(p, driver, nullptr) < 0) {
      H5Pclose(p);
      return hid_t{-1};
    }
    return p;
  }();
  return fapl;
}

}  // namespace slice::h5

#pragma once
// What the two file drivers (checked_driver.cpp, write_driver.cpp) share: a file descriptor with
// HDF5's end markers, the callbacks that only read or set those, and reads and writes at an offset,
// as HDF5's sec2 driver does them (pread, pwrite; retried where a signal interrupted).
#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <iterator>
#include <new>
#include <string>

namespace slice::h5 {

// The largest address a pread offset can hold, as HDF5's sec2 driver has it.
constexpr haddr_t kMaxAddr = (haddr_t{1} << (8 * sizeof(off_t) - 1)) - 1;

// The most bytes one pread or pwrite is asked for.
constexpr std::size_t kMaxTransfer = std::size_t{1} << 30;

// Reads [addr, addr + size) of the file; bytes past its end read as zeros (as sec2 does).
// False, errno set, if the system refuses.
inline bool read_at(int fd, haddr_t addr, std::size_t size, unsigned char* out) {
  while (size > 0) {
    const ssize_t n = pread(fd, out, std::min(size, kMaxTransfer), static_cast<off_t>(addr));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    if (n == 0) {
      std::memset(out, 0, size);
      return true;
    }
    const auto got = static_cast<std::size_t>(n);
    out += got;
    addr += got;
    size -= got;
  }
  return true;
}

// Writes [addr, addr + size) of the file. False, errno set, if the system refuses.
inline bool write_at(int fd, haddr_t addr, std::size_t size, const unsigned char* in) {
  while (size > 0) {
    const ssize_t n = pwrite(fd, in, std::min(size, kMaxTransfer), static_cast<off_t>(addr));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;  // nothing written and no reason given: do not loop
      return false;
    }
    const auto put = static_cast<std::size_t>(n);
    in += put;
    addr += put;
    size -= put;
  }
  return true;
}

// A file open under one of the drivers. HDF5 hands `pub` back to every callback.
struct PosixFile {
  H5FD_t pub;  // first
  int fd = -1;
  dev_t dev = 0;
  ino_t ino = 0;
  haddr_t eoa = 0;  // HDF5's end of allocation
  haddr_t eof = 0;  // the end of the file's bytes
};

inline PosixFile* posix(H5FD_t* f) { return reinterpret_cast<PosixFile*>(f); }
inline const PosixFile* posix(const H5FD_t* f) { return reinterpret_cast<const PosixFile*>(f); }

// Pushes msg on HDF5's error stack, under the call that failed (minor: H5E_READERROR,
// H5E_WRITEERROR, ...); h5.cpp's reason() shows it. Returns -1, a failed herr_t.
inline herr_t push_error(const char* func, hid_t minor, const std::string& msg) {
  H5Epush2(H5E_DEFAULT, __FILE__, func, __LINE__, H5E_ERR_CLS, H5E_VFL, minor, "%s", msg.c_str());
  return -1;
}

// Opens `name` with open(2)'s `oflags` into f (fd, device, inode, end of file). False, with an
// error pushed, if the system refuses.
inline bool open_posix(const char* name, int oflags, haddr_t maxaddr, PosixFile& f) {
  if (maxaddr == 0 || maxaddr == HADDR_UNDEF || maxaddr > kMaxAddr) {
    push_error("open_file", H5E_CANTOPENFILE, "bad maximum address");
    return false;
  }
  const int fd = ::open(name, oflags | O_CLOEXEC, 0666);
  if (fd < 0) {
    push_error("open_file", H5E_CANTOPENFILE,
               std::string("cannot open the file: ") + std::strerror(errno));
    return false;
  }
  struct stat st {};
  if (fstat(fd, &st) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    push_error("open_file", H5E_CANTOPENFILE, "cannot stat the file: " + why);
    return false;
  }
  f.fd = fd;
  f.dev = st.st_dev;
  f.ino = st.st_ino;
  f.eof = static_cast<haddr_t>(st.st_size);
  return true;
}

// A driver's file of type F (a PosixFile with more) holding the file `opened` opened; null, the
// file closed and an error pushed, if there is no memory for it.
template <class F>
F* adopt(const PosixFile& opened) {
  auto* f = new (std::nothrow) F();
  if (f == nullptr) {
    ::close(opened.fd);
    push_error("open_file", H5E_CANTALLOC, "out of memory");
    return nullptr;
  }
  static_cast<PosixFile&>(*f) = opened;
  return f;
}

// Whether [addr, addr + size) lies inside HDF5's allocation of the file: outside is HDF5's own
// error (or a damaged file's).
inline bool allocated(const PosixFile& f, haddr_t addr, std::size_t size) {
  return addr != HADDR_UNDEF && addr <= kMaxAddr && size <= kMaxAddr - addr && addr + size <= f.eoa;
}

namespace posix_callbacks {

inline int compare(const H5FD_t* a, const H5FD_t* b) {
  const PosixFile *x = posix(a), *y = posix(b);
  if (x->dev != y->dev) return x->dev < y->dev ? -1 : 1;
  if (x->ino != y->ino) return x->ino < y->ino ? -1 : 1;
  return 0;
}

inline haddr_t get_eoa(const H5FD_t* f, H5FD_mem_t /*type*/) { return posix(f)->eoa; }

inline herr_t set_eoa(H5FD_t* f, H5FD_mem_t /*type*/, haddr_t addr) {
  if (addr > kMaxAddr) return push_error("set_eoa", H5E_OVERFLOW, "address overflow");
  posix(f)->eoa = addr;
  return 0;
}

inline haddr_t get_eof(const H5FD_t* f, H5FD_mem_t /*type*/) { return posix(f)->eof; }

inline herr_t get_handle(H5FD_t* f, hid_t /*fapl*/, void** handle) {
  if (handle == nullptr) return push_error("get_handle", H5E_BADVALUE, "no handle pointer");
  *handle = &posix(f)->fd;
  return 0;
}

}  // namespace posix_callbacks

// A driver class with `name` and the callbacks above; the caller adds open, close, query, read,
// write, flush and truncate.
inline H5FD_class_t posix_class(const char* name) {
  H5FD_class_t c{};
  c.name = name;
  c.maxaddr = kMaxAddr;
  c.fc_degree = H5F_CLOSE_WEAK;
  c.cmp = posix_callbacks::compare;
  c.get_eoa = posix_callbacks::get_eoa;
  c.set_eoa = posix_callbacks::set_eoa;
  c.get_eof = posix_callbacks::get_eof;
  c.get_handle = posix_callbacks::get_handle;
  const H5FD_mem_t map[] = H5FD_FLMAP_DICHOTOMY;
  std::copy(std::begin(map), std::end(map), std::begin(c.fl_map));
  return c;
}

}  // namespace slice::h5

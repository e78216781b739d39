#include "write_driver.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "posix_io.hpp"

namespace slice::h5 {

namespace {

struct WritingFile : PosixFile {
  WriteFailure* failure = nullptr;  // from the file access property list
};

WritingFile* cast(H5FD_t* f) { return static_cast<WritingFile*>(posix(f)); }

// What the system refused: kept (the first only) and from then on nothing more is written.
void refused(WritingFile& wf) {
  if (wf.failure->error == 0) wf.failure->error = errno != 0 ? errno : EIO;
}

H5FD_t* open_file(const char* name, unsigned flags, hid_t fapl, haddr_t maxaddr) {
  const auto* info = static_cast<WriteFailure* const*>(H5Pget_driver_info(fapl));
  if (info == nullptr || *info == nullptr) {
    push_error("open_file", H5E_CANTOPENFILE, "no failure record in the file access list");
    return nullptr;
  }
  int oflags = (flags & H5F_ACC_RDWR) != 0 ? O_RDWR : O_RDONLY;
  if ((flags & H5F_ACC_TRUNC) != 0) oflags |= O_TRUNC;
  if ((flags & H5F_ACC_CREAT) != 0) oflags |= O_CREAT;
  if ((flags & H5F_ACC_EXCL) != 0) oflags |= O_EXCL;
  PosixFile opened;
  if (!open_posix(name, oflags, maxaddr, opened)) return nullptr;
  auto* wf = adopt<WritingFile>(opened);
  if (wf == nullptr) return nullptr;
  wf->failure = *info;
  return &wf->pub;
}

herr_t close_file(H5FD_t* f) {
  WritingFile* wf = cast(f);
  errno = 0;
  if (::close(wf->fd) != 0) refused(*wf);  // a delayed write error (NFS) shows here
  delete wf;
  return 0;
}

// sec2's features, so that HDF5 lays out and writes the same bytes as with its default driver.
herr_t query(const H5FD_t* /*f*/, unsigned long* flags) {
  if (flags != nullptr)
    *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
             H5FD_FEAT_AGGREGATE_SMALLDATA | H5FD_FEAT_POSIX_COMPAT_HANDLE |
             H5FD_FEAT_SUPPORTS_SWMR_IO | H5FD_FEAT_DEFAULT_VFD_COMPATIBLE;
  return 0;
}

herr_t read_file(H5FD_t* f, H5FD_mem_t /*type*/, hid_t /*dxpl*/, haddr_t addr, std::size_t size,
                 void* buffer) {
  WritingFile* wf = cast(f);
  if (!allocated(*wf, addr, size))
    return push_error("read_file", H5E_OVERFLOW, "address past the end of the file's allocation");
  if (!read_at(wf->fd, addr, size, static_cast<unsigned char*>(buffer)))
    return push_error("read_file", H5E_READERROR,
                      std::string("read failed: ") + std::strerror(errno));
  return 0;
}

herr_t write_file(H5FD_t* f, H5FD_mem_t /*type*/, hid_t /*dxpl*/, haddr_t addr, std::size_t size,
                  const void* buffer) {
  WritingFile* wf = cast(f);
  if (!allocated(*wf, addr, size))
    return push_error("write_file", H5E_OVERFLOW, "address past the end of the file's allocation");
  if (wf->failure->error == 0 &&
      !write_at(wf->fd, addr, size, static_cast<const unsigned char*>(buffer)))
    refused(*wf);
  wf->eof = std::max(wf->eof, addr + size);
  return 0;
}

// As sec2: the file ends where HDF5's allocation ends.
herr_t truncate_file(H5FD_t* f, hid_t /*dxpl*/, hbool_t /*closing*/) {
  WritingFile* wf = cast(f);
  if (wf->eoa == wf->eof) return 0;
  if (wf->failure->error == 0 && ftruncate(wf->fd, static_cast<off_t>(wf->eoa)) != 0) refused(*wf);
  wf->eof = wf->eoa;
  return 0;
}

H5FD_class_t make_class() {
  H5FD_class_t c = posix_class("rockslice-writing");
  c.fapl_size = sizeof(WriteFailure*);  // HDF5 copies the pointer with the property list
  c.open = open_file;
  c.close = close_file;
  c.query = query;
  c.read = read_file;
  c.write = write_file;
  c.truncate = truncate_file;
  return c;
}

}  // namespace

std::int64_t writing_fapl(WriteFailure* failure) {
  static const H5FD_class_t cls = make_class();
  static const hid_t driver = H5FDregister(&cls);
  if (driver < 0) return -1;
  const hid_t p = H5Pcreate(H5P_FILE_ACCESS);
  if (p < 0) return -1;
  if (H5Pset_driver(p, driver, &failure) < 0) {
    H5Pclose(p);
    return -1;
  }
  return p;
}

}  // namespace slice::h5

#include "slice/output.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <vector>

#include "slice/error.hpp"

namespace slice {
namespace {

namespace fs = std::filesystem;

// The .partial files alive in this process, for remove_partial_files(). A signal handler may read
// it at any moment, so a slot holds a heap copy of the path published by one atomic store, and
// is emptied (exchange) before the copy is freed. The one global state of the library: a signal
// handler can reach nothing else.
constexpr std::size_t kSlots = 32;
std::array<std::atomic<char*>, kSlots> g_partials{};
static_assert(std::atomic<char*>::is_always_lock_free);

int register_partial(const fs::path& p) {
  const std::string s = fs::absolute(p).string();
  auto copy = std::make_unique<char[]>(s.size() + 1);
  std::memcpy(copy.get(), s.c_str(), s.size() + 1);
  for (std::size_t i = 0; i < kSlots; ++i) {
    char* expected = nullptr;
    if (g_partials[i].compare_exchange_strong(expected, copy.get())) {
      copy.release();
      return int(i);
    }
  }
  return -1;  // more outputs at once than slots: this one is only removed by its destructor
}

void unregister_partial(int slot) {
  if (slot < 0) return;
  std::unique_ptr<char[]> old(g_partials[std::size_t(slot)].exchange(nullptr));
}

// A write lock on the whole file, of the open file description (F_OFD_SETLK): it is not lost
// when another descriptor of the file is closed (as HDF5 closes its own), and it does not
// conflict with the flock(2) locks HDF5 takes.
bool lock_whole(int fd) {
  struct flock l {};
  l.l_type = F_WRLCK;
  l.l_whence = SEEK_SET;
  return ::fcntl(fd, F_OFD_SETLK, &l) == 0;
}

// Creates `path` (in `dir`) already locked: the file is made unnamed (O_TMPFILE), locked, then
// linked under its name, so no other run can find it unlocked. Where the file system has no
// O_TMPFILE, created by name and then locked, and checked to be still the file the path names.
// The descriptor, or -1 with errno (EEXIST: another run's file is there).
int create_locked(const fs::path& path, const fs::path& dir) {
  int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
  if (fd >= 0) {
    const std::string self = "/proc/self/fd/" + std::to_string(fd);
    if (lock_whole(fd) &&
        ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, path.c_str(), AT_SYMLINK_FOLLOW) == 0)
      return fd;
    const int error = errno;
    ::close(fd);
    errno = error;
    return -1;
  }
  if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) return -1;
  fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) return -1;
  struct stat mine {};
  struct stat named {};
  if (lock_whole(fd) && ::fstat(fd, &mine) == 0 && ::lstat(path.c_str(), &named) == 0 &&
      mine.st_dev == named.st_dev && mine.st_ino == named.st_ino)
    return fd;
  ::close(fd);  // another run took it as stale and replaced it
  errno = EEXIST;
  return -1;
}

}  // namespace

std::string not_a_regular_file(const fs::path& out) {
  // The chain of symlinks, each hop checked: /dev/stdout -> /proc/self/fd/1 -> /tmp/log is a
  // regular file at the end, yet the name stands for a descriptor of whichever process opens it.
  std::error_code ec;
  fs::path p = fs::absolute(out, ec);
  if (ec) return "";
  for (int hops = 0; hops < 40; ++hops) {
    const std::string norm = p.lexically_normal().string();
    if (norm.rfind("/proc/", 0) == 0)
      return "is a link to " + norm + " (a descriptor or a kernel file, not a file)";
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) break;
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) break;
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  struct stat st {};
  if (::stat(out.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return "";  // missing: a new file
  if (S_ISDIR(st.st_mode)) return "is a directory";
  if (S_ISFIFO(st.st_mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISCHR(st.st_mode)) return "is a character device, not a regular file";
  if (S_ISBLK(st.st_mode)) return "is a block device, not a regular file";
  if (S_ISSOCK(st.st_mode)) return "is a socket, not a regular file";
  return "is not a regular file";
}

void settle_truncation(const fs::path& path) noexcept {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd >= 0) ::close(fd);
}

namespace {

void rename_onto(const fs::path& partial, const fs::path& out) {
  std::error_code ec;
  fs::rename(partial, out, ec);
  if (ec)
    throw Error(out.string(),
                "cannot replace it with the finished " + partial.filename().string() + " (" +
                    ec.message() + ")",
                "check that it is not a directory and that its directory is writable");
}

// Outputs complete but held back (hold_commits): their .partial, registry slot and lock.
struct Held {
  fs::path out, partial;
  int slot = -1, lock = -1;
};
std::mutex g_held_mutex;
bool g_holding = false;
std::vector<Held> g_held;

// Ends a held output: renamed already, or (`remove`) deleted.
void release(Held& h, bool remove) noexcept {
  unregister_partial(h.slot);
  if (remove) {
    std::error_code ec;
    if (fs::is_regular_file(fs::symlink_status(h.partial, ec))) fs::remove(h.partial, ec);
  }
  if (h.lock >= 0) ::close(h.lock);
}

}  // namespace

namespace {

// The file an output path stands for: the path, or where its symbolic links lead (a link to a
// file, or one that dangles: the file it names is made). Written there, the link stays a link;
// renamed onto, the link itself was replaced by the new file and its target kept the old one.
fs::path written_file(const fs::path& out) {
  fs::path p = out;
  for (int hops = 0; hops < 40; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    std::error_code ec;
    const fs::path target = fs::read_symlink(p, ec);
    if (ec) return p;
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  throw Error(out.string(), "is a loop of symbolic links (or a chain of more than 40)",
              "give the path of a regular file (or of none yet) for the output; nothing was "
              "written");
}

}  // namespace

void check_output_place(const fs::path& out, const std::string& option) {
  if (out.empty())  // not a name: the rename of ".partial" onto it would be the first to fail
    throw Error("the output path", "is empty", "give the name of the file to write");
  const fs::path file = written_file(out);
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  const std::string give = option.empty() ? "give the output " : "give " + option + " ";
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error(out.string(), "the directory " + dir.string() + " does not exist",
                "create it or " + give + "another path; nothing was written");
  if (fs::is_directory(out, ec))
    throw Error(out.string(), "is a directory", give + "a file name; nothing was written");
  // Renamed onto, a FIFO, a device (/dev/null) or /dev/stdout would be replaced: refused,
  // untouched.
  if (const std::string what = not_a_regular_file(out); !what.empty())
    throw Error(out.string(), what,
                give + "the path of a regular file (or of none yet); nothing was written");
}

PartialFile::PartialFile(fs::path out) : out_(std::move(out)) {
  check_output_place(out_);
  file_ = written_file(out_);
  partial_ = file_.string() + ".partial";
  const fs::path dir = file_.has_parent_path() ? file_.parent_path() : fs::path(".");
  std::error_code ec;
  // Create the .partial locked. A .partial already there is another live run's while that run
  // holds its lock; otherwise it is stale (a run killed by SIGKILL or a power cut) and is
  // replaced. A symlink there is removed, never followed. Another run may do the same at the
  // same moment: whoever creates the file first writes, the other looks again.
  for (int attempt = 0;; ++attempt) {
    if (attempt == 8)
      throw Error(out_.string(), "another run keeps replacing " + partial_.filename().string(),
                  "run one tool at a time on an output");
    const fs::file_status st = fs::symlink_status(partial_, ec);
    if (fs::is_directory(st))
      throw Error(out_.string(), "a directory " + partial_.filename().string() + " is in the way",
                  "remove it or choose another output path");
    if (fs::is_regular_file(st)) {
      const int fd = ::open(partial_.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC);
      if (fd >= 0) {
        const bool live = !lock_whole(fd) && (errno == EAGAIN || errno == EACCES);
        ::close(fd);  // releases the lock taken to test it
        if (live)
          throw Error(out_.string(),
                      "another run is writing it (" + partial_.filename().string() +
                          " is locked by a live process)",
                      "wait for that run to finish, or choose another output path");
      }
    }
    if (fs::exists(st) && !fs::remove(partial_, ec) && ec)
      throw Error(
          out_.string(),
          "cannot remove the stale " + partial_.filename().string() + " (" + ec.message() + ")",
          "remove it by hand or choose another output path");
    // Registered before it exists, so that a signal from the moment it does removes it.
    slot_ = register_partial(partial_);
    const int fd = create_locked(partial_, dir);
    if (fd >= 0) {
      lock_ = fd;
      return;
    }
    const int error = errno;
    unregister_partial(slot_);
    slot_ = -1;
    if (error != EEXIST)  // EEXIST: another run got there first, look again
      throw Error(
          out_.string(),
          "cannot create " + partial_.filename().string() + " (" + std::strerror(error) + ")",
          write_error_fix(error));
  }
}

PartialFile::~PartialFile() {
  if (!committed_) {
    unregister_partial(slot_);
    // Only ever a regular file of ours: never a directory someone put there.
    std::error_code ec;
    if (fs::is_regular_file(fs::symlink_status(partial_, ec))) fs::remove(partial_, ec);
  }
  if (lock_ >= 0) ::close(lock_);
}

void PartialFile::commit() {
  {
    const std::lock_guard lock(g_held_mutex);
    if (g_holding) {
      g_held.push_back({file_, partial_, slot_, lock_});
      slot_ = lock_ = -1;  // the held output owns them now
      committed_ = true;
      return;
    }
  }
  rename_onto(partial_, file_);
  committed_ = true;
  unregister_partial(slot_);
  slot_ = -1;
}

void hold_commits() {
  const std::lock_guard lock(g_held_mutex);
  g_holding = true;
}

void commit_held_outputs() {
  std::vector<Held> held;
  {
    const std::lock_guard lock(g_held_mutex);
    held.swap(g_held);
    g_holding = false;
  }
  std::size_t done = 0;
  try {
    for (; done < held.size(); ++done) {
      rename_onto(held[done].partial, held[done].out);
      release(held[done], false);
    }
  } catch (...) {
    for (; done < held.size(); ++done) release(held[done], true);
    throw;
  }
}

void discard_held_outputs() noexcept {
  std::vector<Held> held;
  {
    const std::lock_guard lock(g_held_mutex);
    held.swap(g_held);
    g_holding = false;
  }
  for (Held& h : held) release(h, true);
}

void remove_partial_files() noexcept {
  for (auto& slot : g_partials)
    if (const char* p = slot.load()) ::unlink(p);
}

std::string system_reason() {
  const int e = errno;
  return e ? " (" + std::string(std::strerror(e)) + ")" : std::string();
}

std::string write_error_fix(int error) {
  switch (error) {
    case EFBIG: {  // RLIMIT_FSIZE (ulimit -f), or the file system's largest file
      rlimit lim{};
      if (::getrlimit(RLIMIT_FSIZE, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY)
        return "raise the file size limit (ulimit -f; it is " + std::to_string(lim.rlim_cur) +
               " bytes now) or write a smaller file";
      return "the file system cannot hold a file this large: write it to another one";
    }
    case ENOSPC:
      return "make room on the disk or write to another one";
    case EDQUOT:
      return "your disk quota is used up: free some of it or write elsewhere";
    case EACCES:
    case EPERM:
      return "check that the directory is writable";
    case EROFS:
      return "the file system is read-only: write elsewhere";
    case EIO:
      return "the disk reported an error: check it, or write elsewhere";
    default:
      return "check that the directory is writable and the disk is not full";
  }
}

void write_text_file(const fs::path& out, const std::string& text) {
  PartialFile part(out);
  {
    errno = 0;
    std::ofstream s(part.path(), std::ios::binary);
    s << text;
    s.flush();
    if (!s) {
      const int e = errno;
      throw Error(out.string(), "cannot write " + part.path().filename().string() + system_reason(),
                  write_error_fix(e));
    }
  }
  part.commit();
}

}  // namespace slice

#pragma once
// Atomic outputs. Every file a tool writes is written to "<out>.partial" in the same directory
// and renamed onto `out` only when complete, so a failed, interrupted or killed run never leaves
// a half-written file that looks valid and never damages an existing `out`. A run holds a lock
// on each .partial it writes (an open file description lock), so a second run on the same
// output is refused while the first is alive, and a .partial nobody holds is stale. A tool with
// several outputs holds back the renames (hold_commits) until every output is complete.
#include <filesystem>
#include <string>

namespace slice {

/// One output in progress. An output that is a symbolic link (to a file, or dangling) is written
/// where the link leads, and the link kept. The constructor replaces a stale "<out>.partial" (left
/// by a run that was killed), creates the .partial and locks it, and registers it so that
/// remove_partial_files() can delete it from a signal handler. If commit() is never reached (an
/// exception), the destructor removes it.
class PartialFile {
 public:
  /// Throws Error if the directory of `out` does not exist, if `out` is a directory or another
  /// file that is not a regular one (not_a_regular_file), if a directory stands where the
  /// .partial goes, if the .partial cannot be created, or if another live run holds it (writes
  /// the same output).
  explicit PartialFile(std::filesystem::path out);
  ~PartialFile();
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;

  const std::filesystem::path& path() const { return partial_; }
  const std::filesystem::path& target() const { return out_; }
  /// Renames the .partial onto `out` (atomic on POSIX). Throws Error on failure. While commits
  /// are held (hold_commits), the complete .partial is kept, still locked and registered, for
  /// commit_held_outputs() to rename.
  void commit();

 private:
  std::filesystem::path out_;
  std::filesystem::path file_;  // out_, or where its symlinks lead: renamed onto, links kept
  std::filesystem::path partial_;
  int slot_ = -1;  // registry slot (-1: not registered)
  int lock_ = -1;  // descriptor holding the lock on the .partial (-1: none)
  bool committed_ = false;
};

/// From now on PartialFile::commit() keeps each complete output as its .partial, until
/// commit_held_outputs() renames them all or discard_held_outputs() deletes them: a run with
/// several outputs (blocks.h5 and --stats, blocks.vtu and --joints, a 3DEC grid and its
/// commands) replaces none of the existing ones unless every new one is complete. For the main
/// thread of a tool.
void hold_commits();
/// Renames every held output onto its target, in the order they were completed, and stops
/// holding. Throws Error on a failed rename (the ones not yet renamed are deleted).
void commit_held_outputs();
/// Deletes every held output and stops holding (a run that failed after some outputs were
/// complete).
void discard_held_outputs() noexcept;

/// What `out` is if it is an output a rename must not replace, "" otherwise (it does not exist,
/// or is a regular file or a symlink to one). Renaming the finished .partial onto a FIFO, a
/// device node (/dev/null, /dev/full) or a link to a process's descriptor (/dev/stdout ->
/// /proc/self/fd/1) would replace that special file by a regular one (as root, /dev/stdout
/// itself): "is a FIFO (named pipe)", "is a character device", "is a directory", "is a link to
/// /proc/self/fd/1 (a descriptor, not a file)", ... For the error lines of PartialFile and of
/// the tools, which check every output before writing any.
std::string not_a_regular_file(const std::filesystem::path& out);

/// Throws Error unless `out` can be an output: the directory of the file it is written to (where
/// its symbolic links lead, so a link into a missing folder is refused here, not after the work)
/// exists, and `out` is no directory and nothing else not_a_regular_file names. `option` ("-o",
/// "--joints") names the option in the advice of a tool's line; empty for the library's own.
/// PartialFile checks this first; the tools check every output before they write any.
void check_output_place(const std::filesystem::path& out, const std::string& option = "");

/// Deletes every .partial of a PartialFile alive in this process. Async-signal-safe (only
/// atomic loads and unlink(2)): for a SIGINT / SIGTERM handler, which then re-raises the signal.
void remove_partial_files() noexcept;

/// " (<what the system said>)" for the errno of a failed write, e.g. " (No space left on
/// device)"; "" if errno is 0. For the messages of writers that use streams.
std::string system_reason();

/// The fix for a write the system refused with `error` (an errno): "raise the file size limit
/// (ulimit -f; it is 1024 bytes now) ..." for EFBIG, "make room on the disk ..." for ENOSPC,
/// "check that the directory is writable" for EACCES, ...; never advice that does not fit.
std::string write_error_fix(int error);

/// For a writer that has just opened `path` with truncation (HDF5's H5Fcreate, fopen "wb") while
/// it is empty: takes now, at no cost, the flush that ext4 (auto_da_alloc) and XFS otherwise make
/// when the file is next closed, to guard programs that rewrite a file in place without fsync.
/// A .partial is truncated only because PartialFile made it empty to hold its lock; that flush at
/// the end cost slice-vertices 0.3 s for a 938 MB geom.h5. Opens and closes a descriptor of it
/// (either file system clears its mark on any close); nothing if it cannot be opened.
void settle_truncation(const std::filesystem::path& path) noexcept;

/// Writes `text` to `out` atomically (through a PartialFile). Throws Error naming `out`.
void write_text_file(const std::filesystem::path& out, const std::string& text);

}  // namespace slice

#pragma once
// Atomic outputs. Every file a tool writes is written to "<out>.partial" in the same directory
// and renamed onto `out` only when complete, so a failed, interrupted or killed run never leaves
// a half-written file that looks valid and never damages an existing `out`.
#include <filesystem>
#include <string>

namespace slice {

/// One output in progress. The constructor replaces a stale "<out>.partial" (left by a run that
/// was killed) and registers the .partial so that remove_partial_files() can delete it from a
/// signal handler. If commit() is never reached (an exception), the destructor removes it.
class PartialFile {
 public:
  /// Throws Error if the directory of `out` does not exist, if `out` is a directory, or if a
  /// directory stands where the .partial goes.
  explicit PartialFile(std::filesystem::path out);
  ~PartialFile();
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;

  const std::filesystem::path& path() const { return partial_; }
  const std::filesystem::path& target() const { return out_; }
  /// Renames the .partial onto `out` (atomic on POSIX). Throws Error on failure.
  void commit();

 private:
  std::filesystem::path out_;
  std::filesystem::path partial_;
  int slot_ = -1;  // registry slot (-1: not registered)
  bool committed_ = false;
};

/// Deletes every .partial of a PartialFile alive in this process. Async-signal-safe (only
/// atomic loads and unlink(2)): for a SIGINT / SIGTERM handler, which then re-raises the signal.
void remove_partial_files() noexcept;

/// Writes `text` to `out` atomically (through a PartialFile). Throws Error naming `out`.
void write_text_file(const std::filesystem::path& out, const std::string& text);

}  // namespace slice

#include "slice/output.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <cstring>
#include <fstream>
#include <memory>

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

}  // namespace

PartialFile::PartialFile(fs::path out)
    : out_(std::move(out)), partial_(out_.string() + ".partial") {
  const fs::path dir = out_.has_parent_path() ? out_.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error(out_.string(), "the directory " + dir.string() + " does not exist",
                "create it or choose another output path");
  if (fs::is_directory(out_, ec))
    throw Error(out_.string(), "is a directory", "give a file name for the output");
  // A stale .partial (a run killed by SIGKILL or a power cut) is replaced. A symlink is removed,
  // never followed: writing through it would truncate whatever it points to.
  const fs::file_status st = fs::symlink_status(partial_, ec);
  if (fs::is_directory(st))
    throw Error(out_.string(), "a directory " + partial_.filename().string() + " is in the way",
                "remove it or choose another output path");
  if (fs::exists(st) && !fs::remove(partial_, ec))
    throw Error(
        out_.string(),
        "cannot remove the stale " + partial_.filename().string() + " (" + ec.message() + ")",
        "remove it by hand or choose another output path");
  slot_ = register_partial(partial_);
}

PartialFile::~PartialFile() {
  unregister_partial(slot_);
  if (committed_) return;
  // Only ever a regular file of ours: never a directory someone put there.
  std::error_code ec;
  if (fs::is_regular_file(fs::symlink_status(partial_, ec))) fs::remove(partial_, ec);
}

void PartialFile::commit() {
  std::error_code ec;
  fs::rename(partial_, out_, ec);
  if (ec)
    throw Error(out_.string(),
                "cannot replace it with the finished " + partial_.filename().string() + " (" +
                    ec.message() + ")",
                "check that it is not a directory and that its directory is writable");
  committed_ = true;
  unregister_partial(slot_);
  slot_ = -1;
}

void remove_partial_files() noexcept {
  for (auto& slot : g_partials)
    if (const char* p = slot.load()) ::unlink(p);
}

void write_text_file(const fs::path& out, const std::string& text) {
  PartialFile part(out);
  {
    std::ofstream s(part.path(), std::ios::binary);
    s << text;
    s.flush();
    if (!s)
      throw Error(out.string(), "cannot write " + part.path().filename().string(),
                  "check that the directory is writable and the disk is not full");
  }
  part.commit();
}

}  // namespace slice

#pragma once
// What the DFN readers (dfn_fab.cpp, dfn_csv.cpp) share: a text file read line by line, every
// refusal one Error naming "<file>:<line>". Private to libslice/src/scene/.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace slice::dfn_text {

// The largest DFN file read, as meshes and surfaces (kMaxMeshFileBytes, mesh.hpp): a bigger one
// is refused by its size before it is read (a 2 GB file took 45 s and 4 GB of memory to fail).
// A network that big is split into several files, each its own [[dfn]] entry (docs/dfn.md).
constexpr std::uintmax_t kMaxDfnFileBytes = std::uintmax_t(256) << 20;

std::string_view trim(std::string_view s);
// At most `max` characters of s for a message, quoted: bytes that are no UTF-8 and control
// characters escaped (\xe9, \r), "..." where it is cut. A message never echoes a whole line,
// which may be a whole file (CR-only line ends of an old editor once were).
std::string excerpt(std::string_view s, std::size_t max = 40);
// Why s cannot be a name that outputs keep (HDF5 strings, Python str): a byte that is no UTF-8,
// a NUL or another control character; "" if it can.
std::string name_problem(std::string_view s);
// A whole number written as one ("12", "-3"), or nothing.
std::optional<std::int64_t> whole(std::string_view s);
// The file's bytes; Error naming it if it cannot be read. `kind` names it in messages ("FAB").
std::string read_file(const std::filesystem::path& file, const std::string& kind);

// The non-blank lines of a text, one at a time, trimmed. A line ends at LF, CRLF or a lone CR
// (old Mac files); a UTF-8 byte-order mark at the start is skipped (Windows editors write one).
class Lines {
 public:
  Lines(const std::filesystem::path& file, std::string text);

  // Moves to the next non-blank line; false at the end of the file.
  bool next();
  std::string_view text() const { return line_; }
  std::int64_t number() const { return number_; }
  // Bytes after the current line.
  std::uint64_t bytes_left() const { return text_.size() - pos_; }
  // The current line split at whitespace (`sep` 0) or at `sep`, each field trimmed.
  std::vector<std::string_view> fields(char sep = 0) const;
  // A field as a finite number; refused naming `what` otherwise.
  double number_at(std::string_view field, const std::string& what) const;
  // Refuses `name` (named `what` in the message: "set name") if name_problem() finds one.
  void check_name(std::string_view name, const std::string& what) const;

  [[noreturn]] void fail(const std::string& what, const std::string& fix) const;
  [[noreturn]] void fail_on(std::int64_t line, const std::string& what,
                            const std::string& fix) const;
  // At the end of the file: names its last line.
  [[noreturn]] void fail_at_end(const std::string& what, const std::string& fix) const;

 private:
  std::string file_;
  std::string text_;
  std::size_t pos_ = 0;
  std::string_view line_;
  std::int64_t number_ = 0;      // the current line's number
  std::int64_t read_lines_ = 0;  // lines passed so far, blank ones included
};

}  // namespace slice::dfn_text

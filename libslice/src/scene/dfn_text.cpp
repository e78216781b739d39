#include "dfn_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <system_error>

#include "slice/error.hpp"
#include "slice/utf8.hpp"

namespace slice::dfn_text {

std::string_view trim(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

std::optional<std::int64_t> whole(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::string excerpt(std::string_view s, std::size_t max) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out = "\"";
  std::size_t shown = 0, i = 0;
  for (; i < s.size() && shown < max; ++shown) {
    const auto [c, len] = decode_utf8(s, i);
    if (len == 0 || c < 0x20 || c == 0x7f) {
      const auto u = static_cast<unsigned char>(s[i]);
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
      ++i;
    } else {
      out.append(s.substr(i, len));
      i += len;
    }
  }
  out += i < s.size() ? "...\"" : "\"";
  return out;
}

std::string name_problem(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto [c, len] = decode_utf8(s, i);
    if (len == 0)
      return "is not UTF-8 text: its byte " + std::to_string(i + 1) + " (" +
             excerpt(s.substr(i, 1)) +
             ") begins no UTF-8 character (a Latin-1 or Windows-1252 file?)";
    if (c < 0x20 || c == 0x7f)
      return std::string("holds ") + (c == 0 ? "a NUL" : "a control") + " character at byte " +
             std::to_string(i + 1);
    i += len;
  }
  return "";
}

std::string read_file(const std::filesystem::path& file, const std::string& kind) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw Error(file.string(), "is not a file", "give the path of the " + kind + " file");
  if (const std::uintmax_t size = std::filesystem::file_size(file, ec);
      !ec && size > kMaxDfnFileBytes)
    throw Error(file.string(),
                "is " + std::to_string(size >> 20) + " MiB, more than the " +
                    std::to_string(kMaxDfnFileBytes >> 20) + " MiB a " + kind + " file may have",
                "split the network into files below that size, each its own [[dfn]] entry "
                "(docs/dfn.md, Large networks)");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string(), "cannot open the " + kind + " file", "check its permissions");
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw Error(file.string(), "reading the " + kind + " file failed", "check it");
  return text;
}

Lines::Lines(const std::filesystem::path& file, std::string text)
    : file_(file.string()), text_(std::move(text)) {
  if (text_.rfind("\xEF\xBB\xBF", 0) == 0) pos_ = 3;  // the byte-order mark U+FEFF
}

bool Lines::next() {
  while (pos_ < text_.size()) {
    const std::size_t end = std::min(text_.find_first_of("\r\n", pos_), text_.size());
    const std::string_view line = trim(std::string_view(text_).substr(pos_, end - pos_));
    pos_ = end;
    if (pos_ < text_.size()) pos_ += text_.compare(pos_, 2, "\r\n") == 0 ? 2 : 1;
    ++read_lines_;
    if (line.empty()) continue;
    line_ = line;
    number_ = read_lines_;
    return true;
  }
  line_ = {};
  return false;
}

std::vector<std::string_view> Lines::fields(char sep) const {
  std::vector<std::string_view> out;
  std::string_view s = line_;
  if (sep != 0) {
    while (true) {
      const std::size_t at = s.find(sep);
      out.push_back(trim(s.substr(0, at)));
      if (at == std::string_view::npos) return out;
      s.remove_prefix(at + 1);
    }
  }
  while (!(s = trim(s)).empty()) {
    std::size_t end = 0;
    while (end < s.size() && s[end] != ' ' && s[end] != '\t') ++end;
    out.push_back(s.substr(0, end));
    s.remove_prefix(end);
  }
  return out;
}

double Lines::number_at(std::string_view field, const std::string& what) const {
  const std::string f(field);
  char* end = nullptr;
  const double v = f.empty() ? 0 : std::strtod(f.c_str(), &end);
  if (f.empty() || end != f.c_str() + f.size())  // a NUL inside ends no number
    fail(what + " is " + excerpt(f) + ", not a number",
         "write a decimal number, e.g. 12.5 or 1e-3");
  if (!std::isfinite(v))
    fail(what + " is " + excerpt(f) + ", not a finite number", "give a finite value");
  return v;
}

void Lines::check_name(std::string_view name, const std::string& what) const {
  if (const std::string why = name_problem(name); !why.empty())
    fail(what + " " + excerpt(name) + " " + why,
         "rockslice's outputs keep names as UTF-8 text: save the file as UTF-8 (e.g. iconv -f "
         "latin1 -t utf-8) and without control characters");
}

void Lines::fail(const std::string& what, const std::string& fix) const {
  fail_on(number_, what, fix);
}
void Lines::fail_on(std::int64_t line, const std::string& what, const std::string& fix) const {
  // Each echo of the file is an excerpt(); this keeps any other from making a long line.
  constexpr std::size_t kMaxWhat = 600;
  throw Error(line > 0 ? file_ + ":" + std::to_string(line) : file_,
              what.size() > kMaxWhat ? what.substr(0, kMaxWhat) + "..." : what, fix);
}
void Lines::fail_at_end(const std::string& what, const std::string& fix) const {
  fail_on(read_lines_, what, fix);
}

}  // namespace slice::dfn_text

#include "dfn_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <system_error>

#include "slice/error.hpp"

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

std::string read_file(const std::filesystem::path& file, const std::string& kind) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw Error(file.string(), "is not a file", "give the path of the " + kind + " file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string(), "cannot open the " + kind + " file", "check its permissions");
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw Error(file.string(), "reading the " + kind + " file failed", "check it");
  return text;
}

bool Lines::next() {
  while (pos_ < text_.size()) {
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    const std::string_view line = trim(std::string_view(text_).substr(pos_, end - pos_));
    pos_ = end < text_.size() ? end + 1 : end;
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
  if (f.empty() || *end != '\0')
    fail(what + " is \"" + f + "\", not a number", "write a decimal number, e.g. 12.5 or 1e-3");
  if (!std::isfinite(v)) fail(what + " is " + f + ", not a finite number", "give a finite value");
  return v;
}

void Lines::fail(const std::string& what, const std::string& fix) const {
  fail_on(number_, what, fix);
}
void Lines::fail_on(std::int64_t line, const std::string& what, const std::string& fix) const {
  throw Error(line > 0 ? file_ + ":" + std::to_string(line) : file_, what, fix);
}
void Lines::fail_at_end(const std::string& what, const std::string& fix) const {
  fail_on(read_lines_, what, fix);
}

}  // namespace slice::dfn_text

#include "slice/error.hpp"

#include <string>

namespace slice {
namespace {
std::string compose(const std::string& where, const std::string& what, const std::string& fix) {
  std::string s = where.empty() ? what : where + ": " + what;
  if (!fix.empty()) s += "; " + fix;
  return escape_control(s);
}
}  // namespace

std::string escape_control(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
      continue;
    }
    switch (c) {
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default: {
        static constexpr char kHex[] = "0123456789abcdef";
        out += "\\x";
        out += kHex[u >> 4];
        out += kHex[u & 15];
      }
    }
  }
  return out;
}

Error::Error(const std::string& where, const std::string& what, const std::string& fix)
    : std::runtime_error(compose(where, what, fix)), where_(where), problem_(what), fix_(fix) {}

void assert_fail(const char* expr, const char* file, int line) {
  throw std::logic_error(std::string(file) + ":" + std::to_string(line) +
                         ": internal check failed: " + expr);
}

}  // namespace slice

#include "slice/error.hpp"

#include <string>

namespace slice {
namespace {
std::string compose(const std::string& where, const std::string& what, const std::string& fix) {
  std::string s = where.empty() ? what : where + ": " + what;
  if (!fix.empty()) s += "; " + fix;
  return s;
}
}  // namespace

Error::Error(const std::string& where, const std::string& what, const std::string& fix)
    : std::runtime_error(compose(where, what, fix)) {}

void assert_fail(const char* expr, const char* file, int line) {
  throw std::logic_error(std::string(file) + ":" + std::to_string(line) +
                         ": internal check failed: " + expr);
}

}  // namespace slice

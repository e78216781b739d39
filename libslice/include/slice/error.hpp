#pragma once
// Errors the library throws. The library never prints or exits: a tool catches these.
//   slice::Error       bad input; what() = "<where>: <what>; <fix>"  -> exit code 1
//   std::logic_error   a broken invariant (a bug), via SLICE_ASSERT   -> exit code 2
#include <stdexcept>
#include <string>
#include <string_view>

namespace slice {

struct Error : std::runtime_error {
  /// Control characters in the parts (a newline in a scene key, say) are escaped, so what() is
  /// always one line.
  Error(const std::string& where, const std::string& what, const std::string& fix = {});
  /// The parts as given (unescaped): a caller that adds its own where or fix to a caught Error
  /// builds the new one from these, so the line holds one fix, not two.
  const std::string& where() const noexcept { return where_; }
  const std::string& problem() const noexcept { return problem_; }
  const std::string& fix() const noexcept { return fix_; }

 private:
  std::string where_, problem_, fix_;
};

/// `s` with every control character escaped ("\n", "\t", "\x1b", ...): one printable line.
std::string escape_control(std::string_view s);

[[noreturn]] void assert_fail(const char* expr, const char* file, int line);

}  // namespace slice

#define SLICE_ASSERT(cond) \
  ((cond) ? static_cast<void>(0) : ::slice::assert_fail(#cond, __FILE__, __LINE__))

#pragma once
// Errors the library throws. The library never prints or exits: a tool catches these.
//   slice::Error       bad input; what() = "<where>: <what>; <fix>"  -> exit code 1
//   std::logic_error   a broken invariant (a bug), via SLICE_ASSERT   -> exit code 2
#include <stdexcept>
#include <string>

namespace slice {

struct Error : std::runtime_error {
  Error(const std::string& where, const std::string& what, const std::string& fix = {});
};

[[noreturn]] void assert_fail(const char* expr, const char* file, int line);

}  // namespace slice

#define SLICE_ASSERT(cond) \
  ((cond) ? static_cast<void>(0) : ::slice::assert_fail(#cond, __FILE__, __LINE__))

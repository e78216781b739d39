#pragma once
// Which kernels run: the library's AVX2 kernels (the native LP's rows, the cut's reach test, the
// vertex extremes) give the portable kernels' bits, so either may run; the tests compare them.
#include <cstdlib>

namespace slice {

/// Whether to use the AVX2 kernels: the CPU has AVX2 and the environment variable SLICE_NO_AVX2
/// is not set (it selects the portable kernels, for the tests that compare the two).
inline bool use_avx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool yes = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0 && std::getenv("SLICE_NO_AVX2") == nullptr;
  }();
  return yes;
#else
  return false;
#endif
}

}  // namespace slice

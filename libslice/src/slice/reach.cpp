#include "reach.hpp"

namespace slice {

// Two copies, chosen when the program loads: AVX2 (four spheres at a time) and the x86-64
// baseline (two). Neither contracts a product and a sum into one rounding (no FMA), so both
// give ReachQuery's answer exactly.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void reach_mask(const ReachQuery& q, const double* x, const double* y, const double* z,
                const double* r, std::size_t n, std::uint8_t* mask) {
  const ReachQuery local = q;  // no store to mask can change it
  if (!local.polygon) {
    for (std::size_t i = 0; i < n; ++i)
      mask[i] =
          std::abs(local.a * x[i] + local.b * y[i] + local.c * z[i] - local.d) < r[i] + local.tol;
    return;
  }
  for (std::size_t i = 0; i < n; ++i) mask[i] = local(x[i], y[i], z[i], r[i]);
}

}  // namespace slice

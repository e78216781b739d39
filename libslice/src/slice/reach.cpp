#include "reach.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SLICE_REACH_AVX2 1
#endif

namespace slice {
namespace {

// Every sphere i < n for which `hit(i)` is called stops at the first call that returns true.
// One sphere at a time, with ReachQuery's own arithmetic.
template <class Hit>
bool scan_portable(const ReachQuery& q, const SphereArrays& s, std::size_t from, Hit hit) {
  for (std::size_t i = from; i < s.n; ++i)
    if (q(s.x[i], s.y[i], s.z[i], s.r[i]) && hit(i)) return true;
  return false;
}

#ifdef SLICE_REACH_AVX2
// Four spheres at a time (AVX2): ReachQuery's arithmetic operation for operation, the products
// summed in the same order and none fused with a sum (no FMA), so each lane's answer is the
// scalar one, bit for bit. The spheres past the last four go one at a time.
template <class Hit>
__attribute__((target("avx2"))) bool scan_avx2(const ReachQuery& q, const SphereArrays& s,
                                               Hit hit) {
  const __m256d a = _mm256_set1_pd(q.a), b = _mm256_set1_pd(q.b), c = _mm256_set1_pd(q.c);
  const __m256d d = _mm256_set1_pd(q.d), tol = _mm256_set1_pd(q.tol);
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
  const __m256d px = _mm256_set1_pd(q.px), py = _mm256_set1_pd(q.py), pz = _mm256_set1_pd(q.pz);
  const __m256d pr = _mm256_set1_pd(q.pr);
  const __m256d lx = _mm256_set1_pd(q.lo[0]), ly = _mm256_set1_pd(q.lo[1]),
                lz = _mm256_set1_pd(q.lo[2]);
  const __m256d hx = _mm256_set1_pd(q.hi[0]), hy = _mm256_set1_pd(q.hi[1]),
                hz = _mm256_set1_pd(q.hi[2]);
  std::size_t i = 0;
  for (; i + 4 <= s.n; i += 4) {
    const __m256d x = _mm256_loadu_pd(s.x + i), y = _mm256_loadu_pd(s.y + i);
    const __m256d z = _mm256_loadu_pd(s.z + i), r = _mm256_loadu_pd(s.r + i);
    // |a x + b y + c z - d| < r + tol
    const __m256d dist = _mm256_sub_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a, x), _mm256_mul_pd(b, y)), _mm256_mul_pd(c, z)),
        d);
    __m256d in = _mm256_cmp_pd(_mm256_and_pd(dist, magnitude), _mm256_add_pd(r, tol), _CMP_LT_OQ);
    if (q.polygon) {
      const __m256d dx = _mm256_sub_pd(x, px), dy = _mm256_sub_pd(y, py), dz = _mm256_sub_pd(z, pz);
      const __m256d reach = _mm256_add_pd(r, pr);
      const __m256d d2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                       _mm256_mul_pd(dz, dz));
      in = _mm256_and_pd(in, _mm256_cmp_pd(d2, _mm256_mul_pd(reach, reach), _CMP_LT_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_add_pd(x, r), lx, _CMP_GT_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_sub_pd(x, r), hx, _CMP_LT_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_add_pd(y, r), ly, _CMP_GT_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_sub_pd(y, r), hy, _CMP_LT_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_add_pd(z, r), lz, _CMP_GT_OQ));
      in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_sub_pd(z, r), hz, _CMP_LT_OQ));
    }
    for (unsigned bits = unsigned(_mm256_movemask_pd(in)); bits; bits &= bits - 1)
      if (hit(i + std::size_t(__builtin_ctz(bits)))) return true;
  }
  return scan_portable(q, s, i, hit);
}

bool have_avx2() {
  static const bool yes = __builtin_cpu_supports("avx2");
  return yes;
}
#endif

template <class Hit>
bool scan(const ReachQuery& q, const SphereArrays& s, bool vector, Hit hit) {
#ifdef SLICE_REACH_AVX2
  if (vector && have_avx2()) return scan_avx2(q, s, hit);
#endif
  static_cast<void>(vector);
  return scan_portable(q, s, 0, hit);
}

}  // namespace

bool reach_any(const ReachQuery& q, const SphereArrays& s, bool vector) {
  return scan(q, s, vector, [](std::size_t) { return true; });
}

void reach_list(const ReachQuery& q, const SphereArrays& s, std::vector<std::size_t>& out,
                bool vector) {
  scan(q, s, vector, [&out](std::size_t i) {
    out.push_back(i);
    return false;
  });
}

bool reach_vectorised() {
#ifdef SLICE_REACH_AVX2
  return have_avx2();
#else
  return false;
#endif
}

}  // namespace slice

#include "reach.hpp"

#include <algorithm>

#include "../cpu.hpp"
#include "slice/error.hpp"

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

#endif

template <class Hit>
bool scan(const ReachQuery& q, const SphereArrays& s, bool vector, Hit hit) {
#ifdef SLICE_REACH_AVX2
  if (vector && use_avx2()) return scan_avx2(q, s, hit);
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

void GroupBoxes::set(std::size_t g, const Vec3& lo, const Vec3& hi) {
  SLICE_ASSERT(g < kMax);
  if (!(lo.array() <= hi.array()).all()) {
    used_ &= ~(1u << g);
    return;
  }
  used_ |= 1u << g;
  const Vec3 c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  for (int k = 0; k < 3; ++k) {
    c_[k][g] = c[k];
    h_[k][g] = h[k];
    lo_[k][g] = lo[k];
    hi_[k][g] = hi[k];
  }
  extent_[g] = c.cwiseAbs().maxCoeff() + h.maxCoeff();
}

namespace {

/// GroupBoxes::may_reach's question in plain numbers.
struct BoxQuery {
  BoxQuery(const PreparedJoint& pj, double tolerance)
      : n{pj.plane.normal[0], pj.plane.normal[1], pj.plane.normal[2]},
        d(pj.plane.d),
        p{pj.centre[0], pj.centre[1], pj.centre[2]},
        radius(pj.radius),
        lo{pj.lo[0], pj.lo[1], pj.lo[2]},
        hi{pj.hi[0], pj.hi[1], pj.hi[2]},
        tol(tolerance),
        polygon(!pj.edges.empty()) {}
  double n[3], d, p[3], radius, lo[3], hi[3], tol;
  bool polygon;
};

/// Whether the box (centre c, half sizes h, corners lo and hi, slack's extent e) may hold a
/// sphere the joint reaches.
bool box_may_reach(const BoxQuery& q, const double* c, const double* h, const double* lo,
                   const double* hi, double e) {
  const double slack = q.tol + 1e-9 * (e + std::abs(q.d));
  // A sphere inside the box lies as far from the plane as the box, or farther ...
  const double dist = q.n[0] * c[0] + q.n[1] * c[1] + q.n[2] * c[2] - q.d;
  const double half = std::abs(q.n[0]) * h[0] + std::abs(q.n[1]) * h[1] + std::abs(q.n[2]) * h[2];
  if (std::abs(dist) > half + slack) return false;
  if (!q.polygon) return true;
  // ... and as far from the polygon's centre, plus its radius; its box is inside this one.
  double out2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double out = std::max(std::abs(q.p[k] - c[k]) - h[k], 0.0);
    out2 += out * out;
  }
  const double reach = q.radius + slack;
  if (out2 > reach * reach) return false;
  for (int k = 0; k < 3; ++k)
    if (q.lo[k] > hi[k] + slack || q.hi[k] < lo[k] - slack) return false;
  return true;
}

#ifdef SLICE_REACH_AVX2
// box_may_reach for four boxes at a time, the same arithmetic in the same order.
__attribute__((target("avx2"))) unsigned boxes_avx2(const BoxQuery& q, const double (*c)[8],
                                                    const double (*h)[8], const double (*lo)[8],
                                                    const double (*hi)[8], const double* e) {
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
  const __m256d zero = _mm256_setzero_pd();
  const __m256d tol = _mm256_set1_pd(q.tol), d = _mm256_set1_pd(q.d);
  const __m256d d_size = _mm256_set1_pd(std::abs(q.d)), scale = _mm256_set1_pd(1e-9);
  const __m256d radius = _mm256_set1_pd(q.radius);
  unsigned bits = 0;
  for (int g = 0; g < 8; g += 4) {
    const __m256d slack =
        _mm256_add_pd(tol, _mm256_mul_pd(scale, _mm256_add_pd(_mm256_load_pd(e + g), d_size)));
    __m256d dist = zero, half = zero;
    for (int k = 0; k < 3; ++k) {
      const __m256d n = _mm256_set1_pd(q.n[k]);
      const __m256d nk = _mm256_and_pd(n, magnitude);
      const __m256d ck = _mm256_load_pd(c[k] + g), hk = _mm256_load_pd(h[k] + g);
      dist = k == 0 ? _mm256_mul_pd(n, ck) : _mm256_add_pd(dist, _mm256_mul_pd(n, ck));
      half = k == 0 ? _mm256_mul_pd(nk, hk) : _mm256_add_pd(half, _mm256_mul_pd(nk, hk));
    }
    dist = _mm256_and_pd(_mm256_sub_pd(dist, d), magnitude);
    // Not greater (unordered: true), as the scalar tests reject only what compares greater.
    __m256d in = _mm256_cmp_pd(dist, _mm256_add_pd(half, slack), _CMP_NGT_UQ);
    if (q.polygon) {
      __m256d out2 = zero;
      for (int k = 0; k < 3; ++k) {
        const __m256d pk = _mm256_set1_pd(q.p[k]);
        const __m256d ck = _mm256_load_pd(c[k] + g), hk = _mm256_load_pd(h[k] + g);
        // max(0, x) keeps a NaN x, as std::max(x, 0.0) does.
        const __m256d out =
            _mm256_max_pd(zero, _mm256_sub_pd(_mm256_and_pd(_mm256_sub_pd(pk, ck), magnitude), hk));
        out2 = k == 0 ? _mm256_mul_pd(out, out) : _mm256_add_pd(out2, _mm256_mul_pd(out, out));
      }
      const __m256d reach = _mm256_add_pd(radius, slack);
      in = _mm256_and_pd(in, _mm256_cmp_pd(out2, _mm256_mul_pd(reach, reach), _CMP_NGT_UQ));
      for (int k = 0; k < 3; ++k) {
        const __m256d lok = _mm256_load_pd(lo[k] + g), hik = _mm256_load_pd(hi[k] + g);
        in = _mm256_and_pd(
            in, _mm256_cmp_pd(_mm256_set1_pd(q.lo[k]), _mm256_add_pd(hik, slack), _CMP_NGT_UQ));
        in = _mm256_and_pd(
            in, _mm256_cmp_pd(_mm256_set1_pd(q.hi[k]), _mm256_sub_pd(lok, slack), _CMP_NLT_UQ));
      }
    }
    bits |= unsigned(_mm256_movemask_pd(in)) << g;
  }
  return bits;
}
#endif

}  // namespace

unsigned GroupBoxes::may_reach(const PreparedJoint& pj, double tol, bool vector) const {
  const BoxQuery q(pj, tol);
#ifdef SLICE_REACH_AVX2
  if (vector && use_avx2()) return boxes_avx2(q, c_, h_, lo_, hi_, extent_) & used_;
#endif
  static_cast<void>(vector);
  unsigned bits = 0;
  for (std::size_t g = 0; g < kMax; ++g) {
    if (!(used_ >> g & 1u)) continue;
    const double c[3] = {c_[0][g], c_[1][g], c_[2][g]}, h[3] = {h_[0][g], h_[1][g], h_[2][g]};
    const double lo[3] = {lo_[0][g], lo_[1][g], lo_[2][g]};
    const double hi[3] = {hi_[0][g], hi_[1][g], hi_[2][g]};
    if (box_may_reach(q, c, h, lo, hi, extent_[g])) bits |= 1u << g;
  }
  return bits;
}

bool reach_vectorised() {
#ifdef SLICE_REACH_AVX2
  return use_avx2();
#else
  return false;
#endif
}

}  // namespace slice

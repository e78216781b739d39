#include "vertex_extremes.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "../cpu.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SLICE_VERTEX_AVX2 1
#endif

namespace slice::detail {
namespace {

// A vertex from faces whose normals' triple product is below this is too ill-conditioned to be
// worth it (its rounding grows as 1 / det); the LP answers those blocks.
constexpr double kMinDet = 1e-4;
// A multiplier this far below zero still proves optimality to ~1e-12 of the block's size.
constexpr double kMultiplierSlack = 1e-12;

// The directions the multipliers (ra, rb, rc) of objective +-e_t prove: bit 2t where all three
// are >= 0 (+e_t), bit 2t + 1 where all are <= 0 (-e_t), each up to the slack.
unsigned proves(const Vec3& ra, const Vec3& rb, const Vec3& rc) {
  unsigned bits = 0;
  for (int t = 0; t < 3; ++t) {
    if (ra[t] >= -kMultiplierSlack && rb[t] >= -kMultiplierSlack && rc[t] >= -kMultiplierSlack)
      bits |= 1u << (2 * t);
    if (ra[t] <= kMultiplierSlack && rb[t] <= kMultiplierSlack && rc[t] <= kMultiplierSlack)
      bits |= 1u << (2 * t + 1);
  }
  return bits;
}

// What one call finds, as the triples go by.
template <std::size_t V>
struct Search {
  std::array<VertexExtremes, V> out{};
  std::array<unsigned, V> wanted{};
  unsigned open = 0;  // variants still looking

  explicit Search(std::array<unsigned, V> w) {
    for (VertexExtremes& e : out) e.x.fill(Vec3::Zero());
    for (std::size_t v = 0; v < V; ++v) {
      wanted[v] = w[v] & 0x3fu;
      if (wanted[v]) open |= 1u << v;
    }
  }
  // The directions of `bits` variant v still wants (none once it has all it wants).
  unsigned fresh(std::size_t v, unsigned bits) const {
    return (open & (1u << v)) ? bits & wanted[v] & ~out[v].found : 0u;
  }
  // Vertex x, inside every face but the last (within `slack`), proves `proven` of each variant:
  // a variant takes them if x is inside its own last face too (variant 1's is (-n, -d), and
  // (-n) . x is -(n . x), exactly). False once no variant looks any more.
  bool take(const Face& last, const Vec3& x, double slack, const std::array<unsigned, V>& proven) {
    const double along = last.normal.dot(x);
    for (std::size_t v = 0; v < V; ++v) {
      if (!proven[v]) continue;
      if (!(v == 0 ? along <= last.d + slack : -along <= -last.d + slack)) continue;
      for (int dir = 0; dir < 6; ++dir)
        if (proven[v] & (1u << dir)) out[v].x[std::size_t(dir)] = x;
      out[v].found |= proven[v];
      if (out[v].found == wanted[v]) open &= ~(1u << v);
    }
    return open != 0;
  }
};

double largest_offset(std::span<const Face> faces) {
  double dmax = 0;
  for (const Face& f : faces) dmax = std::max(dmax, std::abs(f.d));
  return dmax;
}

// The rounding slack of a vertex's inside tests: its coordinates' error grows as 1 / det, so the
// slack is slack_scale(dmax) / |det|.
double slack_scale(double dmax) { return 16 * std::numeric_limits<double>::epsilon() * dmax; }
double inside_slack(double dmax, double det) { return slack_scale(dmax) / std::abs(det); }

// One triple at a time. The variants share every vertex: reversing the last face negates its
// normal and d, so the vertex of faces (i, j, last) is the same bits, only the sign of its last
// multiplier changes (and the last face's inside test).
template <std::size_t V>
std::array<VertexExtremes, V> portable(std::span<const Face> faces, Search<V> s) {
  const std::size_t m = faces.size();
  const double dmax = largest_offset(faces);
  std::array<Vec3, kVertexFaces * kVertexFaces> cross;  // cross[i * m + j] = n_i x n_j, i < j
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 1; j < m; ++j)
      cross[i * m + j] = faces[i].normal.cross(faces[j].normal);
  const std::size_t last = m - 1;
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = i + 1; j < m; ++j) {
      for (std::size_t k = j + 1; k < m; ++k) {
        // x = (d_i a + d_j b + d_k c) / det with a = n_j x n_k, b = n_k x n_i, c = n_i x n_j:
        // the rows of the inverse of (n_i n_j n_k)^T are a, b, c over det, so the multipliers
        // of objective e_t are (a_t, b_t, c_t) / det.
        const Vec3& a = cross[j * m + k];
        const Vec3 b = -cross[i * m + k];
        const Vec3& c = cross[i * m + j];
        const double det = faces[i].normal.dot(a);
        if (!(std::abs(det) >= kMinDet)) continue;
        // Variant 1 reverses face `last`: for k == last its c (and det) change sign.
        const bool flips = V == 2 && k == last;
        const Vec3 ra = a / det, rb = b / det, rc = c / det;
        std::array<unsigned, V> proven{};
        unsigned any = 0;
        for (std::size_t v = 0; v < V; ++v) {
          proven[v] = s.fresh(v, v == 1 && flips ? proves(ra, rb, -rc) : proves(ra, rb, rc));
          any |= proven[v];
        }
        if (!any) continue;
        const Vec3 x = faces[i].d * ra + faces[j].d * rb + faces[k].d * rc;
        const double slack = inside_slack(dmax, det);
        bool inside = true;
        for (std::size_t f = 0; f < last && inside; ++f)
          inside = faces[f].normal.dot(x) <= faces[f].d + slack;
        if (inside && !s.take(faces[last], x, slack, proven)) return s.out;
      }
    }
  }
  return s.out;
}

#ifdef SLICE_VERTEX_AVX2
// Four triples (i, j, k..k+3) at a time (AVX2), with the portable kernel's arithmetic operation
// for operation: the same products summed in the same order ((x + y) + z, as Eigen's dot and
// sums), none fused with a sum (no FMA), and divisions, which are correctly rounded in both. So
// each lane's determinant, multipliers, proofs, vertex and inside tests are the portable
// kernel's bits, and the lanes are taken in the portable kernel's order.
template <std::size_t V>
__attribute__((target("avx2"))) std::array<VertexExtremes, V> avx2(std::span<const Face> faces,
                                                                   Search<V> s) {
  const std::size_t m = faces.size();
  const double dmax = largest_offset(faces);
  // n_i x n_j (i < j) at [i * kRow + j], one array per component; a row's entries from m on are
  // zero (determinant 0: never a vertex), so a last group of four reads no garbage.
  constexpr std::size_t kRow = kVertexFaces + 3;
  alignas(32) double cx[kVertexFaces * kRow], cy[kVertexFaces * kRow], cz[kVertexFaces * kRow];
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = i + 1; j < m; ++j) {
      const Vec3 c = faces[i].normal.cross(faces[j].normal);
      cx[i * kRow + j] = c.x(), cy[i * kRow + j] = c.y(), cz[i * kRow + j] = c.z();
    }
    for (std::size_t j = m; j < m + 3; ++j)
      cx[i * kRow + j] = cy[i * kRow + j] = cz[i * kRow + j] = 0;
  }
  const std::size_t last = m - 1;
  // The faces but the last, for the inside tests four at a time; the padding (0 . x <= 0 +
  // slack) passes.
  alignas(32) double fx[kRow], fy[kRow], fz[kRow], fd[kRow];
  for (std::size_t f = 0; f < kRow; ++f) {
    const bool face = f < last;
    fx[f] = face ? faces[f].normal.x() : 0;
    fy[f] = face ? faces[f].normal.y() : 0;
    fz[f] = face ? faces[f].normal.z() : 0;
    fd[f] = face ? faces[f].d : 0;
  }
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
  const __m256d negate = _mm256_set1_pd(-0.0);
  const __m256d min_det = _mm256_set1_pd(kMinDet);
  const __m256d below = _mm256_set1_pd(-kMultiplierSlack), above = _mm256_set1_pd(kMultiplierSlack);
  const __m256d scale = _mm256_set1_pd(slack_scale(dmax));
  alignas(32) double r[9][4];  // ra, rb, rc (x, y, z each) per lane
  alignas(32) double slacks[4];
  alignas(32) std::uint64_t bits[2][4];  // proven directions per lane: variant 0, variant 1 flipped
  for (std::size_t i = 0; i < m; ++i) {
    const __m256d nx = _mm256_set1_pd(faces[i].normal.x()),
                  ny = _mm256_set1_pd(faces[i].normal.y()),
                  nz = _mm256_set1_pd(faces[i].normal.z());
    for (std::size_t j = i + 1; j < m; ++j) {
      const __m256d c[3] = {_mm256_set1_pd(cx[i * kRow + j]), _mm256_set1_pd(cy[i * kRow + j]),
                            _mm256_set1_pd(cz[i * kRow + j])};
      for (std::size_t k0 = j + 1; k0 < m; k0 += 4) {
        const __m256d a[3] = {_mm256_loadu_pd(cx + j * kRow + k0),
                              _mm256_loadu_pd(cy + j * kRow + k0),
                              _mm256_loadu_pd(cz + j * kRow + k0)};
        const __m256d det =
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, a[0]), _mm256_mul_pd(ny, a[1])),
                          _mm256_mul_pd(nz, a[2]));
        unsigned lanes = unsigned(
            _mm256_movemask_pd(_mm256_cmp_pd(_mm256_and_pd(det, magnitude), min_det, _CMP_GE_OQ)));
        if (k0 + 4 > m) lanes &= (1u << (m - k0)) - 1;
        if (!lanes) continue;
        const __m256d b[3] = {_mm256_xor_pd(_mm256_loadu_pd(cx + i * kRow + k0), negate),
                              _mm256_xor_pd(_mm256_loadu_pd(cy + i * kRow + k0), negate),
                              _mm256_xor_pd(_mm256_loadu_pd(cz + i * kRow + k0), negate)};
        __m256i up0 = _mm256_setzero_si256(), up1 = _mm256_setzero_si256();
        for (int t = 0; t < 3; ++t) {
          const __m256d ra = _mm256_div_pd(a[t], det), rb = _mm256_div_pd(b[t], det),
                        rc = _mm256_div_pd(c[t], det);
          _mm256_store_pd(r[t], ra), _mm256_store_pd(r[3 + t], rb), _mm256_store_pd(r[6 + t], rc);
          // As proves(): variant 1's flipped rc passes >= -slack where rc <= slack, and back.
          const __m256d ge = _mm256_and_pd(_mm256_cmp_pd(ra, below, _CMP_GE_OQ),
                                           _mm256_cmp_pd(rb, below, _CMP_GE_OQ));
          const __m256d le = _mm256_and_pd(_mm256_cmp_pd(ra, above, _CMP_LE_OQ),
                                           _mm256_cmp_pd(rb, above, _CMP_LE_OQ));
          const __m256d c_ge = _mm256_cmp_pd(rc, below, _CMP_GE_OQ);
          const __m256d c_le = _mm256_cmp_pd(rc, above, _CMP_LE_OQ);
          const __m256i plus = _mm256_set1_epi64x(1LL << (2 * t));
          const __m256i minus = _mm256_set1_epi64x(1LL << (2 * t + 1));
          up0 = _mm256_or_si256(
              up0, _mm256_and_si256(_mm256_castpd_si256(_mm256_and_pd(ge, c_ge)), plus));
          up0 = _mm256_or_si256(
              up0, _mm256_and_si256(_mm256_castpd_si256(_mm256_and_pd(le, c_le)), minus));
          if constexpr (V == 2) {
            up1 = _mm256_or_si256(
                up1, _mm256_and_si256(_mm256_castpd_si256(_mm256_and_pd(ge, c_le)), plus));
            up1 = _mm256_or_si256(
                up1, _mm256_and_si256(_mm256_castpd_si256(_mm256_and_pd(le, c_ge)), minus));
          }
        }
        _mm256_store_si256(reinterpret_cast<__m256i*>(bits[0]), up0);
        if constexpr (V == 2) _mm256_store_si256(reinterpret_cast<__m256i*>(bits[1]), up1);
        _mm256_store_pd(slacks, _mm256_div_pd(scale, _mm256_and_pd(det, magnitude)));
        for (; lanes; lanes &= lanes - 1) {
          const unsigned l = unsigned(__builtin_ctz(lanes));
          const std::size_t k = k0 + l;
          const bool flips = V == 2 && k == last;
          std::array<unsigned, V> proven{};
          unsigned any = 0;
          for (std::size_t v = 0; v < V; ++v) {
            proven[v] = s.fresh(v, unsigned(bits[v == 1 && flips ? 1 : 0][l]));
            any |= proven[v];
          }
          if (!any) continue;
          const double di = faces[i].d, dj = faces[j].d, dk = faces[k].d;
          const Vec3 x((di * r[0][l] + dj * r[3][l]) + dk * r[6][l],
                       (di * r[1][l] + dj * r[4][l]) + dk * r[7][l],
                       (di * r[2][l] + dj * r[5][l]) + dk * r[8][l]);
          const __m256d px = _mm256_set1_pd(x.x()), py = _mm256_set1_pd(x.y()),
                        pz = _mm256_set1_pd(x.z()), slack = _mm256_set1_pd(slacks[l]);
          bool inside = true;
          for (std::size_t f = 0; f < last && inside; f += 4) {
            const __m256d along =
                _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_load_pd(fx + f), px),
                                            _mm256_mul_pd(_mm256_load_pd(fy + f), py)),
                              _mm256_mul_pd(_mm256_load_pd(fz + f), pz));
            const __m256d limit = _mm256_add_pd(_mm256_load_pd(fd + f), slack);
            inside = _mm256_movemask_pd(_mm256_cmp_pd(along, limit, _CMP_LE_OQ)) == 0xf;
          }
          if (inside && !s.take(faces[last], x, slacks[l], proven)) return s.out;
        }
      }
    }
  }
  return s.out;
}

#endif

}  // namespace

template <std::size_t V>
std::array<VertexExtremes, V> vertex_extremes_of(std::span<const Face> faces,
                                                 std::array<unsigned, V> wanted, bool vector) {
  const Search<V> s(wanted);
  if (faces.size() < 4 || faces.size() > kVertexFaces || !s.open) return s.out;
#ifdef SLICE_VERTEX_AVX2
  if (vector && use_avx2()) return avx2<V>(faces, s);
#endif
  static_cast<void>(vector);
  return portable<V>(faces, s);
}

template std::array<VertexExtremes, 1> vertex_extremes_of<1>(std::span<const Face>,
                                                             std::array<unsigned, 1>, bool);
template std::array<VertexExtremes, 2> vertex_extremes_of<2>(std::span<const Face>,
                                                             std::array<unsigned, 2>, bool);

}  // namespace slice::detail

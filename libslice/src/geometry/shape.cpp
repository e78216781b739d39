// Block shape factors alpha and beta and the shape classes (slice/shape.hpp). Sources of the
// definitions: docs/block-shape.md.
#include "slice/shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "slice/error.hpp"

namespace slice {

namespace {

constexpr double kAlphaScale = 7.7;  // MBSCT.py: alpha = (surf_area * avg_cod_lng) / (7.7 * vol)
constexpr double kTie = 1e-9;        // relative to the longest chord
// Kalenchuk's beta: a chord counts as longer than the median only by more than this, relative
// to the longest chord. A chord equal to the median in exact arithmetic (a cube's face
// diagonals) then stays out wherever the block is: 1e6 m from the origin a 1 mm block's chords
// carry rounding of 1e-7 of its size, which tipped a cube's beta_k from 10/9 to 1.44 with 1e-9.
constexpr double kLongTie = 1e-6;

// The elongation index at vertex `end` of the longest chord: among the chords from `end` to the
// other vertices at least as long as the median chord, the smallest squared cosine between two.
// NaN if fewer than two such chords.
double end_index(std::span<const Vec3> v, std::size_t end, double median, double tie) {
  std::vector<Vec3> longs;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i == end) continue;
    const Vec3 c = v[i] - v[end];
    if (c.norm() >= median - tie) longs.push_back(c);
  }
  if (longs.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  double lo = 1;
  for (std::size_t i = 0; i < longs.size(); ++i)
    for (std::size_t j = i + 1; j < longs.size(); ++j) {
      const double c = longs[i].dot(longs[j]) / (longs[i].norm() * longs[j].norm());
      lo = std::min(lo, c * c);
    }
  return lo;
}

// Both ends' indices combined as MBSCT does: the harmonic mean where both are defined (0 if
// both are 0), the one that is defined otherwise.
double combine(double a, double b) {
  if (std::isnan(a)) return b;
  if (std::isnan(b)) return a;
  return a + b > 0 ? 2 * a * b / (a + b) : 0.0;
}

}  // namespace

const char* to_string(ShapeClass c) {
  switch (c) {
    case ShapeClass::C:
      return "C";
    case ShapeClass::PC:
      return "PC";
    case ShapeClass::P:
      return "P";
    case ShapeClass::CE:
      return "CE";
    case ShapeClass::EP:
      return "EP";
    case ShapeClass::E:
      return "E";
    case ShapeClass::none:
      break;
  }
  return "none";
}

ShapeClass shape_class(double alpha, double beta) {
  if (std::isnan(alpha) || std::isnan(beta)) return ShapeClass::none;
  if (beta > 0.75) return ShapeClass::E;
  if (beta > 0.3) return alpha <= 3 ? ShapeClass::CE : ShapeClass::EP;
  if (alpha <= 2) return ShapeClass::C;
  return alpha <= 5 ? ShapeClass::PC : ShapeClass::P;
}

ShapeClass kalenchuk_class(double alpha, double beta_k) {
  if (std::isnan(alpha) || std::isnan(beta_k)) return ShapeClass::none;
  if (beta_k >= 7) return ShapeClass::E;
  if (beta_k >= 4) return alpha < 3 ? ShapeClass::CE : ShapeClass::EP;
  if (alpha < 2) return ShapeClass::C;
  return alpha < 5 ? ShapeClass::PC : ShapeClass::P;
}

namespace {

// Kalenchuk's beta as UnBlocks-gen states it (Rasmussen 2020, SoftwareX 12:100577, eq. 5):
// 10 [sum (a . b)^2 / sum |a|^2 |b|^2]^2 over the pairs of chords a, b longer than the median
// (by more than `tie`: kLongTie), a = b included. With T = sum a a^T over those chords the sums are
// |T|_F^2 and (tr T)^2. NaN when no chord is longer than the median.
double kalenchuk_beta(std::span<const Vec3> v, const std::vector<double>& len, double median,
                      double tie) {
  Eigen::Matrix3d t = Eigen::Matrix3d::Zero();
  std::size_t k = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = i + 1; j < v.size(); ++j, ++k)
      if (len[k] > median + tie) {
        const Vec3 d = v[j] - v[i];
        t += d * d.transpose();
      }
  const double trace = t.trace();
  if (!(trace > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double ratio = t.squaredNorm() / (trace * trace);
  return 10 * ratio * ratio;
}

}  // namespace

BlockShape block_shape(std::span<const Vec3> v, double surface_area, double volume,
                       const std::string& where) {
  if (v.size() < 4)
    throw Error(
        where,
        "a block shape needs at least 4 vertices, this block has " + std::to_string(v.size()),
        "run slice-vertices on a pruned blocks.h5 (3-D) to get its /geometry");
  if (!(std::isfinite(volume) && volume > 0) || !(std::isfinite(surface_area) && surface_area > 0))
    throw Error(where,
                "block volume " + std::to_string(volume) + " and surface area " +
                    std::to_string(surface_area) + " must be positive and finite",
                "recompute /geometry with slice-vertices");
  for (const Vec3& x : v)
    if (!x.allFinite())
      throw Error(where, "a vertex is not finite", "recompute /geometry with slice-vertices");
  // All chords between vertex pairs: their mean (alpha), median and longest (beta).
  const std::size_t n = v.size();
  std::vector<double> len;
  len.reserve(n * (n - 1) / 2);
  double sum = 0, longest = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      len.push_back((v[i] - v[j]).norm());
      sum += len.back();
      longest = std::max(longest, len.back());
    }
  BlockShape s;
  s.alpha = surface_area * (sum / double(len.size())) / (kAlphaScale * volume);
  std::vector<double> sorted = len;  // the median as numpy's: the mean of the middle two
  const std::size_t m = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(m), sorted.end());
  double median = sorted[m];
  if (sorted.size() % 2 == 0)
    median = (median + *std::max_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(m))) / 2;
  const double tie = kTie * longest;
  // Every chord as long as the longest (within the tie tolerance) is a candidate; the smallest
  // beta among them, so that the answer does not depend on which one comes first.
  s.beta = std::numeric_limits<double>::quiet_NaN();
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j, ++k) {
      if (len[k] < longest - tie) continue;
      const double b = combine(end_index(v, i, median, tie), end_index(v, j, median, tie));
      if (!std::isnan(b) && !(b >= s.beta)) s.beta = b;
    }
  s.shape = shape_class(s.alpha, s.beta);
  s.beta_k = kalenchuk_beta(v, len, median, kLongTie * longest);
  s.shape_k = kalenchuk_class(s.alpha, s.beta_k);
  return s;
}

std::vector<BlockShape> block_shapes(const std::vector<Block>& blocks, const Geometry& g,
                                     int dimension) {
  if (dimension != 3)
    throw Error("/geometry",
                "block shape factors are defined for 3-D blocks, not for a 2-D "
                "section's polygons",
                "compute them on the 3-D scene the section was taken from");
  if (g.volume.size() != blocks.size() || g.vertex_offset.size() != blocks.size() + 1)
    throw Error("/geometry",
                "has " + std::to_string(g.volume.size()) + " blocks, /blocks has " +
                    std::to_string(blocks.size()),
                "recompute /geometry with slice-vertices");
  std::vector<BlockShape> out(blocks.size());
  std::size_t face = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    double area = 0;
    for (std::size_t f = 0; f < blocks[b].faces.size(); ++f, ++face) area += g.face_area.at(face);
    const auto first = std::size_t(g.vertex_offset[b]), last = std::size_t(g.vertex_offset[b + 1]);
    out[b] = block_shape(std::span<const Vec3>(g.vertices).subspan(first, last - first), area,
                         g.volume[b], "/geometry block " + std::to_string(b));
  }
  return out;
}

ShapeSummary summarise_shapes(const std::vector<BlockShape>& shapes,
                              const std::vector<double>& volume, const std::vector<bool>& keep,
                              bool kalenchuk) {
  ShapeSummary s;
  for (std::size_t b = 0; b < shapes.size(); ++b) {
    if (!keep.empty() && !keep[b]) continue;
    const auto c = std::size_t(kalenchuk ? shapes[b].shape_k : shapes[b].shape);
    ++s.count[c];
    s.volume[c] += volume.at(b);
  }
  return s;
}

}  // namespace slice

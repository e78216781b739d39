#include "slice/set_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>

#include "slice/error.hpp"

namespace slice {
namespace {

// The Kolmogorov-Smirnov statistic of ascending sizes x against the distribution function F.
double ks_statistic(const std::vector<double>& x, const std::function<double(double)>& cdf) {
  const double n = static_cast<double>(x.size());
  double d = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = cdf(x[i]);
    d = std::max({d, static_cast<double>(i + 1) / n - f, f - static_cast<double>(i) / n});
  }
  return d;
}

// b / expm1(b L): the power law's normalising factor, 1 / L at b = 0.
double power_norm(double b, double log_range) {
  const double bl = b * log_range;
  return std::abs(bl) < 1e-12 ? 1 / log_range : b / std::expm1(bl);
}

// The power law's exponent a (density proportional to x^-a on [lo, hi]) of largest likelihood:
// the log-likelihood n ln c(b) - n b ln lo - (1 - b) sum ln x, b = 1 - a, is concave in b (an
// exponential family in ln x), so a golden-section search finds its maximum.
double power_law_exponent(const std::vector<double>& x, double lo, double hi) {
  const double n = static_cast<double>(x.size());
  const double range = std::log(hi / lo);
  double sum_log = 0;
  for (const double v : x) sum_log += std::log(v / lo);  // relative to lo: b ln lo cancels
  const auto loglik = [&](double b) { return n * std::log(power_norm(b, range)) + b * sum_log; };
  // The exponent stays within +-kMaxExponent: beyond, the sizes all sit at one end.
  constexpr double kMaxExponent = 50;
  double a = 1 - kMaxExponent, b = 1 + kMaxExponent;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = loglik(c), fd = loglik(d);
  for (int it = 0; it < 200 && b - a > 1e-12; ++it) {
    if (fc > fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a), fc = loglik(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a), fd = loglik(d);
    }
  }
  return 1 - (a + b) / 2;
}

std::string num(double v, int digits = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v + 0.0);
  return buf;
}

// An angle with two decimals, [0, 360) for a dip direction (359.996 prints as 0.00).
std::string angle(double deg, bool direction) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f", deg + 0.0);
  if (direction && std::string(buf) == "360.00") return "0.00";
  return buf;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace

SizeFits fit_sizes(std::span<const double> sizes) {
  SizeFits out;
  out.count = sizes.size();
  if (sizes.empty()) return out;
  std::vector<double> x(sizes.begin(), sizes.end());
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i]) || !(x[i] > 0))
      throw Error("size fit", "size " + std::to_string(i) + " is " + num(x[i]) + ", not > 0",
                  "give finite sizes > 0");
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  out.ks_critical_95 = 1.358 / std::sqrt(n);
  const double lo = x.front(), hi = x.back();
  if (hi - lo <= kSameSize * hi) {
    SizeFit f;
    f.size.distribution = SizeDistribution::fixed;
    f.size.value = x[x.size() / 2];
    out.fits.push_back(f);
    return out;
  }
  double mean = 0, mean_log = 0;
  for (const double v : x) mean += v, mean_log += std::log(v);
  mean /= n, mean_log /= n;
  double var_log = 0;
  for (const double v : x) var_log += (std::log(v) - mean_log) * (std::log(v) - mean_log);
  var_log /= n;  // maximum likelihood (divides by n)
  const double sigma = std::sqrt(var_log);

  SizeFit logn;  // the scene's parameters: the mean and sd of the size itself
  logn.size.distribution = SizeDistribution::lognormal;
  logn.size.mean = std::exp(mean_log + var_log / 2);
  logn.size.sd = logn.size.mean * std::sqrt(std::expm1(var_log));
  logn.ks = ks_statistic(x, [&](double v) {
    return 0.5 * std::erfc(-(std::log(v) - mean_log) / (sigma * std::numbers::sqrt2));
  });
  out.fits.push_back(logn);

  SizeFit expo;
  expo.size.distribution = SizeDistribution::exponential;
  expo.size.mean = mean;
  expo.ks = ks_statistic(x, [&](double v) { return -std::expm1(-v / mean); });
  out.fits.push_back(expo);

  SizeFit pow;
  pow.size.distribution = SizeDistribution::power_law;
  pow.size.exponent = power_law_exponent(x, lo, hi);
  pow.size.min = lo;
  pow.size.max = hi;
  const double b = 1 - pow.size.exponent, range = std::log(hi / lo);
  pow.ks = ks_statistic(x, [&](double v) {
    const double t = std::log(v / lo);
    return std::abs(b * range) < 1e-12 ? t / range : std::expm1(b * t) / std::expm1(b * range);
  });
  out.fits.push_back(pow);

  for (std::size_t k = 1; k < out.fits.size(); ++k)
    if (out.fits[k].ks < out.fits[out.best].ks) out.best = k;
  return out;
}

namespace {

// The aspect of a polygon as an ellipse's: sqrt of the ratio of its principal second moments of
// area about its centroid (a regular polygon of 3 or more corners has equal ones, so the affine
// image of one with semi-axes a, b gives a / b exactly); 0 for a polygon without area.
double moment_aspect(const std::vector<Vec2>& p) {
  const std::size_t n = p.size();
  if (n < 3) return 0;
  const Vec2 o = p[0];  // about a corner, then moved to the centroid: less cancellation
  double area = 0, cx = 0, cy = 0, sxx = 0, syy = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = p[i] - o, b = p[(i + 1) % n] - o;
    const double c = a.x() * b.y() - b.x() * a.y();
    area += c / 2;
    cx += (a.x() + b.x()) * c / 6;
    cy += (a.y() + b.y()) * c / 6;
    sxx += (a.x() * a.x() + a.x() * b.x() + b.x() * b.x()) * c / 12;
    syy += (a.y() * a.y() + a.y() * b.y() + b.y() * b.y()) * c / 12;
    sxy += (a.x() * b.y() + 2 * a.x() * a.y() + 2 * b.x() * b.y() + b.x() * a.y()) * c / 24;
  }
  if (!(std::abs(area) > 0)) return 0;
  cx /= area, cy /= area;
  const double ixx = sxx / area - cx * cx, iyy = syy / area - cy * cy, ixy = sxy / area - cx * cy;
  const double mean = (ixx + iyy) / 2, half = std::hypot((ixx - iyy) / 2, ixy);
  const double lo = mean - half, hi = mean + half;
  return lo > 0 ? std::sqrt(hi / lo) : 0;
}

}  // namespace

double equivalent_size(double area, JointShape shape, std::int64_t sides, double aspect) {
  switch (shape) {
    case JointShape::square:
      return std::sqrt(area);
    case JointShape::rectangle:
      return std::sqrt(area * aspect);
    case JointShape::polygon: {
      const double n = static_cast<double>(sides);
      return 2 * std::sqrt(2 * area / (n * std::sin(2 * std::numbers::pi / n)));
    }
    case JointShape::ellipse:
      return std::sqrt(4 * area * aspect / std::numbers::pi);
  }
  return std::sqrt(area);
}

SetStatistics set_statistics(const JointSystem& js, std::size_t set) {
  SLICE_ASSERT(set < js.sets.size());
  SetStatistics s;
  s.set = set;
  const JointSetSpec& spec = js.sets[set];
  s.p32 = spec.achieved_p32;
  s.p10 = spec.achieved_p10;
  s.scanline_from = spec.scanline_from;
  s.scanline_to = spec.scanline_to;
  std::vector<const Joint*> mine;
  std::vector<Vec3> normals;
  for (const Joint& j : js.joints)
    if (j.set == static_cast<std::int32_t>(set)) {
      mine.push_back(&j);
      normals.push_back(j.plane.normal);
    }
  s.joints = mine.size();
  s.orientation = orientation_stats(normals);
  if (js.dimension != 3) return s;

  // The shape: the most common corner count (the smallest on a tie), and the median aspect of
  // the joints with that many corners: a quadrilateral's from its sides, any other polygon's
  // from its second moments of area.
  std::map<std::size_t, std::vector<double>> aspects;  // corner count -> the joints' aspects
  for (const Joint* j : mine) {
    if (j->persistent()) continue;
    ++s.finite;
    const auto& p = j->polygon_uv;
    auto& of = aspects[p.size()];
    if (p.size() == 4) {
      const double a = ((p[1] - p[0]).norm() + (p[3] - p[2]).norm()) / 2;
      const double b = ((p[2] - p[1]).norm() + (p[0] - p[3]).norm()) / 2;
      if (a > 0 && b > 0) of.push_back(std::max(a, b) / std::min(a, b));
    } else if (const double a = moment_aspect(p); a > 0) {
      of.push_back(a);
    }
  }
  if (s.finite == 0) return s;
  std::size_t modal = 0, most = 0;
  for (const auto& [k, of] : aspects)
    if (of.size() > most) modal = k, most = of.size();
  auto& of = aspects[modal];
  std::sort(of.begin(), of.end());
  const double median = of.empty() ? 1 : of[of.size() / 2];
  // Elongated above kRound: rectangles, or ellipses (any other corner count: the affine image
  // of a regular polygon, as the scene's ellipse is drawn); else squares and regular polygons.
  constexpr double kRound = 1.01;
  const bool long_shape = median > kRound;
  s.aspect = long_shape ? median : 1;
  if (modal == 4) {
    s.shape = long_shape ? JointShape::rectangle : JointShape::square;
  } else {
    s.shape = long_shape ? JointShape::ellipse : JointShape::polygon;
    s.sides = static_cast<std::int64_t>(modal);
  }
  const std::vector<Plane> domain = solid_region(js.domain, js.dimension);
  const double tol = js.options.tolerance * js.length_scale;
  std::vector<double> inside, all;
  for (const Joint* j : mine) {
    if (j->persistent()) continue;
    const double size = equivalent_size(polygon_area(*j), s.shape, s.sides, s.aspect);
    all.push_back(size);
    if (std::all_of(domain.begin(), domain.end(),
                    [&](const Plane& p) { return p.distance(j->centre) <= tol; }))
      inside.push_back(size);
  }
  s.sizes_centred_inside = !inside.empty();
  s.sizes = fit_sizes(inside.empty() ? all : inside);
  return s;
}

std::string sets_entry(const JointSystem& js, const SetStatistics& s) {
  const JointSetSpec& spec = js.sets[s.set];
  if (s.joints == 0 || js.dimension != 3 || spec.kind == JointKind::boundary) return {};
  std::ostringstream o;
  o << "[[sets]]\n";
  o << "name = " << quoted(spec.name) << '\n';
  if (spec.kind != JointKind::rock) o << "kind = " << quoted(to_string(spec.kind)) << '\n';
  o << "dip = " << angle(s.orientation.mean_dip_deg, false) << '\n';
  o << "dip_direction = " << angle(s.orientation.mean_dip_direction_deg, true) << '\n';
  if (std::isfinite(s.orientation.fisher_kappa))
    o << "fisher_kappa = " << num(s.orientation.fisher_kappa, 4) << '\n';
  if (s.finite > 0 && s.p32 > 0) {
    o << "p32 = " << num(s.p32) << '\n';
    const SizeSpec& z = s.sizes.fits[s.sizes.best].size;
    o << "size = { distribution = " << quoted(to_string(z.distribution));
    switch (z.distribution) {
      case SizeDistribution::fixed:
        o << ", value = " << num(z.value);
        break;
      case SizeDistribution::lognormal:
        o << ", mean = " << num(z.mean) << ", sd = " << num(z.sd);
        break;
      case SizeDistribution::exponential:
        o << ", mean = " << num(z.mean);
        break;
      case SizeDistribution::power_law:
        o << ", exponent = " << num(z.exponent) << ", min = " << num(z.min)
          << ", max = " << num(z.max);
        break;
      case SizeDistribution::persistent:
        break;
    }
    o << " }\n";
    o << "shape = " << quoted(to_string(s.shape)) << '\n';
    if (s.shape == JointShape::rectangle || s.shape == JointShape::ellipse)
      o << "aspect = " << num(s.aspect, 4) << '\n';
    if (s.shape == JointShape::polygon || s.shape == JointShape::ellipse)
      o << "sides = " << s.sides << '\n';
    // The sizes are those of ellipses of each joint's area (equivalent_size): drawn back with the
    // same areas.
    if (s.shape == JointShape::ellipse) o << "fit = \"equal-area\"\n";
  } else if (s.finite == 0 && s.p10 > 0) {  // persistent planes: their p10 on the scanline
    const auto xyz = [&o](const Vec3& v) {
      o << '[' << num(v.x(), 9) << ", " << num(v.y(), 9) << ", " << num(v.z(), 9) << ']';
    };
    o << "p10 = " << num(s.p10) << '\n';
    o << "scanline = { from = ";
    xyz(s.scanline_from);
    o << ", to = ";
    xyz(s.scanline_to);
    o << " }\n";
  } else {
    return {};  // no intensity to give: finite joints with no area in the domain, or no p10
  }
  o << "friction_angle = " << num(spec.friction_angle_deg) << '\n';
  if (spec.cohesion > 0) o << "cohesion = " << num(spec.cohesion) << '\n';
  if (spec.tension > 0) o << "tension = " << num(spec.tension) << '\n';
  return o.str();
}

}  // namespace slice

#include "slice/stochastic.hpp"

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>

#include "scene_common.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"

namespace slice {

namespace {

constexpr double kPi = std::numbers::pi;

std::string fmt(double x, int digits = 6) {
  std::ostringstream s;
  s.precision(digits);
  s << x;
  return s.str();
}

Vec2 rotate(const Vec2& p, double c, double s) {
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

// Shoelace area, positive for counter-clockwise.
double signed_area(const std::vector<Vec2>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& q = p[i];
    const Vec2& r = p[(i + 1) % p.size()];
    a += q.x() * r.y() - q.y() * r.x();
  }
  return 0.5 * a;
}

// Clips a convex polygon by the half-plane a . p <= b (one Sutherland-Hodgman pass). A vertex
// on the line is kept; an edge crossing it is cut at the crossing.
void clip(std::vector<Vec2>& poly, const Vec2& a, double b, std::vector<Vec2>& tmp) {
  tmp.clear();
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % n];
    const double sp = a.dot(p) - b, sq = a.dot(q) - b;
    if (sp <= 0) tmp.push_back(p);
    if ((sp < 0 && sq > 0) || (sp > 0 && sq < 0)) tmp.push_back(p + (sp / (sp - sq)) * (q - p));
  }
  poly.swap(tmp);
}

// Area of the part of a convex polygon (in the frame f about c) inside the region with every
// face moved by `shift` (inward for shift > 0).
double clipped_area(std::vector<Vec2> poly, const JointFrame& f, const Vec3& c,
                    const DomainBox& region, double shift) {
  std::vector<Vec2> tmp;
  tmp.reserve(poly.size() + region.planes.size());
  for (const Plane& pl : region.planes) {
    // normal . (c + u U + v V) <= d - shift, in (u, v).
    const Vec2 a(pl.normal.dot(f.u), pl.normal.dot(f.v));
    clip(poly, a, pl.d - shift - pl.normal.dot(c), tmp);
    if (poly.size() < 3) return 0;
  }
  return std::max(0.0, signed_area(poly));
}

// The area inside the region, counted only if the polygon reaches more than tol into it (so a
// joint on a face, or grazing it, counts nothing).
double area_in(const std::vector<Vec2>& poly, const JointFrame& f, const Vec3& c,
               const DomainBox& region) {
  if (!(clipped_area(poly, f, c, region, region.tol) > 0)) return 0;
  return clipped_area(poly, f, c, region, 0);
}

// Distance from x to the box [lo, hi] (0 inside).
double box_distance(const Vec3& x, const Vec3& lo, const Vec3& hi) {
  return (x.cwiseMax(lo).cwiseMin(hi) - x).norm();
}

// --- SplitMix64 (Steele, Lea & Flood 2014): a fixed, portable mixing function.
std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

struct RngDeleter {
  void operator()(gsl_rng* r) const { gsl_rng_free(r); }
};
using Rng = std::unique_ptr<gsl_rng, RngDeleter>;

// A gsl_rng_mt19937 stream seeded by `seed` (32 bits: set_stream_seed).
Rng make_rng(std::uint64_t seed) {
  Rng rng(gsl_rng_alloc(gsl_rng_mt19937));
  if (!rng) throw std::bad_alloc();
  gsl_rng_set(rng.get(), static_cast<unsigned long>(seed));
  return rng;
}

// Lognormal parameters of the log from the mean m and standard deviation s of the size itself:
// sigma^2 = ln(1 + s^2/m^2), zeta = ln m - sigma^2 / 2.
std::pair<double, double> lognormal_params(const SizeSpec& s) {
  const double sigma2 = std::log1p((s.sd / s.mean) * (s.sd / s.mean));
  return {std::log(s.mean) - 0.5 * sigma2, std::sqrt(sigma2)};
}

// The integral of x^p over [lo, hi].
double power_integral(double p, double lo, double hi) {
  if (std::abs(p + 1) < 1e-12) return std::log(hi / lo);
  return (std::pow(hi, p + 1) - std::pow(lo, p + 1)) / (p + 1);
}

double draw_size(const SizeSpec& s, gsl_rng* r) {
  switch (s.distribution) {
    case SizeDistribution::fixed:
      return s.value;
    case SizeDistribution::lognormal: {
      const auto [zeta, sigma] = lognormal_params(s);
      return gsl_ran_lognormal(r, zeta, sigma);
    }
    case SizeDistribution::exponential:
      return gsl_ran_exponential(r, s.mean);
    case SizeDistribution::power_law: {
      // Inverse CDF of the density proportional to x^-a on [min, max].
      const double u = gsl_rng_uniform(r), a = s.exponent;
      if (std::abs(a - 1) < 1e-12) return s.min * std::pow(s.max / s.min, u);
      const double lo = std::pow(s.min, 1 - a), hi = std::pow(s.max, 1 - a);
      return std::clamp(std::pow(lo + u * (hi - lo), 1 / (1 - a)), s.min, s.max);
    }
    case SizeDistribution::persistent:
      break;
  }
  SLICE_ASSERT(false);
  return 0;
}

// A pole drawn from the Fisher distribution about the mean frame's normal (exactly: the cosine
// w of the angle to the mean by the inverse of its CDF, F(w) = (e^{k w} - e^{-k}) / (2 sinh k),
// written as 1 - w = -log1p(-u (1 - e^{-2k})) / k to stay accurate for any k; the azimuth
// uniform). Returned as the upward normal of the plane.
Vec3 draw_fisher(const JointFrame& mean, double kappa, gsl_rng* r) {
  const double u = gsl_rng_uniform(r), phi = 2 * kPi * gsl_rng_uniform(r);
  const double t = std::clamp(-std::log1p(u * std::expm1(-2 * kappa)) / kappa, 0.0, 2.0);
  const double w = 1 - t, sin_theta = std::sqrt(t * (2 - t));
  Vec3 n = sin_theta * std::cos(phi) * mean.u + sin_theta * std::sin(phi) * mean.v + w * mean.n;
  n.normalize();
  return n.z() < 0 ? Vec3(-n) : n;  // the same plane, its upward normal
}

}  // namespace

// --- Shapes ------------------------------------------------------------------------------------

std::vector<Vec2> joint_polygon(const JointSetSpec& s, double size, double rotation_deg) {
  if (s.size.distribution == SizeDistribution::persistent) return {};
  std::vector<Vec2> p;
  const double h = 0.5 * size;
  const auto n = static_cast<std::size_t>(s.sides);
  switch (s.shape) {
    case JointShape::square:
      p = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
      break;
    case JointShape::rectangle: {
      const double k = h / s.aspect;
      p = {{-h, -k}, {h, -k}, {h, k}, {-h, k}};
      break;
    }
    case JointShape::polygon:
      for (std::size_t i = 0; i < n; ++i) {
        const double t = 2 * kPi * static_cast<double>(i) / static_cast<double>(n);
        p.emplace_back(h * std::cos(t), h * std::sin(t));
      }
      break;
    case JointShape::ellipse: {
      // The affine image (semi-axes a, b) of a regular n-gon about the unit circle: tangent
      // lines map to tangent lines, so a circumscribing n-gon (corners at 1 / cos(pi/n), half a
      // step off the axes) stays circumscribing; areas scale by a b, so the n-gon through the
      // circle scaled by sqrt(2 pi / (n sin(2 pi / n))) has the ellipse's area pi a b.
      const double a = h, b = h / s.aspect, dn = static_cast<double>(n);
      const bool circ = s.fit == EllipseFit::circumscribed;
      const double scale =
          circ ? 1 / std::cos(kPi / dn) : std::sqrt(2 * kPi / (dn * std::sin(2 * kPi / dn)));
      for (std::size_t i = 0; i < n; ++i) {
        const double t = 2 * kPi * (static_cast<double>(i) + (circ ? 0.5 : 0.0)) / dn;
        p.emplace_back(scale * a * std::cos(t), scale * b * std::sin(t));
      }
      break;
    }
  }
  if (rotation_deg != 0) {
    const double c = cosd(rotation_deg), sn = sind(rotation_deg);
    for (Vec2& q : p) q = rotate(q, c, sn);
  }
  return p;
}

double shape_area_factor(const JointSetSpec& s) { return signed_area(joint_polygon(s, 1.0, 0.0)); }

double shape_radius_factor(const JointSetSpec& s) {
  double r = 0;
  for (const Vec2& q : joint_polygon(s, 1.0, 0.0)) r = std::max(r, q.norm());
  return r;
}

double joint_size(const JointSetSpec& s, const Joint& j) {
  if (j.persistent()) return std::numeric_limits<double>::infinity();
  return std::sqrt(std::abs(signed_area(j.polygon_uv)) / shape_area_factor(s));
}

// --- Size distributions ----------------------------------------------------------------------

double size_bound(const SizeSpec& s) {
  switch (s.distribution) {
    case SizeDistribution::persistent:
      return 0;
    case SizeDistribution::fixed:
      return s.value;
    case SizeDistribution::lognormal: {
      const auto [zeta, sigma] = lognormal_params(s);
      return gsl_cdf_lognormal_Qinv(kSizeTail, zeta, sigma);
    }
    case SizeDistribution::exponential:
      return gsl_cdf_exponential_Qinv(kSizeTail, s.mean);
    case SizeDistribution::power_law:
      return s.max;
  }
  return 0;
}

double size_mean_square(const SizeSpec& s) {
  switch (s.distribution) {
    case SizeDistribution::persistent:
      return std::numeric_limits<double>::infinity();
    case SizeDistribution::fixed:
      return s.value * s.value;
    case SizeDistribution::lognormal:
      return s.mean * s.mean + s.sd * s.sd;
    case SizeDistribution::exponential:
      return 2 * s.mean * s.mean;
    case SizeDistribution::power_law:
      return power_integral(2 - s.exponent, s.min, s.max) /
             power_integral(-s.exponent, s.min, s.max);
  }
  return 0;
}

double set_enlargement(const JointSetSpec& s) {
  if (s.size.distribution == SizeDistribution::persistent) return 0;
  return size_bound(s.size) * shape_radius_factor(s);
}

// --- Measures --------------------------------------------------------------------------------

double area_inside(const Joint& j, const DomainBox& region) {
  const JointFrame f = plane_frame(j.dip_deg, j.dip_direction_deg);
  if (!j.persistent()) return area_in(j.polygon_uv, f, j.centre, region);
  // A persistent plane: a square about its centre that holds the whole section (every point of
  // the domain is within the farthest bounding-box corner's distance of the centre).
  double h = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner((k & 1) ? region.max.x() : region.min.x(),
                      (k & 2) ? region.max.y() : region.min.y(),
                      (k & 4) ? region.max.z() : region.min.z());
    h = std::max(h, (corner - j.centre).norm());
  }
  h = 1.01 * h + region.tol;
  return area_in({{-h, -h}, {h, -h}, {h, h}, {-h, h}}, f, j.centre, region);
}

bool crosses_segment(const Joint& j, const Vec3& a, const Vec3& b) {
  const double sa = j.plane.distance(a), sb = j.plane.distance(b);
  if (!((sa < 0 && sb > 0) || (sa > 0 && sb < 0))) return false;
  if (j.persistent()) return true;
  const Vec3 x = a + (sa / (sa - sb)) * (b - a);
  const Vec2 p = plane_frame(j.dip_deg, j.dip_direction_deg).to_uv(j.centre, x);
  const auto& q = j.polygon_uv;  // convex, counter-clockwise
  for (std::size_t i = 0; i < q.size(); ++i) {
    const Vec2 e = q[(i + 1) % q.size()] - q[i], r = p - q[i];
    if (e.x() * r.y() - e.y() * r.x() < 0) return false;
  }
  return true;
}

std::pair<Vec3, Vec3> chord(const DomainBox& region, const Vec3& point, const Vec3& dir) {
  double lo = -std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Plane& p : region.planes) {
    const double nd = p.normal.dot(dir), room = p.d - p.normal.dot(point);
    if (nd > 0) hi = std::min(hi, room / nd);
    if (nd < 0) lo = std::max(lo, room / nd);
  }
  SLICE_ASSERT(std::isfinite(lo) && std::isfinite(hi) && lo <= hi);
  return {point + lo * dir, point + hi * dir};
}

// --- Generation ------------------------------------------------------------------------------

std::uint64_t set_stream_seed(std::uint64_t scene_seed, std::size_t index) {
  const std::uint64_t z = splitmix64(splitmix64(scene_seed) ^ static_cast<std::uint64_t>(index));
  return (z ^ (z >> 32)) & 0xFFFFFFFFull;
}

namespace {

double grown_box_volume(const DomainBox& d, double r) {
  const Vec3 e = (d.max - d.min).array() + 2 * r;
  return e.x() * e.y() * e.z();
}

double scanline_length(const JointSetSpec& s) { return (s.scanline_to - s.scanline_from).norm(); }

}  // namespace

double expected_candidates(const JointSetSpec& s, const DomainBox& region) {
  const double r = set_enlargement(s);
  const double v = grown_box_volume(region, r);
  const bool persistent = s.size.distribution == SizeDistribution::persistent;
  const double mean_area = persistent ? 0 : shape_area_factor(s) * size_mean_square(s.size);
  switch (s.intensity) {
    case SetIntensity::spacing:
    case SetIntensity::deterministic:  // given joints: none drawn
      return 0;
    case SetIntensity::density:
      return s.density * v;
    case SetIntensity::count:
      return static_cast<double>(s.count) * v / region.volume;
    case SetIntensity::p32:
      // A joint at a uniform place in the box has on average area x V_domain / V inside the
      // domain (each of its points is uniform in the box), so the target takes p32 V / area.
      return persistent ? std::numeric_limits<double>::infinity() : s.p32 * v / mean_area;
    case SetIntensity::p10: {
      // Likewise a joint crosses a segment of length L with probability area |cos| L / V.
      const Vec3 line = (s.scanline_to - s.scanline_from).normalized();
      double c = std::abs(normal_from_dip(s.dip_deg, s.dip_direction_deg).dot(line));
      if (s.fisher_kappa > 0) c = std::max(c, 0.5 / (1 + s.fisher_kappa));  // scattered poles
      if (!(c > 1e-12)) return std::numeric_limits<double>::infinity();
      if (persistent) {  // a plane through a uniform point of the box: L |cos| / width
        const Vec3 n = normal_from_dip(s.dip_deg, s.dip_direction_deg);
        const double width = n.cwiseAbs().dot(region.max - region.min);
        return s.p10 * width / c;
      }
      return s.p10 * v / (mean_area * c);
    }
  }
  return 0;
}

double fisher_mean_abs_cos(double kappa) {
  if (!(kappa > 0)) return 1;
  return 1 - std::tanh(kappa / 2) / kappa;
}

std::vector<Joint> generate_stochastic_set(JointSetSpec& spec, std::size_t index,
                                           std::uint64_t scene_seed, const DomainBox& domain,
                                           std::int64_t max_joints, const std::string& where,
                                           const std::function<bool(const Joint&)>& keep) {
  SLICE_ASSERT(spec.intensity != SetIntensity::spacing);
  const std::string set = "[[sets]] \"" + spec.name + "\"";
  const std::string fix_max = "lower the set's intensity, or raise max_joints in [scene] (now " +
                              std::to_string(max_joints) + ")";
  spec.stream_seed = set_stream_seed(scene_seed, index);
  spec.enlargement = set_enlargement(spec);
  spec.candidates = 0;
  const Rng rng = make_rng(spec.stream_seed);
  gsl_rng* r = rng.get();

  const bool persistent = spec.size.distribution == SizeDistribution::persistent;
  const double grow = spec.enlargement;
  const Vec3 lo = domain.min.array() - grow;
  const Vec3 ext = (domain.max - domain.min).array() + 2 * grow;
  const JointFrame mean = plane_frame(spec.dip_deg, spec.dip_direction_deg);
  const double radius_factor = persistent ? 0 : shape_radius_factor(spec);
  const Vec3 line_a = spec.scanline_from, line_b = spec.scanline_to;

  // Number of candidates of a density set, drawn first.
  std::int64_t poisson_count = 0;
  if (spec.intensity == SetIntensity::density) {
    const double mu = spec.density * ext.x() * ext.y() * ext.z();
    if (mu > static_cast<double>(max_joints))
      throw Error(where,
                  set + " would draw about " + fmt(mu, 3) + " joints (density x the volume of " +
                      "the bounding box grown by " + fmt(grow, 3) +
                      "), more than max_joints = " + std::to_string(max_joints),
                  fix_max);
    poisson_count = static_cast<std::int64_t>(gsl_ran_poisson(r, mu));
    if (poisson_count > max_joints)
      throw Error(where,
                  set + " drew a Poisson count of " + std::to_string(poisson_count) +
                      " joints, more than max_joints = " + std::to_string(max_joints),
                  fix_max);
  }
  const double target_area = spec.p32 * domain.volume;
  const auto target_hits =
      static_cast<std::int64_t>(std::llround(spec.p10 * (line_b - line_a).norm()));

  std::vector<Joint> out;
  double area = 0, last_area = 0;
  std::int64_t hits = 0;
  auto done = [&] {
    switch (spec.intensity) {
      case SetIntensity::density:
        return spec.candidates >= poisson_count;
      case SetIntensity::count:
        return static_cast<std::int64_t>(out.size()) >= spec.count;
      case SetIntensity::p32:
        return area >= target_area;
      case SetIntensity::p10:
        return hits >= target_hits;
      case SetIntensity::spacing:
      case SetIntensity::deterministic:
        break;
    }
    return true;
  };
  while (!done()) {
    if (spec.intensity != SetIntensity::density && spec.candidates >= max_joints)
      throw Error(where,
                  set + " drew max_joints = " + std::to_string(max_joints) +
                      " joints without reaching its target " + to_string(spec.intensity),
                  fix_max);
    ++spec.candidates;
    // The fixed order of draws (stochastic.hpp): size, orientation, rotation, centre.
    const double size = persistent ? 0 : draw_size(spec.size, r);
    const Vec3 n = spec.fisher_kappa > 0 ? draw_fisher(mean, spec.fisher_kappa, r) : mean.n;
    const double rotation =
        persistent || spec.rotation_fixed ? spec.rotation_deg : 360 * gsl_rng_uniform(r);
    Vec3 c;
    for (int k = 0; k < 3; ++k) c(k) = lo(k) + ext(k) * gsl_rng_uniform(r);

    if (!persistent && box_distance(c, domain.min, domain.max) > radius_factor * size + domain.tol)
      continue;  // cannot reach the domain
    Joint j;
    if (spec.fisher_kappa > 0) {
      const DipAndDirection dd = dip_from_normal(n);
      j.dip_deg = dd.dip_deg;
      j.dip_direction_deg = dd.dip_direction_deg;
    } else {
      j.dip_deg = spec.dip_deg;
      j.dip_direction_deg = spec.dip_direction_deg;
    }
    // The normal from the stored angles, as readers of joints.h5 rebuild the polygon's frame.
    const Vec3 normal = normal_from_dip(j.dip_deg, j.dip_direction_deg);
    j.plane = {normal, normal.dot(c)};
    j.centre = c;
    scene_read::set_joint_properties(j, spec, static_cast<std::int32_t>(index));
    j.polygon_uv = joint_polygon(spec, size, rotation);
    const double a = area_inside(j, domain);
    if (!(a > 0) || (keep && !keep(j))) continue;
    area += a;
    last_area = a;
    if (spec.intensity == SetIntensity::p10 && crosses_segment(j, line_a, line_b)) ++hits;
    out.push_back(std::move(j));
  }
  // P32: keep the last joint only if it brings the area closer to the target.
  if (spec.intensity == SetIntensity::p32 && !out.empty() &&
      area - target_area > target_area - (area - last_area))
    out.pop_back();
  return out;
}

std::vector<Vec3> fisher_normals(const JointSetSpec& spec, std::uint64_t stream_seed,
                                 std::size_t count) {
  SLICE_ASSERT(spec.fisher_kappa > 0);
  const Rng rng = make_rng(stream_seed);
  const JointFrame mean = plane_frame(spec.dip_deg, spec.dip_direction_deg);
  std::vector<Vec3> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
    out.push_back(draw_fisher(mean, spec.fisher_kappa, rng.get()));
  return out;
}

void measure_set(JointSetSpec& spec, const std::vector<const Joint*>& joints,
                 const DomainBox& domain) {
  double area = 0;
  std::int64_t hits = 0;
  for (const Joint* j : joints) {
    area += area_inside(*j, domain);
    hits += crosses_segment(*j, spec.scanline_from, spec.scanline_to) ? 1 : 0;
  }
  spec.joint_count = static_cast<std::int64_t>(joints.size());
  spec.achieved_p32 = area / domain.volume;
  const double length = scanline_length(spec);
  spec.achieved_p10 = length > 0 ? static_cast<double>(hits) / length : 0;
}

}  // namespace slice

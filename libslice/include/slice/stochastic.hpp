#pragma once
// Stochastic joint sets (docs/design.md, "Stochastic joints"): joint shapes and sizes, Fisher
// orientations, Poisson centres, and the intensity measures P32 (joint area per unit volume) and
// P10 (joints per unit length of a scanline). Randomness is GSL's gsl_rng_mt19937, one stream per
// set, drawn in a fixed order; GSL stays inside stochastic.cpp.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/scene.hpp"

namespace slice {

// --- Shapes ----------------------------------------------------------------------------------

/// The polygon of a joint of set `s` and the given size, turned counter-clockwise by
/// `rotation_deg` in its (u, v) frame (orientation.hpp), about its centre; counter-clockwise.
/// At rotation 0:
///   square     corners (+-size/2, +-size/2)
///   rectangle  long side `size` along u, short side size / aspect along v
///   polygon    `sides` corners on the circle of diameter `size`, the first on +u
///   ellipse    semi-axes size/2 along u and size/(2 aspect) along v, as a `sides`-gon that
///              circumscribes it (every edge tangent: the paper's safe side) or, with
///              fit = equal-area, has its area (pi/4 size^2 / aspect)
/// Persistent sets (size distribution none) have no polygon: the result is empty.
std::vector<Vec2> joint_polygon(const JointSetSpec& s, double size, double rotation_deg);
/// Area of joint_polygon(s, size, any rotation) divided by size^2.
double shape_area_factor(const JointSetSpec& s);
/// Largest distance of a corner of joint_polygon(s, size, any rotation) from the centre,
/// divided by size: the joint's bounding radius per unit size.
double shape_radius_factor(const JointSetSpec& s);
/// The size of joint j of set s, from its polygon's area (the inverse of joint_polygon);
/// +infinity for a persistent joint.
double joint_size(const JointSetSpec& s, const Joint& j);

// --- Size distributions ----------------------------------------------------------------------

/// Probability with which a size exceeds size_bound() for the unbounded distributions.
inline constexpr double kSizeTail = 1e-9;
/// The largest size: value (fixed), max (power-law) or, for the unbounded lognormal and
/// exponential, the size exceeded with probability kSizeTail. 0 for persistent sets.
double size_bound(const SizeSpec& s);
/// E[size^2] of the distribution (for estimates of how many joints a target needs).
double size_mean_square(const SizeSpec& s);
/// The radius by which the domain's bounding box is grown for the centres of set s: the
/// bounding radius of a joint of size size_bound (0 for persistent sets).
double set_enlargement(const JointSetSpec& s);

// --- Measures --------------------------------------------------------------------------------

/// A bounded convex region (a domain) as the generator and the measures see it.
struct DomainBox {
  std::vector<Plane> planes;                    // normal . x <= d, outward unit normals
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();  // bounding box
  Vec3 interior_point = Vec3::Zero();           // a point inside (the vertex mean)
  double volume = 0;
  double tol = 0;  // absolute length tolerance: faces count as moved inward by this
};

/// Area of the part of joint j inside the region (for a persistent joint: the area of the
/// plane's section); 0 if the joint reaches no more than tol into it (e.g. lies on a face).
double area_inside(const Joint& j, const DomainBox& region);
/// Whether joint j crosses the segment a-b: its plane separates a and b strictly and the
/// crossing point lies in the polygon (anywhere, for a persistent joint).
bool crosses_segment(const Joint& j, const Vec3& a, const Vec3& b);
/// The chord of the region along the line through `point` (inside) in direction `dir`.
std::pair<Vec3, Vec3> chord(const DomainBox& region, const Vec3& point, const Vec3& dir);

// --- Generation ------------------------------------------------------------------------------

/// The seed of set `index`'s gsl_rng_mt19937 stream: SplitMix64 mixing of the scene seed, then
/// of the index, folded to the 32 bits mt19937 takes. It depends on nothing else, so adding a
/// set after the others changes none of their joints.
std::uint64_t set_stream_seed(std::uint64_t scene_seed, std::size_t index);

/// About how many joints stochastic set s draws in the region (candidates, including those that
/// miss it): density x V, count x V / V_domain, p32 x V / E[area], p10 x V / (E[area] |cos|),
/// with V the volume of the bounding box grown by set_enlargement(s) and |cos| between the mean
/// pole and the scanline. +infinity if the target cannot be reached (a scanline in the plane of
/// every joint).
double expected_candidates(const JointSetSpec& s, const DomainBox& region);

/// Draws the joints of stochastic set `spec` (intensity density, count, p32 or p10), the set
/// number `index` of the scene, from its own stream. Per joint, in this order: the size, the
/// orientation (two uniforms: the Fisher angle to the mean pole by the inverse of its CDF, and
/// the azimuth about it; none when fisher_kappa is 0), the in-plane rotation (one uniform, unless
/// fixed or persistent), the centre (three uniforms, in the bounding box grown by
/// set_enlargement). Joints that do not reach into the domain (by more than tol) are dropped.
/// A density set first draws its number of candidates, Poisson(density x box volume); the others
/// draw until their target is met: `count` joints kept; the area inside the domain reaching
/// p32 x volume (the last joint kept only if that brings the area closer to the target);
/// round(p10 x length) joints crossing the scanline. spec's scanline must be set. Fills spec's
/// stream_seed, enlargement and candidates. Throws Error(where, ...) when more than max_joints
/// candidates would be drawn. `keep`, if given, drops the joints it refuses as if they missed
/// the domain (they count towards no target); the draws stay the same.
std::vector<Joint> generate_stochastic_set(JointSetSpec& spec, std::size_t index,
                                           std::uint64_t scene_seed, const DomainBox& domain,
                                           std::int64_t max_joints, const std::string& where,
                                           const std::function<bool(const Joint&)>& keep = {});

/// E|cos theta|, theta the angle between a pole drawn from the Fisher distribution of
/// concentration kappa (as a stochastic set draws it, on the whole sphere) and the mean pole:
/// 1 - tanh(kappa / 2) / kappa; 1 for kappa = 0 (every pole at the mean), 1/2 as kappa -> 0+.
/// A line along the mean pole crosses P32 x E|cos theta| joints per unit length.
double fisher_mean_abs_cos(double kappa);

/// The joints of stochastic set `spec` (density, p32, count or p10, with a size) of a 2-D scene
/// with a section (docs/2d.md, "Stochastic sets in a section"): its 3-D joints, of the 3-D
/// orientation `trace` gives (dip_deg, dip_direction_deg), drawn as generate_stochastic_set draws
/// them in the slab of the 3-D region whose section is the domain: the points within the bounding
/// radius of the set's largest joint (set_enlargement) of the section plane, where every joint
/// that can reach the plane has its centre (the generator's own growth of the box adds the
/// joints that only reach into the slab). So the intensity is the set's own (density per unit
/// volume, p32 area per unit volume of the slab). `count` joints are drawn until that many have
/// a trace in the domain; `p10` (joints per unit length along the mean pole, in 3-D) is drawn
/// as p32 = p10 / fisher_mean_abs_cos(kappa), which is stored in spec.p32. Each joint's trace in
/// the section plane that reaches into the domain by more than its tolerance becomes a 2-D
/// joint: the segment, of the trace's apparent dip. `domain` is the 2-D scene's (its slab of unit
/// thickness in y). Fills spec's stream_seed, enlargement and candidates (the 3-D joints drawn).
/// Throws Error(where,
/// ...) as generate_stochastic_set does.
std::vector<Joint> generate_section_set(JointSetSpec& spec, std::size_t index,
                                        std::uint64_t scene_seed, const SectionPlane& section,
                                        const SectionTrace& trace, const DomainBox& domain,
                                        std::int64_t max_joints, const std::string& where);

/// The upward unit normals of `count` planes drawn from the Fisher distribution about the mean
/// pole of set `spec` (its dip, dip direction and fisher_kappa > 0), as a stochastic set draws
/// them (two uniforms per plane), from the stream gsl_rng_mt19937 seeded by `stream_seed`. For
/// the planes of a regular set with scatter (spacing and fisher_kappa), in increasing offset.
std::vector<Vec3> fisher_normals(const JointSetSpec& spec, std::uint64_t stream_seed,
                                 std::size_t count);

/// Sets spec's joint_count, achieved_p32 and achieved_p10 (along its scanline) from the joints
/// of the set.
void measure_set(JointSetSpec& spec, const std::vector<const Joint*>& joints,
                 const DomainBox& domain);

}  // namespace slice

// Sections of a 3-D scene (docs/2d.md, "Sections of a 3-D scene"): the [section] table of a 2-D
// scene, and the trace of a 3-D plane orientation in it (apparent dip, spacing, offset).
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "scene_read.hpp"
#include "slice/orientation.hpp"
#include "slice/scene.hpp"
#include "slice/stochastic.hpp"
#include "slice/traces.hpp"

namespace slice {

// n . X = c with X = point_h + x along + z e_z: (n . along) x + n_z z = c - n . point_h. The
// line's normal in the section is m = (n . along, n_z), |m| = sin of the angle between n and the
// section's normal (n is a unit vector and n . normal is its third component). Dividing by |m|
// makes it the unit normal of a 2-D line: apparent dip atan2(|m_x|, m_z), towards +x if m_x > 0.
SectionTrace section_trace(const SectionPlane& section, double dip_deg, double dip_direction_deg) {
  const Vec3 n = normal_from_dip(dip_deg, dip_direction_deg);
  const Vec3 point_h(section.point.x(), section.point.y(), 0);
  SectionTrace t;
  t.dip_deg = dip_deg;
  t.dip_direction_deg = dip_direction_deg;
  const double mx = n.dot(section.along), mz = n.z();
  t.sin_angle = std::hypot(mx, mz);
  t.shift = n.dot(point_h);
  t.apparent_dip_deg = std::atan2(std::abs(mx), mz) * 180 / std::numbers::pi;
  t.apparent_dip_direction_deg = mx < 0 ? 270 : 90;
  return t;
}

namespace {

// The part of the segment a-b (y = 0) inside the 2-D domain (its planes with y-free normals; the
// slab's +-y planes hold at y = 0) reaching more than tol into it: its length, 0 if none.
double length_inside(const Vec3& a, const Vec3& b, const DomainBox& domain) {
  double t0 = 0, t1 = 1;
  for (const Plane& p : domain.planes) {
    const double da = p.normal.dot(a) - (p.d - domain.tol),
                 db = p.normal.dot(b) - (p.d - domain.tol);
    if (da > 0 && db > 0) return 0;
    if (da > 0) t0 = std::max(t0, da / (da - db));
    if (db > 0) t1 = std::min(t1, da / (da - db));
  }
  return t1 > t0 ? (t1 - t0) * (b - a).norm() : 0;
}

// The window of a section's traces: the domain's bounding rectangle in the plane y = 0.
TraceMapping section_window(const DomainBox& domain) {
  TraceMapping w;
  w.centre = Vec3((domain.min.x() + domain.max.x()) / 2, 0, (domain.min.z() + domain.max.z()) / 2);
  w.dip_deg = 90;
  w.dip_direction_deg = 0;  // normal +y: u = +x, v = +z
  w.width = domain.max.x() - domain.min.x() + 2 * domain.tol;
  w.height = domain.max.z() - domain.min.z() + 2 * domain.tol;
  return w;
}

// The 2-D joint of 3-D joint j3's trace on the section plane (y = 0), if it reaches into the
// domain by more than its tolerance; its properties are left to the caller.
std::optional<Joint> section_joint(const Joint& j3, const TraceMapping& w,
                                   const DomainBox& domain) {
  const std::optional<Trace> t = trace_on(j3, w, domain.tol);
  if (!t) return std::nullopt;
  const JointFrame wf = plane_frame(w.dip_deg, w.dip_direction_deg);
  Vec3 a = wf.to_global(w.centre, t->a), b = wf.to_global(w.centre, t->b);
  a.y() = b.y() = 0;
  if (!(length_inside(a, b, domain) > domain.tol)) return std::nullopt;
  Joint j;
  const DipAndDirection dd =
      dip_from_normal(Vec3(j3.plane.normal.x(), 0, j3.plane.normal.z()).normalized());
  j.dip_deg = dd.dip_deg;
  j.dip_direction_deg = dd.dip_direction_deg;
  j.centre = (a + b) / 2;
  // The normal from the stored angles, as readers of joints.h5 rebuild it.
  const Vec3 m = scene_read::dip_normal(j.dip_deg, j.dip_direction_deg, 2);
  j.plane = {m, m.dot(j.centre)};
  j.polygon_uv =
      scene_read::segment_polygon(plane_frame(j.dip_deg, j.dip_direction_deg), j.centre, a, b);
  const std::vector<Vec2>& r = j.polygon_uv;  // counter-clockwise, as [[joints]] make it
  if ((r[1] - r[0]).x() * (r[2] - r[1]).y() - (r[1] - r[0]).y() * (r[2] - r[1]).x() < 0)
    std::reverse(j.polygon_uv.begin(), j.polygon_uv.end());
  return j;
}

}  // namespace

std::vector<Joint> generate_section_set(JointSetSpec& spec, std::size_t index,
                                        std::uint64_t scene_seed, const SectionPlane& section,
                                        const SectionTrace& trace, const DomainBox& domain,
                                        std::int64_t max_joints, const std::string& where) {
  // The section's own frame (x along, y its normal, z up) is the global one turned about the
  // vertical, so that a section point (x, z) is the point (x, 0, z) and orientations, Fisher
  // scatter and in-plane rotations (measured from the horizontal strike) carry over unchanged.
  const Vec3 n = normal_from_dip(trace.dip_deg, trace.dip_direction_deg);
  const DipAndDirection local =
      dip_from_normal(Vec3(n.dot(section.along), n.dot(section.normal), n.z()));
  JointSetSpec s3 = spec;
  s3.dip_deg = local.dip_deg;
  s3.dip_direction_deg = local.dip_direction_deg;
  if (spec.intensity == SetIntensity::p10) {
    // p10 along the mean pole in 3-D: a line there crosses P32 E|cos| joints per unit length.
    s3.intensity = SetIntensity::p32;
    s3.p32 = spec.p32 = spec.p10 / fisher_mean_abs_cos(spec.fisher_kappa);
  }
  const double reach = set_enlargement(s3);
  SLICE_ASSERT(reach > 0);  // finite joints: the scene refuses a set without a size
  DomainBox slab = domain;
  for (Plane& p : slab.planes)
    if (std::abs(p.normal.y()) == 1) p.d = reach;
  slab.min.y() = -reach;
  slab.max.y() = reach;
  slab.volume = domain.volume * 2 * reach;  // domain.volume: the section's area x 1
  const TraceMapping w = section_window(domain);
  // count: that many joints with a trace in the domain (the others are dropped as drawn).
  std::function<bool(const Joint&)> traced;
  if (spec.intensity == SetIntensity::count)
    traced = [&](const Joint& j3) { return section_joint(j3, w, domain).has_value(); };
  const std::vector<Joint> drawn =
      generate_stochastic_set(s3, index, scene_seed, slab, max_joints, where, traced);
  spec.stream_seed = s3.stream_seed;
  spec.enlargement = s3.enlargement;
  spec.candidates = s3.candidates;

  // Each joint's trace on the plane y = 0, over the domain's bounding rectangle.
  std::vector<Joint> out;
  for (const Joint& j3 : drawn) {
    std::optional<Joint> j = section_joint(j3, w, domain);
    if (!j) continue;
    scene_read::set_joint_properties(*j, spec, static_cast<std::int32_t>(index));
    out.push_back(std::move(*j));
  }
  return out;
}

}  // namespace slice

namespace slice::scene_read {

std::vector<Vec2> segment_polygon(const JointFrame& frame, const Vec3& centre, const Vec3& a,
                                  const Vec3& b) {
  // Around the rectangle: a-, a+, b+, b-.
  return {
      frame.to_uv(centre, a - 0.5 * Vec3::UnitY()), frame.to_uv(centre, a + 0.5 * Vec3::UnitY()),
      frame.to_uv(centre, b + 0.5 * Vec3::UnitY()), frame.to_uv(centre, b - 0.5 * Vec3::UnitY())};
}

SectionPlane read_section_plane(const Context& cx, const toml::table& st) {
  const Reader& r = cx.r;
  const Tbl t{r, st, "[section]"};
  t.check_keys(kSectionKeys);
  if (cx.dimension != 2)
    r.fail(st, "[section] is for a 2-D scene: the section of 3-D joint sets it is cut in",
           "add dimension = 2 to [scene], or remove [section] from a 3-D scene");
  SectionPlane s;
  s.point = to_vector<3>(
      r, t.require("point", "add point = [x, y, z], a point of the section plane (3-D)"),
      t.label("point"));
  const toml::node* strike = t.find("strike");
  const toml::node* normal = t.find("normal");
  const std::string both =
      "give strike = <azimuth of the section's x axis, degrees clockwise from North> or normal "
      "= [nx, ny, 0], the horizontal normal of the vertical section plane";
  if (strike && normal) r.fail(*normal, "[section] gives both 'strike' and 'normal'", "keep one");
  if (!strike && !normal) r.fail(st, "[section] has neither 'strike' nor 'normal'", both);
  if (strike) {
    s.strike_deg = to_number(r, *strike, t.label("strike"));
    check_range(t, "strike", s.strike_deg, 0, 360, true,
                "give the strike clockwise from North in [0, 360) (e.g. 360 -> 0, -30 -> 330)");
    s.along = Vec3(sind(s.strike_deg), cosd(s.strike_deg), 0);
  } else {
    const Vec3 n = to_vector<3>(r, *normal, t.label("normal"));
    const double len = n.norm();
    if (!(len > 0) || !std::isfinite(len))
      r.fail(*normal, t.label("normal") + " is " + fmt(n) + ", which has no direction", both);
    if (std::abs(n.z()) > cx.rel_tol * len)
      r.fail(*normal,
             t.label("normal") + " is " + fmt(n) +
                 ", not horizontal: a section is vertical (gravity acts in it, docs/2d.md)",
             "give a horizontal normal [nx, ny, 0], or the section's strike");
    const Vec3 h = Vec3(n.x(), n.y(), 0) / std::hypot(n.x(), n.y());
    s.along = Vec3(h.y(), -h.x(), 0);  // normal = e_z x along
    double a = std::atan2(s.along.x(), s.along.y()) * 180 / std::numbers::pi;
    if (a < 0) a += 360;
    s.strike_deg = a >= 360 ? 0 : a;
  }
  s.normal = Vec3::UnitZ().cross(s.along);
  return s;
}

// A dip and dip direction of a scene with a section are 3-D: the plane's trace in the section.
// A plane parallel to it (sin of the angle between the normals within the scene's tolerance)
// has no trace: refused with the reason.
SectionTrace trace_in_section(const Context& cx, const Tbl& t, double dip, double dip_direction) {
  const SectionTrace tr = section_trace(*cx.section, dip, dip_direction);
  if (!(tr.sin_angle > cx.rel_tol))
    t.r.fail(*t.find("dip"),
             t.ctx + " (dip " + fmt(dip) + ", dip direction " + fmt(dip_direction) +
                 ") is parallel to the section (strike " + fmt(cx.section->strike_deg) +
                 ", vertical): its planes have no trace in it",
             "leave it out of the section, or choose a section plane across it");
  return tr;
}

}  // namespace slice::scene_read

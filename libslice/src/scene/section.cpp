// Sections of a 3-D scene (docs/2d.md, "Sections of a 3-D scene"): the [section] table of a 2-D
// scene, and the trace of a 3-D plane orientation in it (apparent dip, spacing, offset).
#include <cmath>
#include <numbers>
#include <string>

#include "scene_read.hpp"
#include "slice/orientation.hpp"
#include "slice/scene.hpp"

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

}  // namespace slice

namespace slice::scene_read {

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

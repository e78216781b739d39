// /contacts and /stability of blocks.h5 (slice-stability; docs/formats.md): written after
// /geometry, read and checked against the blocks.
#include <cmath>
#include <string>
#include <vector>

#include "file_common.hpp"

namespace slice::h5file {

namespace {

std::vector<double> flat(const std::vector<Vec3>& v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const Vec3& x : v) out.insert(out.end(), {x.x(), x.y(), x.z()});
  return out;
}

std::vector<Vec3> vecs(const std::vector<double>& v) {
  std::vector<Vec3> out(v.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  return out;
}

template <class T>
std::vector<T> flat(const std::vector<std::array<T, 2>>& v) {
  std::vector<T> out;
  out.reserve(2 * v.size());
  for (const auto& x : v) out.insert(out.end(), {x[0], x[1]});
  return out;
}

template <class T>
std::vector<std::array<T, 2>> pairs(const std::vector<T>& v) {
  std::vector<std::array<T, 2>> out(v.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {v[2 * i], v[2 * i + 1]};
  return out;
}

template <class T>
void expect(const Checker& c, const std::string& name, const std::vector<T>& v, std::size_t n,
            const std::string& because) {
  if (v.size() != n)
    c.fail(name + " has " + str(v.size()) + " rows; expected " + str(n) + " (" + because + ")");
}

void check_contacts(const Checker& c, const BlockSystem& bs, const ContactRows& r) {
  const std::size_t n = r.size(), B = bs.blocks.size(), F = face_count(bs.blocks);
  const auto J = std::int64_t(bs.joints.joints.size());
  const std::string because = "the rows of /contacts/pairs";
  expect(c, "/contacts/faces", r.faces, n, because);
  expect(c, "/contacts/area", r.area, n, because);
  expect(c, "/contacts/centroid", r.centroid, n, because);
  expect(c, "/contacts/normal", r.normal, n, because);
  expect(c, "/contacts/joint", r.joint, n, because);
  expect(c, "/contacts/fraction", r.fraction, n, because);
  expect(c, "/contacts/free", r.free, n, because);
  for (std::size_t i = 0; i < n; ++i) {
    const auto [a, b] = r.pairs[i];
    if (a < 0 || std::size_t(a) >= B || (bs.blocks[std::size_t(a)].flags & kRemoved))
      c.fail(at("/contacts/pairs", i) + " names block " + str(a) +
             ", which is not a kept block of /blocks");
    if (b < -1 || b == a || (b >= 0 && std::size_t(b) >= B))
      c.fail(at("/contacts/pairs", i) + " names block " + str(b) + " beside " + str(a) +
             "; expected another block or -1 (the domain)");
    const auto [fa, fb] = r.faces[i];
    if (fa < 0 || std::size_t(fa) >= F || (b < 0) != (fb < 0) || fb < -1 || std::size_t(fb + 1) > F)
      c.fail(at("/contacts/faces", i) + " is (" + str(fa) + ", " + str(fb) +
             "); expected rows of /blocks/face_normal (-1 beside the domain)");
    c.non_negative(r.area[i], At{"/contacts/area", i});
    c.finite(r.centroid[i], At{"/contacts/centroid", i});
    c.unit(r.normal[i], At{"/contacts/normal", i});
    if (r.joint[i] < -1 || r.joint[i] >= J)
      c.fail(at("/contacts/joint", i) + " is " + str(r.joint[i]) +
             "; expected -1 (the domain) or a row of /joints");
    if (!(r.fraction[i] >= 0 && r.fraction[i] <= 1))
      c.fail(at("/contacts/fraction", i) + " is " + num(r.fraction[i]) + "; expected 0 to 1");
    if (r.free[i] > 1)
      c.fail(at("/contacts/free", i) + " is " + str(std::int64_t(r.free[i])) + "; expected 0 or 1");
  }
}

void check_result(const Checker& c, const BlockSystem& bs, const StabilityResult& s) {
  const std::size_t B = bs.blocks.size();
  const auto J = std::int64_t(bs.joints.joints.size());
  const std::string because = "the rows of /blocks/origin";
  expect(c, "/stability/removable", s.removable, B, because);
  expect(c, "/stability/mode", s.mode, B, because);
  expect(c, "/stability/fos", s.fos, B, because);
  expect(c, "/stability/direction", s.direction, B, because);
  expect(c, "/stability/generation", s.generation, B, because);
  expect(c, "/stability/planes", s.planes, B, because);
  expect(c, "/stability/group", s.group, B, because);
  for (std::size_t b = 0; b < B; ++b) {
    if (s.removable[b] > 1)
      c.fail(at("/stability/removable", b) + " is " + str(std::int64_t(s.removable[b])) +
             "; expected 0 or 1");
    if (s.mode[b] > std::uint8_t(FailureMode::slides_two))
      c.fail(at("/stability/mode", b) + " is " + str(std::int64_t(s.mode[b])) +
             "; expected 0 to 5 (docs/stability.md)");
    if (std::isnan(s.fos[b]) || s.fos[b] < 0)
      c.fail(at("/stability/fos", b) + " is " + num(s.fos[b]) + "; expected 0 or more (inf)");
    c.finite(s.direction[b], At{"/stability/direction", b});
    const double len = s.direction[b].norm();
    if (len != 0 && std::abs(len - 1) > kUnitTolerance)
      c.fail(at("/stability/direction", b) + " has length " + num(len) + "; expected 1 or 0");
    if (s.generation[b] < -1)
      c.fail(at("/stability/generation", b) + " is " + str(std::int64_t(s.generation[b])) +
             "; expected -1 (never fails) or a round");
    if (s.group[b] < -1 || s.group[b] >= std::int64_t(B) ||
        (s.group[b] >= 0 && s.generation[b] < 0))
      c.fail(at("/stability/group", b) + " is " + str(s.group[b]) +
             "; expected -1 or, for a block that fails, a row of /blocks");
    for (const std::int64_t j : s.planes[b])
      if (j < -1 || j >= J)
        c.fail(at("/stability/planes", b) + " names joint " + str(j) +
               "; expected -1 or a row of /joints");
  }
}

}  // namespace

void check_stability(const Checker& c, const BlockSystem& bs) {
  if (!bs.stability) return;
  if (!bs.geometry) c.fail("/stability is there, but /geometry is not");
  check_contacts(c, bs, bs.stability->contacts);
  check_result(c, bs, bs.stability->result);
}

void write_stability_groups(const Group& root, const BlockSystem& bs) {
  const StabilityData& d = *bs.stability;
  const ContactRows& r = d.contacts;
  const Group c = root.create_group("contacts");
  c.write<std::int64_t>("pairs", flat(r.pairs), 2);
  c.write<std::int64_t>("faces", flat(r.faces), 2);
  c.write<double>("area", r.area);
  c.write<double>("centroid", flat(r.centroid), 3);
  c.write<double>("normal", flat(r.normal), 3);
  c.write<std::int64_t>("joint", r.joint);
  c.write<double>("fraction", r.fraction);
  c.write<std::uint8_t>("free", r.free);
  const StabilityResult& s = d.result;
  const Group g = root.create_group("stability");
  const StabilityOptions& o = s.options;
  g.write_attribute<double>("density", o.density);
  g.write_attribute<double>("gravity", o.gravity);
  g.write_attribute<double>("seismic", o.seismic);
  g.write_attribute<double>("seismic_azimuth", o.seismic_azimuth_deg);
  if (o.water_table) g.write_attribute<double>("water_table", *o.water_table);
  g.write_attribute<double>("water_density", o.water_density);
  g.write_attribute<double>("support_pressure", o.support_pressure);
  g.write_attribute<std::string>("free_faces", fixed_faces_string(o.free_faces));
  g.write_attribute<double>("fos_target", o.fos_target);
  g.write_attribute<std::int64_t>("max_group", std::int64_t(o.max_group));
  g.write<std::uint8_t>("removable", s.removable);
  g.write<std::uint8_t>("mode", s.mode);
  g.write<double>("fos", s.fos);
  g.write<double>("direction", flat(s.direction), 3);
  g.write<std::int32_t>("generation", s.generation);
  g.write<std::int64_t>("planes", flat(s.planes), 2);
  g.write<std::int64_t>("group", s.group);
}

void read_stability_groups(const Group& root, BlockSystem& bs) {
  if (!root.exists("stability") && !root.exists("contacts")) return;
  const Group c = root.open_group("contacts");
  const Group g = root.open_group("stability");
  StabilityData d;
  ContactRows& r = d.contacts;
  r.pairs = pairs(c.read<std::int64_t>("pairs", 2));
  r.faces = pairs(c.read<std::int64_t>("faces", 2));
  r.area = c.read<double>("area");
  r.centroid = vecs(c.read<double>("centroid", 3));
  r.normal = vecs(c.read<double>("normal", 3));
  r.joint = c.read<std::int64_t>("joint");
  r.fraction = c.read<double>("fraction");
  r.free = c.read<std::uint8_t>("free");
  StabilityResult& s = d.result;
  StabilityOptions& o = s.options;
  o.density = g.read_attribute<double>("density");
  o.gravity = g.read_attribute<double>("gravity");
  o.seismic = g.read_attribute<double>("seismic");
  o.seismic_azimuth_deg = g.read_attribute<double>("seismic_azimuth");
  if (g.has_attribute("water_table")) o.water_table = g.read_attribute<double>("water_table");
  o.water_density = g.read_attribute<double>("water_density");
  o.support_pressure = g.read_attribute<double>("support_pressure");
  const auto faces = g.read_attribute<std::string>("free_faces");
  const auto bits = parse_fixed_faces(faces);
  if (!bits)
    fail(g, "/stability attribute free_faces is \"" + faces + "\"; expected e.g. \"+z,-x\"");
  o.free_faces = *bits;
  o.fos_target = g.read_attribute<double>("fos_target");
  // Files written before groups (rockslice 2026-11-28 and older) analysed one body at a time.
  o.max_group = 1;
  if (g.has_attribute("max_group")) {
    const auto m = g.read_attribute<std::int64_t>("max_group");
    if (m < 1 || m > std::int64_t(kMaxGroup))
      fail(g, "/stability attribute max_group is " + std::to_string(m) + "; expected 1 to " +
                  std::to_string(kMaxGroup));
    o.max_group = std::size_t(m);
  }
  s.removable = g.read<std::uint8_t>("removable");
  s.mode = g.read<std::uint8_t>("mode");
  s.fos = g.read<double>("fos");
  s.direction = vecs(g.read<double>("direction", 3));
  s.generation = g.read<std::int32_t>("generation");
  s.planes = pairs(g.read<std::int64_t>("planes", 2));
  s.group = g.exists("group") ? g.read<std::int64_t>("group")
                              : std::vector<std::int64_t>(s.generation.size(), -1);
  bs.stability = std::move(d);
}

}  // namespace slice::h5file

#include "slice/export_3dec.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "slice/contacts.hpp"
#include "slice/error.hpp"
#include "slice/export_udec.hpp"
#include "slice/output.hpp"
#include "slice/version.hpp"

namespace slice {
namespace {

// Shortest text that reads back as the same double.
void put_num(std::string& out, double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  out.append(buf.data(), r.ptr);
}

/// A text file written through "<path>.partial", a buffer at a time.
class TextOut {
 public:
  explicit TextOut(const std::filesystem::path& path) : part_(path), name_(path.string()) {
    f_ = std::fopen(part_.path().c_str(), "wb");
    if (!f_) {
      const int e = errno;
      throw Error(name_, std::string("cannot be written (") + std::strerror(e) + ")",
                  write_error_fix(e));
    }
    settle_truncation(part_.path());
    buf_.reserve(kFlush + 4096);
  }
  ~TextOut() {
    if (f_) std::fclose(f_);
  }
  TextOut(const TextOut&) = delete;
  TextOut& operator=(const TextOut&) = delete;
  std::string& buf() { return buf_; }
  void maybe_flush() {
    if (buf_.size() >= kFlush) flush();
  }
  void commit() {
    flush();
    const int closed = std::fclose(f_);
    f_ = nullptr;
    if (closed != 0) fail();
    part_.commit();
  }

 private:
  static constexpr std::size_t kFlush = 1 << 20;
  void flush() {
    if (!buf_.empty() && std::fwrite(buf_.data(), 1, buf_.size(), f_) != buf_.size()) fail();
    buf_.clear();
  }
  [[noreturn]] void fail() const {
    const int e = errno;
    throw Error(name_, std::string("could not be written (") + std::strerror(e) + ")",
                write_error_fix(e));
  }
  PartialFile part_;
  std::string name_;
  std::FILE* f_ = nullptr;
  std::string buf_;
};

std::string num_text(double v) {
  std::string s;
  put_num(s, v);
  return s;
}

/// The joint-set ID of each joint (export_3dec.hpp): set s -> s + 1, the k-th joint with set -1
/// -> sets + 1 + k. `count` IDs in all; a rock bridge of ID i has ID i + count.
struct JointSetIds {
  std::vector<std::size_t> of_joint;
  std::size_t count = 0;
};

JointSetIds joint_set_ids(const JointSystem& js) {
  JointSetIds ids;
  std::size_t k = 0;
  for (const Joint& j : js.joints)
    ids.of_joint.push_back(j.set >= 0 ? std::size_t(j.set) + 1 : js.sets.size() + 1 + k++);
  ids.count = js.sets.size() + k;
  return ids;
}

/// A contact of the JS lines: two kept blocks (rows a < b) facing each other on a joint.
struct Contact {
  std::size_t js, a, b;
  double area;  // of the overlap of the two faces
};

/// The contacts across rock and boundary joints (contacts.hpp) by joint-set ID, sorted by (JS ID,
/// a, b), each pair once. With a [rock] table, a rock bridge (is_rock_bridge) takes its joint's
/// ID + ids.count.
std::vector<Contact> js_contacts(const BlockSystem& bs, const JointSetIds& ids) {
  std::vector<Contact> contacts;
  for (const BlockContact& c : find_contacts(bs))
    contacts.push_back(
        {ids.of_joint[std::size_t(c.joint)] + (is_rock_bridge(bs, c) ? ids.count : 0), c.a, c.b,
         c.area});
  const auto key = [](const Contact& c) { return std::tie(c.js, c.a, c.b); };
  std::sort(contacts.begin(), contacts.end(), [&](const Contact& x, const Contact& y) {
    return std::tie(x.js, x.a, x.b, x.area) < std::tie(y.js, y.a, y.b, y.area);
  });
  contacts.erase(std::unique(contacts.begin(), contacts.end(),
                             [&](const Contact& x, const Contact& y) { return key(x) == key(y); }),
                 contacts.end());
  return contacts;
}

/// 3DEC range text for sorted block IDs: "id a b" per run of consecutive IDs.
std::vector<std::string> id_ranges(const std::vector<std::size_t>& ids) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < ids.size();) {
    std::size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    out.push_back(ids[i] == ids[j] ? "id " + std::to_string(ids[i])
                                   : "id " + std::to_string(ids[i]) + " " + std::to_string(ids[j]));
    i = j + 1;
  }
  return out;
}

/// The TOL line's value (export_3dec.hpp): 3DEC's default ATOL, at most a fifth of the shortest
/// edge, at least the scene's own tolerance.
double grid_tol(const BlockSystem& bs) {
  const Geometry& g = *bs.geometry;
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  double shortest = INFINITY;
  std::size_t row = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const std::size_t nf = bs.blocks[b].faces.size();
    if (bs.blocks[b].flags & kRemoved) {
      row += nf;
      continue;
    }
    const auto base = g.vertex_offset[b];
    for (auto v = base; v < g.vertex_offset[b + 1]; ++v) {
      lo = lo.cwiseMin(g.vertices[std::size_t(v)]);
      hi = hi.cwiseMax(g.vertices[std::size_t(v)]);
    }
    for (std::size_t f = 0; f < nf; ++f, ++row) {
      const auto first = g.face_vertex_offset[row], last = g.face_vertex_offset[row + 1];
      for (auto k = first; k < last; ++k) {
        const auto next = k + 1 < last ? k + 1 : first;
        const Vec3& p = g.vertices[std::size_t(base + g.face_vertices[std::size_t(k)])];
        const Vec3& q = g.vertices[std::size_t(base + g.face_vertices[std::size_t(next)])];
        shortest = std::min(shortest, (q - p).norm());
      }
    }
  }
  const double floor = bs.joints.options.tolerance * bs.joints.length_scale;
  if (!(hi.x() >= lo.x())) return floor;
  return std::max(floor, std::min(0.0012 * (hi - lo).sum() / 3, 0.2 * shortest));
}

/// The kept blocks of each cluster with two or more kept blocks (3DEC IDs: rows + 1, ascending).
std::map<std::int64_t, std::vector<std::size_t>> joined_clusters(const BlockSystem& bs) {
  std::map<std::int64_t, std::vector<std::size_t>> clusters;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b)
    if (!(bs.blocks[b].flags & kRemoved) && bs.blocks[b].cluster >= 0)
      clusters[bs.blocks[b].cluster].push_back(b + 1);
  std::erase_if(clusters, [](const auto& c) { return c.second.size() < 2; });
  return clusters;
}

/// The bodies and 3DEC's critical time step (ThreeDecStats).
void time_step(const BlockSystem& bs, const ThreeDecOptions& opt,
               const std::vector<Contact>& contacts, ThreeDecStats& st) {
  const Geometry& g = *bs.geometry;
  st.dem = dem_bodies(bs);
  for (const Contact& c : contacts) st.max_contact_area = std::max(st.max_contact_area, c.area);
  if (contacts.empty()) {  // no JS contact: bound by the largest face of a kept block
    std::size_t row = 0;
    for (const Block& blk : bs.blocks)
      for (std::size_t f = 0; f < blk.faces.size(); ++f, ++row)
        if (!(blk.flags & kRemoved))
          st.max_contact_area = std::max(st.max_contact_area, g.face_area[row]);
  }
  st.max_contact_stiffness = opt.jkn * st.max_contact_area;
  if (st.dem.moving_block < 0 || !(st.max_contact_area > 0)) return;
  st.min_mass = opt.density * st.dem.moving_volume;
  // 3DEC theory, rigid blocks: dt = frac x 2 sqrt(m_min / k_max) (docs/3dec.md).
  st.critical_timestep =
      kThreeDecTimestepFrac * 2 * std::sqrt(st.min_mass / st.max_contact_stiffness);
  // Options each finite but past the doubles together (--3dec-jkn 1e308 times a contact's area
  // is inf) would give a time step of 0 s or inf (issue 42 item 9).
  if (!(std::isfinite(st.max_contact_stiffness) && std::isfinite(st.critical_timestep) &&
        st.critical_timestep > 0))
    throw Error("--3dec-jkn " + num_text(opt.jkn),
                "with the largest contact (" + num_text(st.max_contact_area) +
                    " m2) and --3dec-density " + num_text(opt.density) +
                    " the contact stiffness would be " + num_text(st.max_contact_stiffness) +
                    " N/m and the time step " + num_text(st.critical_timestep) + " s",
                "give a stiffness and density of the model's order (defaults 1e10 Pa/m, 2650 "
                "kg/m3)");
}

void write_grid(TextOut& out, const BlockSystem& bs, ThreeDecStats& st,
                const std::vector<Contact>& contacts) {
  const Geometry& g = *bs.geometry;
  std::string& s = out.buf();
  // The scene's name with control characters escaped: a comment line stays one line.
  s += "* rockslice " + std::string(version()) + ": 3DEC grid of scene \"" +
       escape_control(bs.joints.name) + "\", rigid blocks (block import filename \"...\")\n";
  s += "* Block IDs are rows of blocks.h5 + 1; faces go clockwise seen from outside.\n";
  s += "TOL ";
  put_num(s, st.tol);
  s += "\n* GRIDPOINTS\n";
  std::size_t gp = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    if (bs.blocks[b].flags & kRemoved) continue;
    for (auto v = g.vertex_offset[b]; v < g.vertex_offset[b + 1]; ++v) {
      const Vec3& x = g.vertices[std::size_t(v)];
      s += "G " + std::to_string(++gp);
      for (int k = 0; k < 3; ++k) s += ' ', put_num(s, x[k]);
      s += '\n';
    }
    out.maybe_flush();
  }
  s += "* FACES\n";
  std::size_t row = 0, face = 0;
  gp = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const std::size_t nf = bs.blocks[b].faces.size();
    if (bs.blocks[b].flags & kRemoved) {
      row += nf;
      continue;
    }
    for (std::size_t f = 0; f < nf; ++f, ++row) {
      // /geometry's loops go counter-clockwise seen from outside: written backwards, from the
      // same first point.
      const auto lo = g.face_vertex_offset[row], hi = g.face_vertex_offset[row + 1];
      s += "F " + std::to_string(++face);
      for (auto k = lo; k < hi; ++k) {
        const auto v = k == lo ? lo : hi - (k - lo);
        s += ' ' + std::to_string(gp + 1 + std::size_t(g.face_vertices[std::size_t(v)]));
      }
      s += '\n';
    }
    gp += std::size_t(g.vertex_offset[b + 1] - g.vertex_offset[b]);
    out.maybe_flush();
  }
  st.gridpoints = gp;
  st.faces = face;
  s += "* BLOCKS\n";
  face = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    if (bs.blocks[b].flags & kRemoved) continue;
    s += "B " + std::to_string(b + 1) + " 1 F";
    for (std::size_t f = 0; f < bs.blocks[b].faces.size(); ++f) s += ' ' + std::to_string(++face);
    s += '\n';
    ++st.blocks;
    out.maybe_flush();
  }
  s += "* JOINT SETS: contacts across rock and boundary joints (docs/3dec.md gives the IDs)\n";
  for (std::size_t i = 0; i < contacts.size();) {
    const std::size_t id = contacts[i].js;
    s += "JS " + std::to_string(id);
    for (std::size_t n = 0; n < 8 && i < contacts.size() && contacts[i].js == id; ++n, ++i)
      s += ' ' + std::to_string(contacts[i].a + 1) + '-' + std::to_string(contacts[i].b + 1);
    s += '\n';
    out.maybe_flush();
  }
  st.contacts = contacts.size();
}

/// `text` as a 3DEC string: in double quotes, or in single quotes if it holds a double quote.
/// Nothing quotes a control character or both quote marks: Error naming `file`.
std::string quoted(const std::string& text, const std::filesystem::path& file) {
  if (std::any_of(text.begin(), text.end(),
                  [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
    throw Error(file.string(), "its name holds a control character, which no 3DEC string can hold",
                "give the grid file a name without control characters");
  const char q = text.find('"') == std::string::npos ? '"' : '\'';
  if (text.find(q) != std::string::npos)
    throw Error(file.string(),
                "its name holds both quote marks (\" and '), which no 3DEC string "
                "can hold",
                "give the grid file a name without one of them");
  return q + text + q;
}

/// The Mohr-Coulomb properties of a contact, as a `block contact property` command.
void put_properties(std::string& s, const ThreeDecOptions& opt, double friction, double cohesion,
                    double tension) {
  s += "block contact property stiffness-normal " + num_text(opt.jkn) + " stiffness-shear " +
       num_text(opt.jks) + " friction " + num_text(friction) + " cohesion " + num_text(cohesion) +
       " tension " + num_text(tension);
}

void write_commands(TextOut& out, const std::string& grid_name, const BlockSystem& bs,
                    const ThreeDecOptions& opt, const JointSetIds& ids,
                    const std::map<std::int64_t, std::vector<std::size_t>>& clusters,
                    const std::vector<Contact>& contacts, ThreeDecStats& st) {
  const JointSystem& js = bs.joints;
  std::vector<std::size_t> fixed;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b)
    if (!(bs.blocks[b].flags & kRemoved) && is_fixed(bs.blocks[b])) fixed.push_back(b + 1);
  std::string& s = out.buf();
  s += "; rockslice " + std::string(version()) + ": the rigid blocks of scene \"" +
       escape_control(js.name) + "\" as a 3DEC model (block IDs: rows of blocks.h5 + 1)\n";
  s += "; critical time step of rigid blocks, 0.1 x 2 sqrt(m_min / k_max): " +
       num_text(st.critical_timestep) + " s (m_min " + num_text(st.min_mass) + " kg, k_max " +
       num_text(st.max_contact_stiffness) + " N/m; docs/3dec.md)\n";
  s += "model new\nblock import filename " + grid_name + "\n";
  s += "block property density " + num_text(opt.density) + "\nmodel gravity 0 0 -9.81\n";
  s += "; blocks joined across construction joints (clusters): group \"cluster-<c>\" in slot "
       "\"cluster\", joined into one block\n";
  for (const auto& [c, members] : clusters) {
    const std::string group = "\"cluster-" + std::to_string(c) + "\" slot \"cluster\"";
    for (const std::string& r : id_ranges(members)) {
      s += "block group " + group + " range " + r + "\n";
      out.maybe_flush();
    }
    s += "block join range group " + group + "\n";
  }
  st.clusters = clusters.size();
  s += "; boundary blocks, and blocks on a face named in fixed_faces: group \"boundary\", fixed\n";
  for (const std::string& r : id_ranges(fixed)) {
    s += "block group \"boundary\" range " + r + "\n";
    out.maybe_flush();
  }
  if (!fixed.empty()) s += "block fix range group \"boundary\"\n";
  st.fixed = fixed.size();
  s += "; contacts: Mohr-Coulomb; first all of them (joint set 0: --3dec-friction), then each "
       "joint set of the grid's JS lines\nblock contact generate-subcontacts\n"
       "block contact jmodel assign mohr\n";
  put_properties(s, opt, opt.friction_deg, 0, 0);
  s += "\n";
  std::vector<const Joint*> joint_of(ids.count + 1, nullptr);  // by base ID
  for (std::size_t i = js.joints.size(); i-- > 0;) joint_of[ids.of_joint[i]] = &js.joints[i];
  std::vector<std::size_t> used;
  for (const Contact& c : contacts)
    if (used.empty() || used.back() != c.js) used.push_back(c.js);
  for (const std::size_t id : used) {
    const bool bridge = id > ids.count;
    const Joint& j = *joint_of[bridge ? id - ids.count : id];
    s += "; JS " + std::to_string(id) + ": " + (bridge ? "rock bridges of " : "");
    s += j.set >= 0
             ? "set \"" + escape_control(js.sets[std::size_t(j.set)].name) + "\""
             : "[[joints]] entry, row " + std::to_string(&j - js.joints.data()) + " of /joints";
    s += bridge ? ", intact rock ([rock])\n" : "\n";
    if (bridge)
      put_properties(s, opt, js.rock.friction_angle_deg, js.rock.cohesion, js.rock.tension);
    else
      put_properties(s, opt, j.friction_angle_deg, j.cohesion, j.tension);
    s += " range joint-set " + std::to_string(id) + "\n";
  }
  st.joint_sets = used.size();
  for (const Contact& c : contacts) st.bridge_contacts += c.js > ids.count ? 1 : 0;
}

}  // namespace

void ThreeDecOptions::validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0))
      throw Error(std::string("--3dec-") + name, "is " + num_text(v), "give a positive number");
  };
  positive(density, "density");
  positive(jkn, "jkn");
  positive(jks, "jks");
  if (!(friction_deg >= 0 && friction_deg < 90))
    throw Error("--3dec-friction", "is " + num_text(friction_deg), "give an angle in [0, 90)");
}

ThreeDecStats write_3dec(const std::filesystem::path& grid, const std::filesystem::path& commands,
                         const BlockSystem& bs, const ThreeDecOptions& opt) {
  opt.validate();
  // A section's polygons (docs/2d.md) would be UDEC blocks, not 3DEC polyhedra: not written.
  if (bs.joints.dimension == 2)
    throw Error(grid.string(), "not written: the blocks are a 2-D section, the export is 3-D only",
                "export it with --format yade (Polyhedra prisms) or --format vtu");
  geometry_of(bs, grid.string());
  const bool same_dir = std::filesystem::absolute(grid).parent_path() ==
                        std::filesystem::absolute(commands).parent_path();
  const std::string grid_name =
      quoted(same_dir ? grid.filename().string() : std::filesystem::absolute(grid).string(), grid);
  ThreeDecStats st;
  for (const Block& b : bs.blocks) st.removed += (b.flags & kRemoved) ? 1 : 0;
  const JointSetIds ids = joint_set_ids(bs.joints);
  const auto contacts = js_contacts(bs, ids);
  const auto clusters = joined_clusters(bs);
  st.tol = grid_tol(bs);
  time_step(bs, opt, contacts, st);
  TextOut g(grid);
  TextOut c(commands);
  write_grid(g, bs, st, contacts);
  write_commands(c, grid_name, bs, opt, ids, clusters, contacts, st);
  g.commit();
  c.commit();
  return st;
}

// UDEC (export_udec.hpp): here, beside the 3DEC writer, for its text file and numbers.
UdecStats write_udec(const std::filesystem::path& out, const BlockSystem& bs) {
  if (bs.joints.dimension != 2)
    throw Error(out.string(),
                "not written: the blocks are 3-D, the UDEC export is for 2-D sections",
                "export a 3-D model with --format 3dec, or slice a section (dimension = 2)");
  const Geometry& g = geometry_of(bs, out.string());
  UdecStats st;
  TextOut f(out);
  std::string& s = f.buf();
  s += "; rockslice " + std::string(version()) + ": the blocks of section \"" +
       escape_control(bs.joints.name) + "\" as UDEC 7 commands (docs/2d.md)\n";
  s += "; UDEC x, y = the section's x, z; corners clockwise; block N is row N - 1 of blocks.h5\n";
  s += "model new\n";
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    if (blk.flags & kRemoved) {
      ++st.removed;
      continue;
    }
    s += "; block " + std::to_string(b + 1);
    if (blk.flags & kBoundary) s += " boundary";
    if (blk.flags & kFixed) s += " fixed";
    if (blk.cluster >= 0) s += " cluster " + std::to_string(blk.cluster);
    s += "\nblock create polygon";
    const auto v0 = std::size_t(g.vertex_offset[b]), v1 = std::size_t(g.vertex_offset[b + 1]);
    for (std::size_t v = v1; v-- > v0;) {  // counter-clockwise in (x, z), written backwards
      s += ' ';
      put_num(s, g.vertices[v].x());
      s += ',';
      put_num(s, g.vertices[v].z());
    }
    s += '\n';
    st.vertices += v1 - v0;
    ++st.blocks;
    f.maybe_flush();
  }
  f.commit();
  return st;
}

}  // namespace slice

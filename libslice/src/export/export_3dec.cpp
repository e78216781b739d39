#include "slice/export_3dec.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "slice/error.hpp"
#include "slice/orientation.hpp"
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
    if (!f_)
      throw Error(name_, std::string("cannot be written (") + std::strerror(errno) + ")",
                  "check that the directory is writable");
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
    throw Error(name_, std::string("could not be written (") + std::strerror(errno) + ")",
                "check that the disk is not full");
  }
  PartialFile part_;
  std::string name_;
  std::FILE* f_ = nullptr;
  std::string buf_;
};

/// A face of a kept block on a rock or boundary joint, for the contact search.
struct JointFace {
  std::int64_t joint;
  std::size_t block, row;  // row: the face's row in /blocks/face_*
  bool plus;               // its outward normal points along the joint's normal
};

/// A face polygon in the joint's plane coordinates, with its box.
struct Flat {
  std::size_t block;
  bool plus;
  std::vector<Vec2> pts;
  Vec2 lo, hi;
};

/// Do two convex polygons of one plane overlap with positive area (by more than tol across
/// every separating direction their edges give)?
bool overlap(const Flat& a, const Flat& b, double tol) {
  for (const Flat* p : {&a, &b}) {
    const std::size_t n = p->pts.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 e = p->pts[(i + 1) % n] - p->pts[i];
      const double len = e.norm();
      if (len <= 0) continue;
      const Vec2 axis(-e.y() / len, e.x() / len);
      double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
      for (const Vec2& q : a.pts) a0 = std::min(a0, axis.dot(q)), a1 = std::max(a1, axis.dot(q));
      for (const Vec2& q : b.pts) b0 = std::min(b0, axis.dot(q)), b1 = std::max(b1, axis.dot(q));
      if (std::min(a1, b1) - std::max(a0, b0) <= tol) return false;
    }
  }
  return true;
}

/// The contacts across rock and boundary joints: (JS id, block, block), sorted, each once.
std::vector<std::array<std::size_t, 3>> find_contacts(const BlockSystem& bs) {
  const Geometry& g = *bs.geometry;
  const JointSystem& js = bs.joints;
  const double tol = js.options.tolerance * js.length_scale;
  std::vector<JointFace> faces;
  std::size_t row = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    for (const Face& f : blk.faces) {
      if (!(blk.flags & kRemoved) && f.joint >= 0 &&
          js.joints[std::size_t(f.joint)].kind != JointKind::construction)
        faces.push_back(
            {f.joint, b, row, f.normal.dot(js.joints[std::size_t(f.joint)].plane.normal) > 0});
      ++row;
    }
  }
  std::stable_sort(faces.begin(), faces.end(),
                   [](const JointFace& x, const JointFace& y) { return x.joint < y.joint; });
  std::vector<std::array<std::size_t, 3>> contacts;
  std::vector<Flat> flats;
  std::vector<std::size_t> order, active;
  for (std::size_t lo = 0; lo < faces.size();) {
    std::size_t hi = lo;
    while (hi < faces.size() && faces[hi].joint == faces[lo].joint) ++hi;
    const Joint& joint = js.joints[std::size_t(faces[lo].joint)];
    const JointFrame fr = plane_frame(joint.dip_deg, joint.dip_direction_deg);
    const std::size_t set_id = joint.set >= 0 ? std::size_t(joint.set) + 1 : js.sets.size() + 1;
    flats.clear();
    for (std::size_t k = lo; k < hi; ++k) {
      const JointFace& jf = faces[k];
      Flat fl{jf.block, jf.plus, {}, Vec2::Constant(INFINITY), Vec2::Constant(-INFINITY)};
      const auto base = g.vertex_offset[jf.block];
      for (auto v = g.face_vertex_offset[jf.row]; v < g.face_vertex_offset[jf.row + 1]; ++v) {
        const Vec3& x = g.vertices[std::size_t(base + g.face_vertices[std::size_t(v)])];
        const Vec2 q(fr.u.dot(x), fr.v.dot(x));
        fl.pts.push_back(q);
        fl.lo = fl.lo.cwiseMin(q);
        fl.hi = fl.hi.cwiseMax(q);
      }
      flats.push_back(std::move(fl));
    }
    // Sweep along u: each face meets the faces of the other side whose u-ranges overlap.
    order.resize(flats.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
      return std::tie(flats[x].lo.x(), x) < std::tie(flats[y].lo.x(), y);
    });
    active.clear();
    for (const std::size_t k : order) {
      const Flat& f = flats[k];
      std::erase_if(active, [&](std::size_t a) { return flats[a].hi.x() <= f.lo.x() + tol; });
      for (const std::size_t a : active) {
        const Flat& o = flats[a];
        if (o.plus == f.plus || o.hi.y() <= f.lo.y() + tol || f.hi.y() <= o.lo.y() + tol) continue;
        if (overlap(f, o, tol))
          contacts.push_back({set_id, std::min(f.block, o.block), std::max(f.block, o.block)});
      }
      active.push_back(k);
    }
    lo = hi;
  }
  std::sort(contacts.begin(), contacts.end());
  contacts.erase(std::unique(contacts.begin(), contacts.end()), contacts.end());
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

void write_grid(TextOut& out, const BlockSystem& bs, ThreeDecStats& st,
                const std::vector<std::array<std::size_t, 3>>& contacts) {
  const Geometry& g = *bs.geometry;
  std::string& s = out.buf();
  s += "* rockslice " + std::string(version()) + ": 3DEC grid of scene " + bs.joints.name +
       ", rigid blocks (block import filename \"...\")\n";
  s += "* Block IDs are rows of blocks.h5 + 1; faces go clockwise seen from outside.\n";
  s += "* GRIDPOINTS\n";
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
  s += "* JOINT SETS: contacts across rock and boundary joints, JS set+1 block-block\n";
  for (std::size_t i = 0; i < contacts.size();) {
    const std::size_t id = contacts[i][0];
    s += "JS " + std::to_string(id);
    for (std::size_t n = 0; n < 8 && i < contacts.size() && contacts[i][0] == id; ++n, ++i)
      s += ' ' + std::to_string(contacts[i][1] + 1) + '-' + std::to_string(contacts[i][2] + 1);
    s += '\n';
    out.maybe_flush();
  }
  st.contacts = contacts.size();
}

void write_commands(TextOut& out, const std::filesystem::path& grid,
                    const std::filesystem::path& commands, const BlockSystem& bs,
                    ThreeDecStats& st) {
  const bool same_dir = std::filesystem::absolute(grid).parent_path() ==
                        std::filesystem::absolute(commands).parent_path();
  const std::string name =
      same_dir ? grid.filename().string() : std::filesystem::absolute(grid).string();
  std::vector<std::size_t> fixed;
  std::map<std::int64_t, std::vector<std::size_t>> clusters;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    if (blk.flags & kRemoved) continue;
    if (blk.flags & (kBoundary | kFixed)) fixed.push_back(b + 1);
    if (blk.cluster >= 0) clusters[blk.cluster].push_back(b + 1);
  }
  std::string& s = out.buf();
  s += "; rockslice " + std::string(version()) + ": imports the rigid blocks of scene " +
       bs.joints.name + " into 3DEC (block IDs: rows of blocks.h5 + 1)\n";
  s += "model new\nblock import filename \"" + name + "\"\n";
  s += "; boundary blocks, and blocks on a face named in fixed_faces: group \"boundary\", fixed\n";
  for (const std::string& r : id_ranges(fixed)) {
    s += "block group \"boundary\" range " + r + "\n";
    out.maybe_flush();
  }
  if (!fixed.empty()) s += "block fix range group \"boundary\"\n";
  s += "; blocks joined across construction joints (clusters): group \"cluster-<c>\"\n";
  for (const auto& [c, ids] : clusters) {
    if (ids.size() < 2) continue;
    ++st.clusters;
    for (const std::string& r : id_ranges(ids)) {
      s += "block group \"cluster-" + std::to_string(c) + "\" range " + r + "\n";
      out.maybe_flush();
    }
  }
  st.fixed = fixed.size();
}

}  // namespace

ThreeDecStats write_3dec(const std::filesystem::path& grid, const std::filesystem::path& commands,
                         const BlockSystem& bs) {
  // A section's polygons (docs/2d.md) would be UDEC blocks, not 3DEC polyhedra: not written.
  if (bs.joints.dimension == 2)
    throw Error(grid.string(), "not written: the blocks are a 2-D section, the export is 3-D only",
                "export it with --format yade (Polyhedra prisms) or --format vtu");
  if (!bs.geometry)
    throw Error(grid.string(), "the blocks have no vertices (no /geometry)",
                "run slice-vertices on the blocks file first");
  ThreeDecStats st;
  for (const Block& b : bs.blocks) st.removed += (b.flags & kRemoved) ? 1 : 0;
  const auto contacts = find_contacts(bs);
  TextOut g(grid);
  TextOut c(commands);
  write_grid(g, bs, st, contacts);
  write_commands(c, grid, commands, bs, st);
  g.commit();
  c.commit();
  return st;
}

}  // namespace slice

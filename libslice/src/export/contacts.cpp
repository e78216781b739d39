#include "slice/contacts.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/polytope.hpp"

namespace slice {
namespace {

/// A face of a kept block on a joint, for the contact search.
struct JointFace {
  std::int64_t joint;
  std::size_t block, row;  // row: the face's row in /blocks/face_*
  bool plus;               // its outward normal points along the joint's normal
};

/// A face polygon in the joint's plane coordinates, with its box.
struct Flat {
  std::size_t block, row;
  bool plus;
  std::vector<Vec2> pts;  // in the joint's (u, v)
  std::vector<Vec3> xs;   // the same, global
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

/// The intersection of two convex polygons of one plane (global frame): `a` clipped by the
/// inner side of each edge of `b`.
std::vector<Vec3> overlap_polygon(std::vector<Vec3> a, const std::vector<Vec3>& b) {
  const Vec3 n = newell_normal(b);  // b runs counter-clockwise about n
  for (std::size_t i = 0; i < b.size() && a.size() >= 3; ++i) {
    const Vec3 out = (b[(i + 1) % b.size()] - b[i]).cross(n).normalized();
    a = clip_polygon(a, Plane{out, out.dot(b[i])});
  }
  return a;
}

}  // namespace

void for_each_contact(const BlockSystem& bs, ContactScope scope, const ContactVisitor& visit) {
  if (!bs.geometry)
    throw Error("/geometry", "the blocks have no vertices, volumes or face areas",
                "run slice-vertices on the blocks file first");
  const Geometry& g = *bs.geometry;
  const JointSystem& js = bs.joints;
  const double tol = js.options.tolerance * js.length_scale;
  std::vector<JointFace> faces;
  std::size_t row = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    for (const Face& f : blk.faces) {
      if ((scope.removed || !(blk.flags & kRemoved)) && f.joint >= 0 &&
          (scope.construction || js.joints[std::size_t(f.joint)].kind != JointKind::construction))
        faces.push_back(
            {f.joint, b, row, f.normal.dot(js.joints[std::size_t(f.joint)].plane.normal) > 0});
      ++row;
    }
  }
  std::stable_sort(faces.begin(), faces.end(),
                   [](const JointFace& x, const JointFace& y) { return x.joint < y.joint; });
  std::vector<Flat> flats;
  std::vector<std::size_t> order, active;
  const auto open_area = [&](std::size_t r) { return g.face_joint_fraction[r] * g.face_area[r]; };
  for (std::size_t lo = 0; lo < faces.size();) {
    std::size_t hi = lo;
    while (hi < faces.size() && faces[hi].joint == faces[lo].joint) ++hi;
    const Joint& joint = js.joints[std::size_t(faces[lo].joint)];
    const JointFrame fr = plane_frame(joint.dip_deg, joint.dip_direction_deg);
    flats.clear();
    for (std::size_t k = lo; k < hi; ++k) {
      const JointFace& jf = faces[k];
      Flat fl{
          jf.block, jf.row, jf.plus, {}, {}, Vec2::Constant(INFINITY), Vec2::Constant(-INFINITY)};
      const auto base = g.vertex_offset[jf.block];
      for (auto v = g.face_vertex_offset[jf.row]; v < g.face_vertex_offset[jf.row + 1]; ++v) {
        const Vec3& x = g.vertices[std::size_t(base + g.face_vertices[std::size_t(v)])];
        const Vec2 q(fr.u.dot(x), fr.v.dot(x));
        fl.pts.push_back(q);
        fl.xs.push_back(x);
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
        const bool f_removed = bs.blocks[f.block].flags & kRemoved,
                   o_removed = bs.blocks[o.block].flags & kRemoved;
        if ((f_removed && o_removed) || !overlap(f, o, tol)) continue;
        // A convex block has no two faces on one plane back to back: the readers refuse a face
        // whose joint is not its plane's, so a contact of a block with itself is a defect here.
        SLICE_ASSERT(f.block != o.block);
        // a < b, but a kept block first in a contact with a removed one.
        const bool f_first = f_removed == o_removed ? f.block < o.block : o_removed;
        const Flat& fa = f_first ? f : o;
        const Flat& fb = f_first ? o : f;
        const Vec3 n = fa.plus ? joint.plane.normal : Vec3(-joint.plane.normal);
        std::vector<Vec3> polygon = overlap_polygon(fa.xs, fb.xs);
        const auto [area, centroid] = polygon_area_centroid(polygon);
        visit({fa.block, fb.block, fa.row, fb.row, faces[lo].joint, area, centroid, n,
               std::min(open_area(f.row), open_area(o.row))},
              polygon);
      }
      active.push_back(k);
    }
    lo = hi;
  }
}

std::vector<BlockContact> find_contacts(const BlockSystem& bs, bool construction) {
  std::vector<BlockContact> contacts;
  for_each_contact(bs, {construction, false},
                   [&](const BlockContact& c, std::span<const Vec3>) { contacts.push_back(c); });
  std::sort(contacts.begin(), contacts.end(), [](const BlockContact& x, const BlockContact& y) {
    return std::tie(x.a, x.b, x.joint, x.face_a, x.face_b) <
           std::tie(y.a, y.b, y.joint, y.face_a, y.face_b);
  });
  return contacts;
}

}  // namespace slice

#include "slice/contacts.hpp"

#include <oneapi/tbb/parallel_for.h>

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
  bool removed;            // its block is
};

/// A face polygon in the joint's plane coordinates, with its box.
struct Flat {
  std::size_t block, row;
  bool plus, removed;
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

namespace {

/// A contact found, with its overlap polygon, before it is handed to the visitor.
struct Found {
  BlockContact contact;
  std::vector<Vec3> polygon;
};

/// The contacts across one joint: `faces` are its faces (of kept blocks, and of removed ones if
/// the scope says so). A uniform grid over the joint's plane, cells about a face's size: each
/// pair of faces of opposite sides whose boxes overlap is tested once, in the cell that holds
/// the lower corner of the overlap of their boxes (the sweep along u this replaces met every
/// face of a 100 m joint's strip: 20 of the 32 s of a million-block model).
void joint_contacts(const BlockSystem& bs, std::span<const JointFace> faces, double tol,
                    bool polygons, std::vector<Found>& out) {
  const Geometry& g = *bs.geometry;
  const Joint& joint = bs.joints.joints[std::size_t(faces.front().joint)];
  const JointFrame fr = plane_frame(joint.dip_deg, joint.dip_direction_deg);
  // The faces' polygons, in a pool of this thread's that keeps its memory from joint to joint
  // (two allocations a face were a tenth of the search).
  thread_local std::vector<Flat> pool;
  if (pool.size() < faces.size()) pool.resize(faces.size());
  const std::span<Flat> flats(pool.data(), faces.size());
  Vec2 lo = Vec2::Constant(INFINITY), hi = Vec2::Constant(-INFINITY);
  double size = 0;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const JointFace& jf = faces[k];
    Flat& fl = flats[k];
    fl.block = jf.block;
    fl.row = jf.row;
    fl.plus = jf.plus;
    fl.removed = jf.removed;
    fl.pts.clear();
    fl.xs.clear();
    fl.lo = Vec2::Constant(INFINITY);
    fl.hi = Vec2::Constant(-INFINITY);
    const auto base = g.vertex_offset[jf.block];
    for (auto v = g.face_vertex_offset[jf.row]; v < g.face_vertex_offset[jf.row + 1]; ++v) {
      const Vec3& x = g.vertices[std::size_t(base + g.face_vertices[std::size_t(v)])];
      const Vec2 q(fr.u.dot(x), fr.v.dot(x));
      fl.pts.push_back(q);
      fl.xs.push_back(x);
      fl.lo = fl.lo.cwiseMin(q);
      fl.hi = fl.hi.cwiseMax(q);
    }
    lo = lo.cwiseMin(fl.lo);
    hi = hi.cwiseMax(fl.hi);
    size += (fl.hi - fl.lo).maxCoeff();
  }
  // Cells of the mean face size, at most about 4 per face.
  const Vec2 extent = (hi - lo).cwiseMax(Vec2::Constant(tol));
  double cell = std::max(size / double(flats.size()), tol);
  const double most = 4.0 * double(flats.size());
  if ((extent.x() / cell + 1) * (extent.y() / cell + 1) > most)
    cell = std::sqrt(extent.x() * extent.y() / most) + std::max(extent.x(), extent.y()) / most;
  const auto nx = std::size_t(extent.x() / cell) + 1, ny = std::size_t(extent.y() / cell) + 1;
  const auto index = [&](double x, double x0, std::size_t n) {
    const double k = std::floor((x - x0) / cell);
    return k <= 0 ? std::size_t(0) : std::min(n - 1, std::size_t(k));
  };
  // Cell lists (CSR), faces in order.
  std::vector<std::size_t> count(nx * ny + 1, 0), members;
  const auto cells_of = [&](const Flat& f, auto&& each) {
    const std::size_t x0 = index(f.lo.x() - tol, lo.x(), nx),
                      x1 = index(f.hi.x() + tol, lo.x(), nx);
    const std::size_t y0 = index(f.lo.y() - tol, lo.y(), ny),
                      y1 = index(f.hi.y() + tol, lo.y(), ny);
    for (std::size_t y = y0; y <= y1; ++y)
      for (std::size_t x = x0; x <= x1; ++x) each(y * nx + x);
  };
  for (const Flat& f : flats) cells_of(f, [&](std::size_t c) { ++count[c + 1]; });
  for (std::size_t c = 0; c < nx * ny; ++c) count[c + 1] += count[c];
  members.resize(count.back());
  {
    std::vector<std::size_t> next(count.begin(), count.end() - 1);
    for (std::size_t k = 0; k < flats.size(); ++k)
      cells_of(flats[k], [&](std::size_t c) { members[next[c]++] = k; });
  }
  const auto open_area = [&](std::size_t r) { return g.face_joint_fraction[r] * g.face_area[r]; };
  for (std::size_t c = 0; c < nx * ny; ++c)
    for (std::size_t i = count[c]; i < count[c + 1]; ++i)
      for (std::size_t j = i + 1; j < count[c + 1]; ++j) {
        const Flat& f = flats[members[i]];
        const Flat& o = flats[members[j]];
        if (o.plus == f.plus) continue;
        const Vec2 low = f.lo.cwiseMax(o.lo), high = f.hi.cwiseMin(o.hi);
        if (high.x() <= low.x() + tol || high.y() <= low.y() + tol) continue;
        // Tested in one cell only: the one that holds the lower corner of the boxes' overlap.
        if (index(low.y(), lo.y(), ny) * nx + index(low.x(), lo.x(), nx) != c) continue;
        const bool f_removed = f.removed, o_removed = o.removed;
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
        if (!polygons) polygon = {};
        out.push_back({{fa.block, fb.block, fa.row, fb.row, faces.front().joint, area, centroid, n,
                        std::min(open_area(f.row), open_area(o.row))},
                       std::move(polygon)});
      }
}

}  // namespace

void for_each_contact(const BlockSystem& bs, ContactScope scope, const ContactVisitor& visit) {
  geometry_of(bs, "/geometry");
  const JointSystem& js = bs.joints;
  const double tol = js.options.tolerance * js.length_scale;
  std::vector<JointFace> faces;
  std::size_t row = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    for (const Face& f : blk.faces) {
      if ((scope.removed || !(blk.flags & kRemoved)) && f.joint >= 0 &&
          (scope.construction || js.joints[std::size_t(f.joint)].kind != JointKind::construction))
        faces.push_back({f.joint, b, row,
                         f.normal.dot(js.joints[std::size_t(f.joint)].plane.normal) > 0,
                         (blk.flags & kRemoved) != 0});
      ++row;
    }
  }
  // By joint, in block order within each (a counting sort: the joints are few).
  std::vector<std::size_t> start(js.joints.size() + 1, 0);
  for (const JointFace& f : faces) ++start[std::size_t(f.joint) + 1];
  for (std::size_t j = 0; j < js.joints.size(); ++j) start[j + 1] += start[j];
  {
    std::vector<JointFace> sorted(faces.size());
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (const JointFace& f : faces) sorted[next[std::size_t(f.joint)]++] = f;
    faces = std::move(sorted);
  }
  std::vector<std::size_t> groups;  // where each joint's faces start (joints with faces)
  for (std::size_t j = 0; j < js.joints.size(); ++j)
    if (start[j + 1] > start[j]) groups.push_back(start[j]);
  groups.push_back(faces.size());
  // The joints in parallel, a batch at a time; each batch's contacts are handed over in joint
  // order on this thread, so the visitor sees the same order on any number of threads.
  constexpr std::size_t kBatchFaces = std::size_t(1) << 18;
  std::vector<std::vector<Found>> found;
  for (std::size_t g0 = 0; g0 + 1 < groups.size();) {
    std::size_t g1 = g0 + 1;
    while (g1 + 1 < groups.size() && groups[g1] - groups[g0] < kBatchFaces) ++g1;
    found.assign(g1 - g0, {});
    tbb::parallel_for(g0, g1, [&](std::size_t k) {
      joint_contacts(bs, std::span(faces).subspan(groups[k], groups[k + 1] - groups[k]), tol,
                     scope.polygons, found[k - g0]);
    });
    for (const auto& joint : found)
      for (const Found& f : joint) visit(f.contact, f.polygon);
    g0 = g1;
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

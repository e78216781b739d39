#include "bodies.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <tuple>

namespace slice {
namespace {

/// Disjoint sets of blocks (union by pointing one root at the other, path halving). Each block
/// its own set until the first join (no array until then).
class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : n_(n) {}
  std::size_t root(std::size_t x) {
    if (parent_.empty()) return x;
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void join(std::size_t a, std::size_t b) {
    const std::size_t ra = root(a), rb = root(b);
    if (ra == rb) return;
    if (parent_.empty()) {
      parent_.resize(n_);
      std::iota(parent_.begin(), parent_.end(), std::size_t(0));
    }
    parent_[ra] = rb;
  }
  /// Whether two sets were ever joined.
  bool joined() const { return !parent_.empty(); }

 private:
  std::size_t n_;
  std::vector<std::size_t> parent_;
};

/// A face of a block on a joint's plane.
struct Side {
  std::size_t block, face;
};

/// The faces on each joint's plane, by side: below[j] holds faces whose outward normal points
/// along the joint's normal (their block lies below the plane), above[j] the others. Only the
/// joints `wanted` says (all if empty), and only blocks `use` accepts.
struct SidesByJoint {
  std::vector<std::vector<Side>> below, above;

  template <typename Wanted, typename Use>
  SidesByJoint(const std::vector<Block>& blocks, const JointSystem& js, Wanted&& wanted, Use&& use)
      : below(js.joints.size()), above(js.joints.size()) {
    for (std::size_t i = 0; i < blocks.size(); ++i) {
      if (!use(i)) continue;
      const Block& b = blocks[i];
      for (std::size_t f = 0; f < b.faces.size(); ++f) {
        const auto j = b.faces[f].joint;
        if (j < 0 || !wanted(std::size_t(j))) continue;
        const bool is_below = b.faces[f].normal.dot(js.joints[std::size_t(j)].plane.normal) > 0;
        (is_below ? below : above)[std::size_t(j)].push_back({i, f});
      }
    }
  }
  /// The faces facing face `f` of block `b` across its joint's plane.
  const std::vector<Side>& facing(const Block& b, std::size_t f, const JointSystem& js) const {
    const auto j = std::size_t(b.faces[f].joint);
    return b.faces[f].normal.dot(js.joints[j].plane.normal) > 0 ? above[j] : below[j];
  }
};

/// How two blocks touch across the plane of one joint, on which both have a face (a.face and
/// c.face, facing each other): the inscribed radius of the region of the plane inside both
/// blocks' other faces. Positive area: touches (the cut test's LP on the plane; docs/design.md,
/// "Clusters and slivers"). `merged` is scratch.
struct Contact {
  bool solved = false;  // an LP was solved (the bounding spheres overlap)
  bool touches = false;
  bool failed = false;
  double size = 0;  // inscribed radius of the shared region (-s* of the cut test)
};

Contact contact(const std::vector<Block>& blocks, const Side& a, const Side& c,
                const JointSystem& js, Referee& referee, std::vector<Face>& merged) {
  const Block& ba = blocks[a.block];
  const Block& bc = blocks[c.block];
  Contact out;
  const double gap = (ba.bsphere.head<3>() - bc.bsphere.head<3>()).norm();
  if (gap >= ba.bsphere[3] + bc.bsphere[3]) return out;
  // Both blocks' other faces, in ba's frame; the cut test on the joint plane.
  merged.clear();
  for (std::size_t f = 0; f < ba.faces.size(); ++f)
    if (f != a.face) merged.push_back(ba.faces[f]);
  const Vec3 shift = bc.origin - ba.origin;
  for (std::size_t f = 0; f < bc.faces.size(); ++f)
    if (f != c.face) {
      Face g = bc.faces[f];
      g.d += g.normal.dot(shift);
      merged.push_back(g);
    }
  const Plane plane = to_local(js.joints[std::size_t(ba.faces[a.face].joint)].plane, ba.origin);
  const CutTest t = referee.cut(merged, plane, {});
  out.solved = true;
  out.failed = t.status != LpStatus::optimal;
  out.touches = !out.failed && t.cuts;
  out.size = -t.s;
  return out;
}

/// How far block b reaches behind its face f: d_f - min over b of n_f . x (one LP); negative if
/// the LP fails.
double depth_behind(const Block& b, std::size_t f, LpSolver& solver, const Tolerances& tol) {
  DenseLp& lp = extents_lp(solver, b.faces, tol);
  lp.c.setZero();
  for (int k = 0; k < 3; ++k)
    if (const int column = lp_column(k, tol); column >= 0) lp.c[column] = -b.faces[f].normal[k];
  const LpResult r = solver.solve(lp);
  return r.status == LpStatus::optimal ? b.faces[f].d + r.objective : -1;
}

/// Clusters (docs/design.md, "Clusters and slivers"): kept blocks with opposite faces of the same
/// construction joint whose other faces leave a region of the shared plane with positive area. A
/// removed block joins no cluster, so nothing kept is joined through one (kept blocks at a slope
/// face would otherwise chain through the removed air blocks into one clump).
void join_clusters(const std::vector<Block>& blocks, const JointSystem& js, Referee& referee,
                   UnionFind& sets, BodyStats& st) {
  std::vector<std::uint8_t> construction(js.joints.size(), 0);
  for (std::size_t j = 0; j < js.joints.size(); ++j)
    construction[j] = js.joints[j].kind == JointKind::construction;
  if (std::find(construction.begin(), construction.end(), 1) == construction.end()) return;
  const SidesByJoint sides(
      blocks, js, [&](std::size_t j) { return construction[j] != 0; },
      [&](std::size_t i) { return !(blocks[i].flags & kRemoved); });
  std::vector<Face> merged;
  for (std::size_t j = 0; j < js.joints.size(); ++j)
    for (const Side& a : sides.below[j])
      for (const Side& c : sides.above[j]) {
        if (sets.root(a.block) == sets.root(c.block)) continue;
        const Contact k = contact(blocks, a, c, js, referee, merged);
        st.contact_lps += k.solved ? 1 : 0;
        st.failed += k.failed ? 1 : 0;
        if (k.touches) sets.join(a.block, c.block);
      }
}

/// A kept block a sliver may join, with what ranks it (larger is better).
struct Neighbour {
  std::size_t block;
  bool sound;  // not a free sliver itself
  bool alike;  // as fixed as the sliver
  double size;
  auto rank() const { return std::make_tuple(sound, alike, size); }
};

/// What a block is to the sliver rules.
enum class Kind : std::uint8_t { removed, kept, sliver };

/// The blocks of sliver bodies (in block order), and per block its kind, its body (the root of
/// its set) and, per body, its kept blocks.
struct Slivers {
  const std::vector<std::size_t>& blocks;
  const std::vector<Kind>& kind;
  const std::vector<std::size_t>& body;
  const std::vector<std::size_t>& members;
};

/// Rules 2 and 3 of form_bodies for the sliver bodies: removed with an excavation, or joined to
/// a kept neighbour in `sets`.
void resolve_slivers(std::vector<Block>& blocks, const JointSystem& js, Referee& referee,
                     const Tolerances& tol, const Slivers& sl, UnionFind& sets, BodyStats& st) {
  const std::vector<std::size_t>& slivers = sl.blocks;
  std::vector<bool> in_sliver_body(blocks.size(), false);
  std::vector<bool> wanted(js.joints.size(), false);
  for (const std::size_t i : slivers) {
    in_sliver_body[i] = true;
    for (const Face& f : blocks[i].faces)
      if (f.joint >= 0) wanted[std::size_t(f.joint)] = true;
  }
  const SidesByJoint sides(
      blocks, js, [&](std::size_t j) { return bool(wanted[j]); }, [](std::size_t) { return true; });
  // Rule 1 needs a size the excavated surface may move by; it takes free blocks only.
  const double excavation =
      js.options.slivers == SliverRule::excavate ? js.options.min_inscribed_diameter : 0.0;
  std::vector<std::vector<Neighbour>> kept(slivers.size());
  std::vector<Face> merged;
  // Pass 1: each sliver's contacts with blocks outside its body; a free one behind an
  // excavated face within the minimum size goes with the removed block. Decided against the
  // zones' removals only (sl.kind): order-free.
  for (std::size_t k = 0; k < slivers.size(); ++k) {
    const std::size_t s = slivers[k];
    const bool alone = sl.members[sl.body[s]] == 1;
    bool removed = false;
    for (std::size_t f = 0; f < blocks[s].faces.size(); ++f) {
      if (blocks[s].faces[f].joint < 0) continue;
      for (const Side& c : sides.facing(blocks[s], f, js)) {
        const bool zone_removed = sl.kind[c.block] == Kind::removed;
        if (c.block == s || (!zone_removed && sl.body[c.block] == sl.body[s])) continue;
        const Contact t = contact(blocks, {s, f}, c, js, referee, merged);
        st.contact_lps += t.solved ? 1 : 0;
        st.failed += t.failed ? 1 : 0;
        if (!t.touches) continue;
        if (!zone_removed) {
          kept[k].push_back({c.block, !in_sliver_body[c.block],
                             is_fixed(blocks[c.block]) == is_fixed(blocks[s]), t.size});
        } else if (alone && !removed && excavation > 0) {
          ++st.reach_lps;
          const double depth = depth_behind(blocks[s], f, referee.solver(), tol);
          removed = depth >= 0 && depth <= excavation + tol.geometry;
          st.failed += depth < 0 ? 1 : 0;
        }
      }
    }
    if (removed) {
      blocks[s].flags |= kRemoved;
      ++st.slivers_removed;
    }
  }
  // Pass 2: each sliver body left joins the best kept neighbour of any of its blocks (not one
  // pass 1 removed), all decided on the bodies as pass 1 left them.
  std::vector<const Neighbour*> best(blocks.size(), nullptr);  // by body
  for (std::size_t k = 0; k < slivers.size(); ++k) {
    if (blocks[slivers[k]].flags & kRemoved) continue;
    const Neighbour*& b = best[sl.body[slivers[k]]];
    for (const Neighbour& n : kept[k]) {
      if (blocks[n.block].flags & kRemoved) continue;
      if (!b || n.rank() > b->rank()) b = &n;  // ties: the first, in block and face order
    }
  }
  for (const std::size_t s : slivers) {
    if (blocks[s].flags & kRemoved) continue;
    if (best[sl.body[s]]) {
      sets.join(s, best[sl.body[s]]->block);
      ++st.slivers_joined;
    } else {
      ++st.slivers_left;
    }
  }
}

}  // namespace

bool is_sliver(const Block& b, const SliceOptions& o, const Tolerances& tol) {
  return !within_limits(b.inradius + tol.geometry, b.bsphere[3] - tol.geometry,
                        o.min_inscribed_diameter, o.max_aspect_ratio);
}

BodyStats form_bodies(std::vector<Block>& blocks, const JointSystem& js, Referee& referee,
                      const Tolerances& tol) {
  BodyStats st;
  const std::size_t n = blocks.size();
  UnionFind sets(n);
  join_clusters(blocks, js, referee, sets, st);

  // Sliver bodies: a free block under the limits, or a cluster of such blocks only (thin pieces
  // on both sides of an exempt cut): either would be one of the model's smallest bodies. Each
  // block's kind on every thread (the blocks' fields are all the work); the rest on arrays.
  // Its cluster is -1 until the ids below are given.
  std::vector<Kind> kind(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        Block& b = blocks[i];
                        b.cluster = -1;
                        kind[i] = (b.flags & kRemoved)            ? Kind::removed
                                  : is_sliver(b, js.options, tol) ? Kind::sliver
                                                                  : Kind::kept;
                      }
                    });
  // Every block a body of its own, none a sliver: no cluster (what follows would give that).
  if (!sets.joined() && std::find(kind.begin(), kind.end(), Kind::sliver) == kind.end()) return st;
  std::vector<std::size_t> body(n);  // the root of each block's set
  for (std::size_t i = 0; i < n; ++i) body[i] = sets.root(i);
  std::vector<std::size_t> members(n, 0), thin(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (kind[i] == Kind::removed) continue;
    ++members[body[i]];
    thin[body[i]] += kind[i] == Kind::sliver ? 1 : 0;
  }
  std::vector<std::size_t> slivers;  // the blocks of sliver bodies, in block order
  for (std::size_t i = 0; i < n; ++i)
    if (kind[i] != Kind::removed && thin[body[i]] == members[body[i]]) slivers.push_back(i);
  if (!slivers.empty()) {
    resolve_slivers(blocks, js, referee, tol, {slivers, kind, body, members}, sets, st);
    for (std::size_t i = 0; i < n; ++i) body[i] = sets.root(i);
  }

  // Cluster ids 0, 1, ... in order of each cluster's first block; -1 for blocks on their own.
  std::fill(members.begin(), members.end(), 0);
  for (std::size_t i = 0; i < n; ++i) ++members[body[i]];
  std::vector<std::int64_t> id(n, -1);
  std::int64_t next = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (members[body[i]] >= 2 && id[body[i]] < 0) id[body[i]] = next++;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i)
                        blocks[i].cluster = id[body[i]];
                    });
  st.clusters = std::size_t(next);
  return st;
}

}  // namespace slice

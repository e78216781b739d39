#include "slice/cut.hpp"

#include <oneapi/tbb/combinable.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#ifdef __linux__
#include <sys/mman.h>
#include <unistd.h>
#endif
#include <exception>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <vector>

#include "../prefetch.hpp"
#include "../threads.hpp"
#include "bodies.hpp"
#include "reach.hpp"
#include "referees.hpp"
#include "slice/cut_reject.hpp"
#include "slice/decide.hpp"
#include "slice/error.hpp"
#include "slice/estimate.hpp"
#include "slice/mesh.hpp"
#include "slice/polytope.hpp"
#include "sphere_grid.hpp"

namespace slice {
namespace {

/// Moves a block's origin by `shift` (block frame): faces keep their planes.
void move_origin(Block& b, const Vec3& shift) {
  for (Face& f : b.faces) f.d -= f.normal.dot(shift);
  b.origin += shift;
}

/// Sizes `v` (empty) to n blocks. A fresh array's pages are first faulted in on every thread:
/// the kernel zeroing them is most of its cost (1e6 blocks: 0.2-0.3 s on one thread here).
void resize_prefaulted(std::vector<Block>& v, std::size_t n) {
  v.reserve(n);
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t chunk = page * 1024;
  const auto at = reinterpret_cast<std::uintptr_t>(v.data());
  const std::uintptr_t lo = (at + page - 1) / page * page,
                       hi = (at + n * sizeof(Block)) / page * page;
  if (page > 0 && hi > lo)
    tbb::parallel_for(lo, hi, chunk, [&](std::uintptr_t a) {
      // On failure (a kernel before 5.14) the pages fault in below, as without this.
      static_cast<void>(
          madvise(reinterpret_cast<void*>(a), std::min(chunk, hi - a), MADV_POPULATE_WRITE));
    });
#endif
  v.resize(n);
}

// ---- Threads (issue 15) ------------------------------------------------------------------------
// The subdivision is sequential by nature, yet once a joint has split a block, what happens to
// each piece later depends only on that piece and on the joints that reach it. So the cut is a
// tree of tasks (oneTBB task groups): a task cuts its blocks by its joints in order until it
// holds CutOptions::tasks blocks, then hands them, in kGroups spatially compact groups, to child
// tasks, each given the task's remaining joints that reach one of its blocks' spheres. Whether
// and where a task splits depends only on its own blocks, never on the threads. The blocks are
// then put back in the order one sequential subdivision makes them (SplitOrder), so blocks.h5 is
// the same bytes for every thread count; the figures a run reports add up over the tasks, so they
// are the same too.

/// One split: at joint `joint`, block `block` kept the side below and `child` (a new block) the
/// side above. Block numbers are local to the subdivision that made them.
struct SplitEvent {
  std::size_t joint, block, child;
};

/// What every subdivision shares (read only, but for the block count).
struct CutContext {
  const JointSystem& js;
  const CutOptions& opt;
  Tolerances tol;
  std::int64_t max_blocks = 0;
  bool limits = false;
  /// The blocks made so far by all tasks together (for max_blocks).
  std::atomic<std::int64_t>* total = nullptr;
  /// The joints, prepared (by number).
  const std::vector<PreparedJoint>* prepared = nullptr;
};

/// A subdivision of up to this many blocks tests a joint against every block's sphere; a larger
/// one looks them up in a grid first.
constexpr std::size_t kScanMax = 2048;

std::string max_blocks_fix() {
  return "raise max_blocks ([options] max_blocks in the scene, or slice-cut --max-blocks) if "
         "the machine has the memory (about 1.4 kB a block at slice-cut's peak), or cut less: "
         "a larger spacing, fewer joints, a smaller domain";
}

/// Where a block reaches its six extremes (eq. 17), in its frame: x[2k] maximises coordinate k,
/// x[2k + 1] minimises it (the extents LPs' optimal points). A piece of the block that still
/// holds such a point has the same extreme there, without an LP.
struct Extremes {
  std::array<Vec3, 6> x;
  /// A ball known to lie inside the block (its frame; radius 0: none known): what remains of
  /// it in a piece bounds that piece's inscribed radius from below, without an LP.
  Ball ball;
};

/// The sequential subdivision of some blocks (its roots: the domain, or those a task was
/// handed) by joints given one at a time in increasing order.
class Subdivision {
 public:
  Subdivision(const CutContext& ctx, std::vector<Block> roots, std::vector<Extremes> root_extremes,
              const Vec3& lo, const Vec3& hi)
      : blocks(std::move(roots)), extremes(std::move(root_extremes)), ctx_(ctx), lo_(lo), hi_(hi) {
    SLICE_ASSERT(extremes.size() == blocks.size());
    if (ctx_.opt.use_index)
      for (const Block& b : blocks) spheres_.push_back(b.bsphere);
  }

  /// The box this subdivision's blocks lie in.
  const Vec3& lo() const { return lo_; }
  const Vec3& hi() const { return hi_; }

  /// Frees the index once no joint is left (a leaf task: thousands of them hold the blocks).
  void release_index() {
    std::vector<Extremes>().swap(extremes);  // no split is left to come
    grid_ = SphereGrid();
    grid_built_for_ = 0;
    spheres_ = SphereList();
    std::vector<std::uint32_t>().swap(stamp_);
    std::vector<std::size_t>().swap(candidates_);
    std::vector<Vec3>().swap(corners_);
    clip_ = ClipScratch();
  }
  /// Frees the blocks (handed to child tasks) and the index; size() keeps their number.
  void release() {
    count = blocks.size();
    std::vector<Block>().swap(blocks);
    release_index();
  }
  /// Blocks made or handed here (also once released).
  std::size_t size() const { return count ? count : blocks.size(); }

 private:
  std::size_t count = 0;

 public:
  std::vector<Block> blocks;
  std::vector<Extremes> extremes;  // of each block, while it may still be split
  std::vector<SplitEvent> events;
  std::vector<std::size_t> joints_that_cut;  // increasing
  LpCounts lps;
  std::size_t splits = 0, splits_undone = 0;
  std::size_t tested = 0;  // joint-block pairs past the index (to the cut LP or settled)
  std::array<std::size_t, 4> rejected{};  // pairs settled without the LP, by CutReject
  std::size_t settled_by_limit = 0;       // CutStats::settled_by_limit
  std::size_t cut_without_lp = 0;         // CutStats::cut_without_lp

  /// The extremes of a split block (`parent`) that lie well inside the piece with new face
  /// `plane` (both in the piece's frame): the piece has the same extremes there, without an LP.
  static unsigned inherited(const CutContext& ctx, const Extremes& parent, const Plane& plane) {
    unsigned bits = 0;
    for (int k = 0; k < 6; ++k)
      if (plane.distance(parent.x[std::size_t(k)]) < -ctx.tol.geometry) bits |= 1u << k;
    return bits;
  }

  /// Sets the bounding sphere of a block (the root's, before a subdivision starts) and `ext`,
  /// moving its origin to the centre of its extents. `v`: the extremes vertex_extremes found for
  /// the directions not `kept`. A piece of a split block keeps the extremes of `parent` (the
  /// split block's, in the piece's frame) that `kept` names (inherited; eq. 17's LPs for the
  /// others only: about half of them on the Table 3 scene).
  static bool set_sphere(const CutContext& ctx, LpSolver& solver, Block& b, LpCounts& lps,
                         Extremes& ext, const VertexExtremes& v, const Extremes* parent = nullptr,
                         unsigned kept = 0) {
    DenseLp* lp = nullptr;
    Vec3 lo, hi;
    const unsigned inherited = parent ? kept : 0u;
    lps.vertex_extremes += static_cast<std::size_t>(std::popcount(v.found));
    for (int k = 0; k < 6; ++k) {
      const int axis = k / 2;
      const double sign = k % 2 == 0 ? 1.0 : -1.0;
      const int column = lp_column(axis, ctx.tol);
      if (column < 0) {
        ext.x[std::size_t(k)] = Vec3::Zero();  // y in a 2-D section: the section itself
      } else if (inherited & (1u << k)) {
        ext.x[std::size_t(k)] = parent->x[std::size_t(k)];
      } else if (v.found & (1u << k)) {
        ext.x[std::size_t(k)] = v.x[std::size_t(k)];
      } else {
        if (!lp) lp = &extents_lp(solver, b.faces, ctx.tol);
        lp->c.setZero();
        lp->c[column] = sign;
        const LpResult r = solver.solve(*lp);
        ++lps.extents;
        if (r.status != LpStatus::optimal) {
          ++lps.failed;
          return false;
        }
        ext.x[std::size_t(k)] = lp_point(r, ctx.tol);
        // The objective is the extent; the point's coordinate may differ by rounding.
        ext.x[std::size_t(k)][axis] = sign * r.objective;
      }
      (sign > 0 ? hi : lo)[axis] = ext.x[std::size_t(k)][axis];
    }
    const Vec3 centre = 0.5 * (lo + hi);
    move_origin(b, centre);
    for (Vec3& x : ext.x) x -= centre;
    ext.ball.centre -= centre;
    b.bsphere << b.origin, 0.5 * (hi - lo).norm();
    // A face whose half-space holds the block's whole bounding box (half sizes h about the
    // origin) cannot touch the block: dropping it changes no geometry and keeps the LPs small
    // (without this, a block inherits every face of its ancestors: ~100 rows per LP on the
    // Table 3 scene). Faces that touch the box but not the block are left to prune_blocks.
    const Vec3 h = (hi - lo) / 2;
    std::erase_if(b.faces, [&](const Face& f) {
      return f.normal.cwiseAbs().dot(h) < f.d - ctx.tol.geometry;
    });
    return true;
  }

  /// Cuts every block this joint may reach. The referee is the calling thread's.
  void cut_by(std::size_t j, Referee& referee) {
    const Joint& joint = ctx_.js.joints[j];
    const PreparedJoint& pj = (*ctx_.prepared)[j];
    find_candidates(j, pj);
    std::size_t cut = 0;
    std::vector<Plane> edges_local;
    for (const std::size_t i : candidates_) {
      Block& b = blocks[i];
      if (b.flags & kBoundary) continue;  // boundary blocks are never cut again
      const Plane plane = to_local(pj.plane, b.origin);
      ++tested;
      const bool shortcuts = use_shortcuts();
      if (shortcuts) frame_pair(pj, i);
      const CutReject settled = shortcuts ? reject(i, plane) : CutReject::none;
      if (settled != CutReject::none) ++rejected[std::size_t(settled)];
      if (settled == CutReject::none && undone_either_way(joint, b, plane, referee)) {
        ++settled_by_limit;
        continue;
      }
      CutTest t;  // no cut, when geometry settled it
      t.status = LpStatus::optimal;
      if (settled == CutReject::none) {
        edges_local.clear();
        for (const Plane& e : pj.edges) edges_local.push_back(to_local(e, b.origin));
        if (shortcuts && surely_cuts(b.faces, plane, corners_, edges_local, pair_lo_, pair_hi_,
                                     ctx_.tol.cut, pair_margin_, clip_)) {
          t.cuts = true;
          ++cut_without_lp;
        } else {
          t = referee.cut(b.faces, plane, edges_local);
          ++lps.cut_test;
        }
      }
      if (t.status != LpStatus::optimal) {
        ++lps.failed;  // the paper's "self-defence": no new data structure
        continue;
      }
      if (!t.cuts) {
        if (joint.kind == JointKind::boundary && pj.edges.empty())
          flag_side(b, joint, plane, referee.solver());
        continue;
      }
      if (split(i, j, plane, referee)) ++cut;
    }
    if (cut > 0) joints_that_cut.push_back(j);
    check_max_blocks(cut);
    if (joint.kind == JointKind::boundary && pj.edges.empty()) {
      // A persistent boundary joint: every block wholly on the keep side becomes a boundary
      // block, also those its plane passes far from.
      for (Block& b : blocks) {
        if (b.flags & kBoundary) continue;
        const double dist = pj.plane.distance(b.bsphere.head<3>());
        if (std::abs(dist) >= b.bsphere[3] + ctx_.tol.cut && dist * joint.boundary_side > 0)
          b.flags |= kBoundary;
      }
    }
  }

 private:
  const CutContext& ctx_;
  Vec3 lo_, hi_;        // a box holding every block of this subdivision
  SphereList spheres_;  // the blocks' spheres (with the index)
  SphereGrid grid_;     // over them, once there are more than kScanMax blocks
  std::size_t grid_built_for_ = 0;
  std::vector<std::uint32_t> stamp_;  // last joint (+1) that visited a block in the grid
  std::vector<std::size_t> candidates_;

  std::vector<Vec3> corners_;  // a joint's corners in a block's frame (frame_pair)
  Vec3 pair_lo_, pair_hi_;     // the block's box (frame_pair)
  double pair_margin_ = 0;     // reject_margin of the pair (frame_pair)
  ClipScratch clip_;

  /// Whether geometry may settle pairs without the cut LP (cut_reject.hpp). Not in a 2-D section
  /// (its blocks are unbounded in y), nor without the index (every pair then goes to the LP).
  bool use_shortcuts() const {
    return ctx_.opt.use_index && ctx_.opt.use_shortcuts && ctx_.tol.dimension == 3;
  }

  /// The pair of joint `pj` and block i as the shortcuts take it: the block's box (the extents
  /// its extremes reach), the joint's corners in its frame, and the margin.
  void frame_pair(const PreparedJoint& pj, std::size_t i) {
    const Block& b = blocks[i];
    const auto& x = extremes[i].x;
    pair_hi_ = Vec3(x[0][0], x[2][1], x[4][2]);
    pair_lo_ = Vec3(x[1][0], x[3][1], x[5][2]);
    corners_.clear();
    for (const Vec3& c : pj.corners) corners_.push_back(c - b.origin);
    // The largest coordinate a corner, the plane's point or the block reaches (global frame).
    const double magnitude =
        std::max(b.origin.cwiseAbs().maxCoeff(), pj.centre.cwiseAbs().maxCoeff() + pj.radius) +
        b.bsphere[3];
    pair_margin_ = reject_margin(ctx_.tol, magnitude);
  }

  /// Whether geometry proves, without the cut LP, that the joint framed by frame_pair does not
  /// cut block i (its plane in the block's frame).
  CutReject reject(std::size_t i, const Plane& plane) {
    return reject_cut(blocks[i].faces, plane, corners_, pair_lo_, pair_hi_, extremes[i].x,
                      pair_margin_, clip_);
  }

  void check_max_blocks(std::size_t cut) {
    // Tasks run in any order: which joint passes the limit first is not defined, so it is not
    // named (the same message for every thread count). Whether the limit is passed is.
    const std::int64_t limit = ctx_.max_blocks;
    if (ctx_.total->fetch_add(std::int64_t(cut)) + std::int64_t(cut) > limit)
      throw Error("/joints", "the cut passed max_blocks = " + std::to_string(limit) + " blocks",
                  max_blocks_fix());
  }

  void rebuild_grid() {
    // Only for a subdivision of more than kScanMax blocks: one task (CutOptions::tasks = 0) or
    // large ones. The finest level has about two cells per block, at most 2^18 cells; rebuilt (one
    // entry per block) as the blocks multiply.
    const std::size_t cells = std::clamp<std::size_t>(blocks.size() * 2, 64, std::size_t(1) << 18);
    grid_.reset(lo_, hi_, cells);
    for (std::size_t i = 0; i < blocks.size(); ++i) grid_.insert(i, blocks[i].bsphere);
    grid_built_for_ = blocks.size();
  }

  /// The blocks joint j may reach (may_reach; all of them without the index), in increasing
  /// index order.
  void find_candidates(std::size_t j, const PreparedJoint& pj) {
    candidates_.clear();
    if (!ctx_.opt.use_index) {
      for (std::size_t i = 0; i < blocks.size(); ++i) candidates_.push_back(i);
      return;
    }
    if (blocks.size() <= kScanMax) {
      spheres_.reached(ReachQuery(pj, ctx_.tol.cut), candidates_);
      return;
    }
    if (blocks.size() >= 2 * grid_built_for_) rebuild_grid();
    if (stamp_.size() < blocks.size()) stamp_.resize(blocks.size(), 0);
    const auto visit = [&](std::size_t i) {
      if (stamp_[i] == j + 1) return;
      stamp_[i] = std::uint32_t(j + 1);
      candidates_.push_back(i);
    };
    if (pj.edges.empty())
      grid_.visit_plane(pj.plane, visit);
    else
      grid_.visit_box(pj.lo, pj.hi, visit);
    std::sort(candidates_.begin(), candidates_.end());
    std::erase_if(candidates_,
                  [&](std::size_t i) { return !may_reach(pj, blocks[i].bsphere, ctx_.tol.cut); });
  }

  /// A block the plane does not cut lies on one side of it: its Chebyshev centre tells which.
  void flag_side(Block& b, const Joint& joint, const Plane& plane_local, LpSolver& solver) {
    const ChebyshevBall c = chebyshev_ball(solver, b.faces, ctx_.tol);
    ++lps.chebyshev;
    if (c.status != LpStatus::optimal) {
      ++lps.failed;
      return;
    }
    if (plane_local.distance(c.centre) * joint.boundary_side > 0) b.flags |= kBoundary;
  }

  /// Whether the size limit would undo a split of block `b` by joint `joint` (its plane in the
  /// block's frame) and the pair may skip the cut LP: a piece between the plane and a parallel face
  /// of the block is thinner than the limit by the margin early_limits uses (the same test,
  /// moved before the LP). Cut or not, nothing changes then: an undone split keeps the block, and
  /// a plane that misses it keeps it too. Not for a boundary joint (a block it misses is flagged
  /// by its side), nor without the shortcuts (every pair then goes to the LP).
  bool undone_either_way(const Joint& joint, const Block& b, const Plane& plane,
                         Referee& referee) const {
    const double min_d = ctx_.js.options.min_inscribed_diameter;
    if (!ctx_.opt.use_shortcuts || !ctx_.limits || !joint.limits ||
        joint.kind == JointKind::boundary || ctx_.opt.backend != LpBackend::native || min_d <= 0)
      return false;
    return thin_slab(b.faces, plane, referee);
  }

  /// How far clear of min_inscribed_diameter a size settled without the child's own LP must be:
  /// twice the band in which limit_ball decides again exactly, plus 1e-7 of the limit.
  static double limit_margin(Referee& referee, double min_d) {
    return 2 * referee.limit_band(min_d) + 1e-7 * min_d;
  }

  /// A child between `plane` and a parallel face of a block with `faces` (a joint of the same
  /// set) is no thicker than their distance apart: true if that is thinner than the limit by more
  /// than the margin and the geometry tolerance (far more than the LP's rounding), so that the
  /// child's LP would say so too.
  bool thin_slab(std::span<const Face> faces, const Plane& plane, Referee& referee) const {
    const double min_d = ctx_.js.options.min_inscribed_diameter;
    return parallel_slab_width(faces, plane) <
           min_d - limit_margin(referee, min_d) - ctx_.tol.geometry;
  }

  /// A copy of block b with room for one more face, and no more (Block's copy assignment keeps
  /// the room: a vector's copy keeps its storage when the copy fits).
  static Block piece(const Block& b) {
    Block p;
    p.faces.reserve(b.faces.size() + 1);
    p = b;
    return p;
  }

  /// Splits block i by the plane of joint j (block frame). False if undone.
  bool split(std::size_t i, std::size_t j, const Plane& plane, Referee& referee) {
    const Joint& joint = ctx_.js.joints[j];
    // An exempt joint (limits = false, e.g. a construction joint outlining an excavation)
    // keeps its cuts: its thin pieces cluster with their neighbours across it.
    const bool limited = ctx_.limits && joint.limits;
    std::array<double, 2> early{-1, -1};
    std::array<bool, 2> open{false, false};  // children early_limits leaves to settled_limits
    Extremes ext_below, ext_above;           // their balls from early_limits, their extremes below
    if (limited && !early_limits(i, plane, referee, early, open, ext_below, ext_above)) {
      ++splits_undone;
      return false;
    }
    // n . x <= d and -n . x <= -d: each piece's faces in an array of exactly their count (a copy
    // and a push_back would double it; the faces took 2.2 times their bytes at 980,152 blocks).
    Block below = piece(blocks[i]);
    Block above = piece(blocks[i]);
    below.faces.push_back({plane.normal, plane.d, std::int64_t(j)});
    above.faces.push_back({-plane.normal, -plane.d, std::int64_t(j)});
    LpSolver& solver = referee.solver();
    const Plane flipped{-plane.normal, -plane.d};
    const unsigned keep_below = inherited(ctx_, extremes[i], plane);
    const unsigned keep_above = inherited(ctx_, extremes[i], flipped);
    // Both pieces' vertices in one pass (below.faces ends with the new face, above's reversed).
    const auto v = vertex_extremes_split(solver, below.faces, 0x3fu & ~keep_below,
                                         0x3fu & ~keep_above, ctx_.tol);
    if (!set_sphere(ctx_, solver, below, lps, ext_below, v[0], &extremes[i], keep_below) ||
        !set_sphere(ctx_, solver, above, lps, ext_above, v[1], &extremes[i], keep_above))
      return false;
    if (limited &&
        (!settled_limits(below, ext_below, open[0], early[0], referee) ||
         !settled_limits(above, ext_above, open[1], early[1], referee) ||
         !within_limits(below, early[0], referee) || !within_limits(above, early[1], referee))) {
      ++splits_undone;
      return false;
    }
    if (joint.kind == JointKind::boundary) {
      (joint.boundary_side > 0 ? above : below).flags |= kBoundary;
    }
    ++splits;
    blocks[i] = std::move(below);
    blocks.push_back(std::move(above));
    extremes[i] = ext_below;
    extremes.push_back(ext_above);
    events.push_back({j, i, blocks.size() - 1});
    if (ctx_.opt.use_index) {
      spheres_.set(i, blocks[i].bsphere);
      spheres_.push_back(blocks.back().bsphere);
    }
    if (grid_built_for_ > 0) {
      grid_.update(i, blocks[i].bsphere);
      grid_.insert(blocks.size() - 1, blocks.back().bsphere);
    }
    return true;
  }

  /// The size limit decided before the children exist, from what the split block knows: false
  /// if a piece between the plane and a parallel face is surely too thin. early[k] is child k's
  /// radius (below, above), or a lower bound of it, where it surely passes, else -1; open[k]:
  /// settled_limits is to try the child once it exists. `below`, `above`: the children's known
  /// balls (Extremes::ball, the part of the split block's ball on their side), for their own
  /// splits. Only with the native backend, and only outside twice the band in which limit_ball
  /// decides again exactly (plus 1e-7 of the limit): there the child's own LP, a few rounding
  /// errors away, decides the same.
  bool early_limits(std::size_t i, const Plane& plane, Referee& referee,
                    std::array<double, 2>& early, std::array<bool, 2>& open, Extremes& below,
                    Extremes& above) {
    const double min_d = ctx_.js.options.min_inscribed_diameter;
    if (ctx_.opt.backend != LpBackend::native || min_d <= 0) return true;
    const double margin = limit_margin(referee, min_d);
    // Other pairs met this test before the cut LP (undone_either_way): here only those of a
    // boundary joint, or every pair without the shortcuts.
    if (thin_slab(blocks[i].faces, plane, referee)) return false;
    for (std::size_t k = 0; k < 2; ++k) {
      const double sign = k == 0 ? 1.0 : -1.0;
      Extremes& child = k == 0 ? below : above;
      // The part of the block's known ball on the child's side holds a ball of the child:
      // thicker than the limit by the margin and the geometry tolerance, the child's LP would
      // pass it too (early[k] is then that ball's radius, a lower bound of the LP's).
      const Ball kept = ball_in_half_space(extremes[i].ball, {sign * plane.normal, sign * plane.d},
                                           ctx_.tol.geometry);
      if (kept.radius > 0) child.ball = kept;
      if (2 * kept.radius > min_d + margin)
        early[k] = kept.radius;
      else
        open[k] = true;
    }
    return true;
  }

  /// The size limit of a child early_limits left open, now that it exists (set_sphere has put its
  /// origin at the middle of its extents): false if it is surely too thin. The ball about the
  /// origin that touches the nearest face is inside it; if that is clear of the limit (as in
  /// early_limits), no LP (a shortcut: not with --no-shortcuts); otherwise its Chebyshev ball
  /// (eq. 18) decides, clear of the limit, or leaves early = -1 for within_limits. Either ball
  /// becomes the child's known ball if larger.
  bool settled_limits(const Block& b, Extremes& ext, bool open, double& early, Referee& referee) {
    if (!open) return true;
    const double min_d = ctx_.js.options.min_inscribed_diameter;
    const double margin = limit_margin(referee, min_d);
    double reach = std::numeric_limits<double>::infinity();  // from the origin to the nearest face
    for (const Face& f : b.faces) reach = std::min(reach, f.d);
    if (reach - ctx_.tol.geometry > ext.ball.radius)
      ext.ball = {Vec3::Zero(), reach - ctx_.tol.geometry};
    if (ctx_.opt.use_shortcuts && 2 * reach > min_d + margin) {
      early = reach;
      return true;
    }
    const ChebyshevBall c = chebyshev_ball(referee.solver(), b.faces, ctx_.tol);
    ++lps.chebyshev;
    if (c.status != LpStatus::optimal) return true;  // within_limits' own LP decides
    ext.ball = {c.centre, c.radius - ctx_.tol.geometry};
    if (2 * c.radius < min_d - margin) return false;
    if (2 * c.radius > min_d + margin) early = c.radius;
    return true;
  }

  /// Size and shape limits (eq. 18): inscribed diameter and bounding / inscribed radius.
  /// `early`: the child's radius from early_limits, which passed the size limit, or -1. With it,
  /// the shape limit too is decided without an LP where R / r is clear of it (by 1e-6).
  bool within_limits(Block& b, double early, Referee& referee) {
    const auto& o = ctx_.js.options;
    if (early >= 0 &&
        (o.max_aspect_ratio <= 0 || b.bsphere[3] < o.max_aspect_ratio * early * (1 - 1e-6)))
      return true;
    const ChebyshevBall c =
        referee.limit_ball(b.faces, o.min_inscribed_diameter, o.max_aspect_ratio, b.bsphere[3]);
    ++lps.chebyshev;
    if (c.status != LpStatus::optimal) {
      ++lps.failed;
      return false;
    }
    b.inradius = c.radius;
    return slice::within_limits(c.radius, b.bsphere[3], o.min_inscribed_diameter,
                                o.max_aspect_ratio);
  }
};

void add(LpCounts& a, const LpCounts& b) {
  a.cut_test += b.cut_test;
  a.extents += b.extents;
  a.chebyshev += b.chebyshev;
  a.redundancy += b.redundancy;
  a.contact += b.contact;
  a.failed += b.failed;
  a.vertex_extremes += b.vertex_extremes;
}

/// A node of the task tree: a subdivision, the joints it is to cut by and, once it has split,
/// the child tasks that hold its blocks.
struct Task {
  Task(const CutContext& ctx, std::vector<Block> roots, std::vector<Extremes> extremes,
       const Vec3& lo, const Vec3& hi)
      : sub(ctx, std::move(roots), std::move(extremes), lo, hi) {}
  Subdivision sub;
  std::vector<std::size_t> joints;              // increasing
  std::vector<std::size_t> from;                // per root: its number in the parent task
  std::vector<std::unique_ptr<Task>> children;  // empty for a leaf
};

constexpr std::size_t kGroups = 8;       // child tasks per split
constexpr std::size_t kNone = SIZE_MAX;  // no parent

/// A 30-bit Morton code of a point of the box [lo, hi]: sorting by it keeps neighbours together.
std::uint32_t morton(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  std::uint32_t code = 0;
  std::uint32_t q[3];
  for (int k = 0; k < 3; ++k) {
    const double t = (p[k] - lo[k]) / std::max(hi[k] - lo[k], 1e-300);
    q[k] = std::uint32_t(std::clamp(t, 0.0, 1.0) * 1023.0);
  }
  for (int bit = 9; bit >= 0; --bit)
    for (int k = 0; k < 3; ++k) code = (code << 1) | ((q[k] >> bit) & 1u);
  return code;
}

/// The order one thread makes blocks in: at each joint, the blocks it splits in increasing
/// (global) number, each keeping its number for the side below and appending the side above.
/// `tasks` lists the tree parents first; parent[t] is t's parent (kNone for the root, whose
/// block 0 is the domain, global block 0).
///
/// Each block made has an id: 0 for the domain, 1 + e for the piece above of the e-th split (the
/// tasks' events counted in task order; a task's k-th split appended its block roots + k). A
/// task's root is a block of its parent, made at an earlier joint. The ids of the blocks split
/// are found on every thread and bucketed by joint; only the numbering is one pass, joint after
/// joint (a piece's number needs the numbers of the blocks split at the same joint).
class SplitOrder {
 public:
  SplitOrder(const std::vector<Task*>& tasks, const std::vector<std::size_t>& parent,
             std::size_t joints)
      : tasks_(tasks), parent_(parent), first_(tasks.size() + 1, 0), splits_at_(joints, 0) {
    for (std::size_t t = 0; t < tasks.size(); ++t)
      first_[t + 1] = first_[t] + tasks[t]->sub.events.size();
    for_each_task([&](std::size_t t) {
      for (const SplitEvent& e : tasks_[t]->sub.events)
        std::atomic_ref(splits_at_[e.joint]).fetch_add(1, std::memory_order_relaxed);
    });
    // The splits by joint, each as (id of the block split, event). Their order within a joint
    // depends on the threads; sorting them by the block's number (unique there) does not.
    std::vector<std::size_t> cursor(joints, 0);
    for (std::size_t j = 0; j + 1 < joints; ++j) cursor[j + 1] = cursor[j] + splits_at_[j];
    std::vector<std::size_t> end = cursor;
    struct Split {
      std::size_t key, event;
    };
    std::vector<Split> by_joint(first_.back());
    for_each_task([&](std::size_t t) {
      const auto& events = tasks_[t]->sub.events;
      for (std::size_t k = 0; k < events.size(); ++k) {
        const SplitEvent& e = events[k];
        SLICE_ASSERT(e.child == roots(t) + k);
        const std::size_t at =
            std::atomic_ref(end[e.joint]).fetch_add(1, std::memory_order_relaxed);
        by_joint[at] = {id(t, e.block), first_[t] + k};
      }
    });
    number_.assign(first_.back() + 1, 0);
    std::size_t next = 1;
    for (std::size_t j = 0; j < joints; ++j) {
      const auto lo = by_joint.begin() + std::ptrdiff_t(cursor[j]);
      const auto hi = lo + std::ptrdiff_t(splits_at_[j]);
      for (auto s = lo; s != hi; ++s) s->key = number_[s->key];
      std::sort(lo, hi, [](const Split& a, const Split& b) { return a.key < b.key; });
      for (auto s = lo; s != hi; ++s) number_[1 + s->event] = next++;
    }
  }

  /// Splits made at each joint.
  const std::vector<std::size_t>& splits_at() const { return splits_at_; }
  /// The global number of block i of task t.
  std::size_t number(std::size_t t, std::size_t i) const { return number_[id(t, i)]; }

  /// Calls f(t) for every task t, on every thread.
  template <typename F>
  void for_each_task(F&& f) const {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tasks_.size()),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t t = range.begin(); t != range.end(); ++t) f(t);
                      });
  }

 private:
  const std::vector<Task*>& tasks_;
  const std::vector<std::size_t>& parent_;
  std::vector<std::size_t> first_;      // per task, its first event (task order), then all
  std::vector<std::size_t> splits_at_;  // by joint
  std::vector<std::size_t> number_;     // by id

  /// The blocks task t started with: the domain for the root, else those it was handed.
  std::size_t roots(std::size_t t) const {
    return parent_[t] == kNone ? 1 : tasks_[t]->from.size();
  }
  std::size_t id(std::size_t t, std::size_t i) const {
    while (parent_[t] != kNone && i < tasks_[t]->from.size()) {
      i = tasks_[t]->from[i];
      t = parent_[t];
    }
    const std::size_t r = roots(t);
    return i < r ? 0 : 1 + first_[t] + (i - r);
  }
};

class Cutter {
 public:
  Cutter(const JointSystem& js, const CutOptions& opt, const Progress& progress)
      : js_(js),
        opt_(opt),
        progress_(progress),
        ctx_{js,
             opt,
             Tolerances::from_scale(js.length_scale, js.options.tolerance, js.dimension),
             opt.max_blocks > 0 ? opt.max_blocks : js.options.max_blocks,
             js.options.min_inscribed_diameter > 0 || js.options.max_aspect_ratio > 0,
             nullptr},
        referees_(opt.backend, ctx_.tol, opt.certify),
        arena_(threads_for(opt.backend, opt.threads)) {}

  CutResult run() {
    check_estimate();
    CutResult out;
    out.blocks.joints = js_;
    arena_.execute([&] {
      const auto t0 = Clock::now();
      subdivide();
      stats_.seconds_cut = seconds_since(t0);
      const auto t1 = Clock::now();
      finish();
      stats_.seconds_finish = seconds_since(t1);
    });
    stats_.joints = js_.joints.size();
    stats_.decisions = referees_.counts();
    stats_.lps.failed += stats_.decisions.failed;
    stats_.blocks = blocks_.size();
    out.blocks.blocks = std::move(blocks_);
    out.stats = stats_;
    return out;
  }

 private:
  const JointSystem& js_;
  const CutOptions& opt_;
  const Progress& progress_;
  CutContext ctx_;
  Referees referees_;
  tbb::task_arena arena_;
  std::mutex progress_mutex_;
  std::atomic<std::size_t> done_{0}, assigned_{0};  // joint-task pairs, for the progress bar
  std::vector<PreparedJoint> prepared_;             // by joint number
  std::vector<Block> blocks_;
  CutStats stats_;
  Vec3 domain_lo_ = Vec3::Zero(), domain_hi_ = Vec3::Zero();

  void report(std::string_view stage, std::size_t done, std::size_t total) {
    if (!progress_) return;
    const std::lock_guard lock(progress_mutex_);
    progress_(stage, done, total);
  }

  /// Refuses, before any work, a joint system whose persistent joints alone make more than
  /// max_blocks blocks.
  void check_estimate() const {
    const BlockEstimate e = estimate_blocks(js_);
    if (e.blocks() <= double(ctx_.max_blocks)) return;
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "its persistent joints make %s%.0f blocks (1 + %lld planes + %.0f lines + %.0f "
                  "points inside the domain), more than max_blocks = %lld",
                  e.sampled ? "about " : "", e.blocks(), static_cast<long long>(e.planes), e.lines,
                  e.points, static_cast<long long>(ctx_.max_blocks));
    throw Error("/joints", buf, max_blocks_fix());
  }

  Block domain_block(Extremes& ext) {
    // A 2-D section is analysed as its unit-thickness slab; its blocks have no y faces.
    const PolytopeInfo info =
        analyse_polytope(solid_region(js_.domain, js_.dimension), ctx_.tol.geometry);
    if (!info.bounded || !info.has_interior)
      throw Error("/domain", "the domain is empty or unbounded", "regenerate it with slice-joints");
    if (const std::string why = precision_problem(info.min, info.max, ctx_.tol.cut); !why.empty())
      throw Error("/domain", why, "move the scene nearer the origin or raise its tolerance");
    domain_lo_ = info.min;
    domain_hi_ = info.max;
    Block b;
    b.origin = info.interior_point;
    for (const Plane& p : js_.domain.planes) {
      const Plane l = to_local(p, b.origin);
      b.faces.push_back({l.normal, l.d, -1});
    }
    LpSolver& solver = referees_.local().solver();
    if (!Subdivision::set_sphere(ctx_, solver, b, stats_.lps, ext,
                                 vertex_extremes(solver, b.faces, 0x3fu, ctx_.tol)))
      throw Error("/domain", "the domain's extents LP failed", "check the domain");
    return b;
  }

  /// The whole cut: the task tree from the domain, then the blocks in sequential order.
  void subdivide() {
    const std::size_t joints = js_.joints.size();
    std::vector<Block> domain;
    std::vector<Extremes> extremes(1);
    domain.push_back(domain_block(extremes[0]));  // sets domain_lo_, domain_hi_
    Task root(ctx_, std::move(domain), std::move(extremes), domain_lo_, domain_hi_);
    root.joints.resize(joints);
    std::iota(root.joints.begin(), root.joints.end(), std::size_t(0));
    std::atomic<std::int64_t> total{1};
    ctx_.total = &total;
    prepared_.resize(joints);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, joints, 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t j = range.begin(); j != range.end(); ++j)
                          prepared_[j] = prepare(js_.joints[j]);
                      });
    ctx_.prepared = &prepared_;
    assigned_ = joints;
    run_task(root);
    ctx_.total = nullptr;
    ctx_.prepared = nullptr;
    std::vector<PreparedJoint>().swap(prepared_);

    // The tree, parents first.
    std::vector<Task*> tasks{&root};
    std::vector<std::size_t> parent{kNone};
    for (std::size_t t = 0; t < tasks.size(); ++t)
      for (auto& c : tasks[t]->children) {
        tasks.push_back(c.get());
        parent.push_back(t);
      }

    // The block array, made while the splits are numbered.
    std::size_t count = 1;
    for (const Task* t : tasks) count += t->sub.events.size();
    tbb::task_group allocation;
    allocation.run([&] { resize_prefaulted(blocks_, count); });
    const SplitOrder order(tasks, parent, joints);

    // Figures: as if one subdivision had run. A joint-block pair is skipped unless the cut LP
    // saw it; there were as many blocks at joint j as the domain and the earlier splits make.
    std::vector<std::uint8_t> cut(joints, 0);
    for (const Task* t : tasks) {
      const Subdivision& s = t->sub;
      add(stats_.lps, s.lps);
      stats_.splits += s.splits;
      stats_.splits_undone += s.splits_undone;
      stats_.pairs_skipped -= s.tested;
      stats_.rejected_plane += s.rejected[std::size_t(CutReject::plane)];
      stats_.rejected_box += s.rejected[std::size_t(CutReject::box)];
      stats_.rejected_faces += s.rejected[std::size_t(CutReject::faces)];
      stats_.settled_by_limit += s.settled_by_limit;
      stats_.cut_without_lp += s.cut_without_lp;
      for (const std::size_t j : s.joints_that_cut) cut[j] = 1;
    }
    std::size_t made = 1;  // blocks before joint j
    for (std::size_t j = 0; j < joints; ++j) {
      stats_.pairs_skipped += made;
      made += order.splits_at()[j];
      stats_.joints_missing += cut[j] ? 0 : 1;
    }

    allocation.wait();
    order.for_each_task([&](std::size_t t) {
      if (!tasks[t]->children.empty()) return;  // its blocks went to its children
      auto& blocks = tasks[t]->sub.blocks;
      for (std::size_t i = 0; i < blocks.size(); ++i)
        blocks_[order.number(t, i)] = std::move(blocks[i]);
      std::vector<Block>().swap(blocks);  // the peak: keep one copy of the block array
    });
  }

  /// Cuts the task's blocks by its joints until it holds opt.tasks blocks; then its children
  /// do the rest, concurrently.
  void run_task(Task& task) {
    const std::size_t split_at = std::max<std::size_t>(opt_.tasks, 2);
    std::size_t k = 0;
    {
      Referee& referee = referees_.local();
      while (k < task.joints.size()) {
        // Two joints ahead the prepared polygon, one ahead its corners and edges (heap arrays
        // of their own, found through the polygon loaded the turn before).
        if (k + 2 < task.joints.size()) prefetch_joint(task.joints[k + 2]);
        if (k + 1 < task.joints.size()) prefetch_polygon(task.joints[k + 1]);
        task.sub.cut_by(task.joints[k++], referee);
        if (opt_.tasks > 0 && task.sub.blocks.size() >= split_at && k < task.joints.size()) break;
      }
    }
    done_ += k;
    report("cut", done_, assigned_);
    if (k < task.joints.size()) hand_out(task, k);
    std::vector<std::size_t>().swap(task.joints);
    if (task.children.empty()) {
      task.sub.release_index();
      return;
    }
    tbb::task_group group;
    for (auto& c : task.children) group.run([this, c = c.get()] { run_task(*c); });
    group.wait();
  }

  /// Starts loading what the reach tests read of joint j: the task's joints are in no order,
  /// and their prepared polygons (about 160 bytes each) fill more than the cache.
  static constexpr std::size_t kPrefetchJoints = 6;
  void prefetch_joint(std::size_t j) const {
    const auto* p = reinterpret_cast<const char*>(&prepared_[j]);
    prefetch(p);
    prefetch(p + 64);
    prefetch(p + sizeof(PreparedJoint) - 1);
    prefetch(&js_.joints[j].kind);
  }

  /// The same for its corners and edges (heap arrays of their own, found through the prepared
  /// polygon: best loaded a turn before, by prefetch_joint).
  void prefetch_polygon(std::size_t j) const {
    const PreparedJoint& pj = prepared_[j];
    for (const auto* v :
         {static_cast<const void*>(pj.corners.data()), static_cast<const void*>(pj.edges.data())}) {
      if (!v) continue;
      prefetch(v);
      prefetch(static_cast<const char*>(v) + 64);
    }
  }

  /// Hands the task's blocks, in kGroups groups of neighbours (Morton order of their spheres'
  /// centres), to as many child tasks, each with those of joints [k, ...) that may reach one of
  /// its blocks: every joint without the index, and every persistent boundary joint (it also
  /// flags blocks it does not reach). Later pieces of a block lie inside its box, so no other
  /// joint can cut them.
  void hand_out(Task& task, std::size_t k) {
    Subdivision& sub = task.sub;
    const std::size_t n = sub.blocks.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::vector<std::uint32_t> code(n);
    for (std::size_t i = 0; i < n; ++i)
      code[i] = morton(sub.blocks[i].bsphere.head<3>(), sub.lo(), sub.hi());
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return code[a] < code[b]; });
    const std::size_t groups = std::min(kGroups, n);
    std::vector<std::size_t> group_of(n);
    for (std::size_t g = 0; g < groups; ++g)
      for (std::size_t r = g * n / groups; r < (g + 1) * n / groups; ++r) group_of[order[r]] = g;

    // The groups' blocks (in their order in the task) and spheres.
    std::vector<std::vector<std::size_t>> members(groups);
    for (std::size_t i = 0; i < n; ++i) members[group_of[i]].push_back(i);
    std::vector<SphereGroup> spheres(groups);
    GroupBoxes boxes;
    for (std::size_t g = 0; g < groups; ++g) {
      for (const std::size_t i : members[g]) spheres[g].add(sub.blocks[i].bsphere);
      boxes.set(g, spheres[g].lo(), spheres[g].hi());
    }

    // The joints of each group: the groups each joint may reach (bits), on every thread (the
    // root's hand-out tests all the joints).
    static_assert(kGroups <= 8 && kGroups <= GroupBoxes::kMax);
    std::vector<std::uint8_t> reached(task.joints.size() - k, 0);
    // Isolated: a thread waiting here runs only these tests, not another task (whose children
    // would then wait for it).
    tbb::this_task_arena::isolate([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, reached.size(), 1024),
          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t m = range.begin(); m != range.end(); ++m) {
              if (m + kPrefetchJoints < range.end())
                prefetch_joint(task.joints[k + m + kPrefetchJoints]);
              const std::size_t j = task.joints[k + m];
              const Joint& joint = js_.joints[j];
              const bool all =
                  !opt_.use_index || (joint.kind == JointKind::boundary && joint.persistent());
              if (all) {
                reached[m] = std::uint8_t((1u << groups) - 1);
                continue;
              }
              // The groups' boxes first, then the spheres of those they pass.
              const PreparedJoint& pj = prepared_[j];
              const ReachQuery q(pj, ctx_.tol.cut);
              for (unsigned bits = boxes.may_reach(pj, ctx_.tol.cut); bits; bits &= bits - 1) {
                const auto g = std::size_t(std::countr_zero(bits));
                if (spheres[g].any_reached(q)) reached[m] |= std::uint8_t(1u << g);
              }
            }
          });
    });
    std::vector<std::vector<std::size_t>> lists(groups);
    for (std::size_t m = 0; m < reached.size(); ++m)
      for (std::size_t g = 0; g < groups; ++g)
        if (reached[m] >> g & 1u) lists[g].push_back(task.joints[k + m]);
    // The progress bar's total: the pairs handed out replace the task's unprocessed ones.
    for (const auto& l : lists) assigned_ += l.size();
    assigned_ -= task.joints.size() - k;

    // The children: each group's blocks and its box.
    for (std::size_t g = 0; g < groups; ++g) {
      std::vector<Block> roots;
      std::vector<Extremes> extremes;
      for (const std::size_t i : members[g]) {
        roots.push_back(std::move(sub.blocks[i]));
        extremes.push_back(sub.extremes[i]);
      }
      auto child = std::make_unique<Task>(ctx_, std::move(roots), std::move(extremes),
                                          spheres[g].lo().cwiseMax(sub.lo()),
                                          spheres[g].hi().cwiseMin(sub.hi()));
      child->from = std::move(members[g]);
      child->joints = std::move(lists[g]);
      task.children.push_back(std::move(child));
    }
    sub.release();
  }

  void finish() {
    tbb::task_group trim;
#ifdef __GLIBC__
    // The tasks' many small arrays are freed now; give their pages back before the blocks are
    // pruned and written (1.0 m Table 3 scene: peak RSS 1.75 GB -> 1.62 GB), on one thread while
    // the others find the centres.
    trim.run([] { malloc_trim(0); });
#endif
    // Chebyshev centre: the origin of every block, its inradius. Blocks are independent.
    std::atomic<std::size_t> done{0};
    tbb::combinable<LpCounts> lps;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        LpSolver& solver = referees_.local().solver();
                        LpCounts& mine = lps.local();
                        std::vector<Face> core;
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          prefetch_faces_ahead(blocks_, i);
                          Block& b = blocks_[i];
                          const ChebyshevBall c = chebyshev_ball(solver, b.faces, ctx_.tol);
                          ++mine.chebyshev;
                          SLICE_ASSERT(c.status == LpStatus::optimal && c.radius > 0);
                          b.inradius = c.radius;
                          move_origin(b, unique_centre(b, c, core, solver, mine));
                        }
                        const std::size_t n = done += range.size();
                        report("centres", n, blocks_.size());
                      });
    trim.wait();
    lps.combine_each([&](const LpCounts& c) { add(stats_.lps, c); });
    // Removal zones: blocks whose centre is inside are removed (kept in the file, flagged).
    std::vector<MeshInside> meshes;
    for (const TriangleMesh& m : js_.zone_meshes) meshes.emplace_back(m);
    std::atomic<std::size_t> boundary{0}, removed{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::size_t on_boundary = 0, inside_zone = 0;
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          Block& b = blocks_[i];
                          if (in_zone(b.origin, meshes)) b.flags |= kRemoved;
                          on_boundary += (b.flags & kBoundary) ? 1 : 0;
                          inside_zone += (b.flags & kRemoved) ? 1 : 0;
                        }
                        boundary += on_boundary;
                        removed += inside_zone;
                      });
    stats_.boundary += boundary;
    stats_.removed += removed;
    if (js_.options.fixed_faces) mark_fixed();
    // Clusters, and the slivers exempt cuts leave (bodies.hpp): removed with an excavation, or
    // joined to a neighbour.
    const BodyStats b = form_bodies(blocks_, js_, referees_.local(), ctx_.tol);
    stats_.clusters = b.clusters;
    stats_.lps.contact += b.contact_lps;
    stats_.lps.extents += b.reach_lps;
    stats_.lps.failed += b.failed;
    stats_.removed += b.slivers_removed;
    stats_.slivers_removed = b.slivers_removed;
    stats_.slivers_joined = b.slivers_joined;
    stats_.slivers_left = b.slivers_left;
  }

  /// Whether a block's centre `x` is inside a removal zone (`meshes`: the mesh zones').
  bool in_zone(const Vec3& x, const std::vector<MeshInside>& meshes) const {
    for (const Region& z : js_.zones)
      if (std::all_of(z.planes.begin(), z.planes.end(),
                      [&](const Plane& p) { return p.distance(x) < 0; }))
        return true;
    return std::any_of(meshes.begin(), meshes.end(),
                       [&](const MeshInside& inside) { return inside(x); });
  }

  // [options] fixed_faces: a block that reaches a named face of the domain's bounding box, to
  // within the geometry tolerance, is fixed. Its extents (six LPs) only when faces are named.
  void mark_fixed() {
    std::atomic<std::size_t> lp_count{0}, vertex_count{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        LpSolver& solver = referees_.local().solver();
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          Block& b = blocks_[i];
                          const Extents e = extents(solver, b.faces, ctx_.tol);
                          // Failed LPs were solved again exactly.
                          SLICE_ASSERT(e.status == LpStatus::optimal);
                          lp_count += static_cast<std::size_t>(e.lps);
                          vertex_count += static_cast<std::size_t>(e.at_vertices);
                          const Vec3 lo = b.origin + e.min, hi = b.origin + e.max;
                          for (int k = 0; k < 6; ++k) {
                            if (!(js_.options.fixed_faces & (1u << k))) continue;
                            const int axis = k / 2;
                            const bool touches =
                                k % 2 == 0 ? lo[axis] <= domain_lo_[axis] + ctx_.tol.geometry
                                           : hi[axis] >= domain_hi_[axis] - ctx_.tol.geometry;
                            if (touches) b.flags |= kFixed;
                          }
                        }
                      });
    stats_.lps.extents += lp_count;
    stats_.lps.vertex_extremes += vertex_count;
    for (const Block& b : blocks_) stats_.fixed += (b.flags & kFixed) ? 1 : 0;
  }

  /// The Chebyshev centre is not unique (a box longer than wide has a segment of them) and each
  /// backend may return another point of that set, which would make zone membership depend on
  /// the backend. The centre used is the middle of the extents of the "core": the points where
  /// a ball of radius (1 - kCoreShrink) r* fits. That is one point whatever the backend (up to
  /// LP accuracy), and on a segment or a centrally symmetric set of centres, its middle.
  Vec3 unique_centre(const Block& b, const ChebyshevBall& c, std::vector<Face>& core,
                     LpSolver& solver, LpCounts& lps) const {
    constexpr double kCoreShrink = 1e-6;
    core = b.faces;
    for (Face& f : core) f.d -= (1 - kCoreShrink) * c.radius;
    const Extents e = extents(solver, core, ctx_.tol);
    lps.chebyshev += static_cast<std::size_t>(e.lps);
    lps.vertex_extremes += static_cast<std::size_t>(e.at_vertices);
    if (e.status != LpStatus::optimal) {
      ++lps.failed;
      return c.centre;
    }
    return e.centre;
  }
};

}  // namespace

CutResult cut_blocks(const JointSystem& js, const CutOptions& opt, const Progress& progress) {
  return Cutter(js, opt, progress).run();
}

}  // namespace slice

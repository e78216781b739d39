#pragma once
// The sequential subdivision (paper section 3): the blocks of one task (cut.cpp) cut by its
// joints one at a time, each pair settled by geometry where it can (cut_reject.hpp) and by the
// referee's LP where it cannot, each split checked against the size and shape limits (eq. 18).
// Internal to the cut: cut.cpp makes the tasks, hands their blocks on and puts them back in order.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "reach.hpp"
#include "referees.hpp"
#include "slice/cut.hpp"
#include "slice/cut_reject.hpp"
#include "slice/error.hpp"
#include "sphere_grid.hpp"

namespace slice::cutting {

/// Moves a block's origin by `shift` (block frame): faces keep their planes.
inline void move_origin(Block& b, const Vec3& shift) {
  for (Face& f : b.faces) f.d -= f.normal.dot(shift);
  b.origin += shift;
}

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

/// How to get past CutOptions::max_blocks (the fix of its error).
std::string max_blocks_fix();

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
                         unsigned kept = 0);

  /// Cuts every block this joint may reach. The referee is the calling thread's.
  void cut_by(std::size_t j, Referee& referee);

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
  void frame_pair(const PreparedJoint& pj, std::size_t i);

  /// Whether geometry proves, without the cut LP, that the joint framed by frame_pair does not
  /// cut block i (its plane in the block's frame).
  CutReject reject(std::size_t i, const Plane& plane);

  void check_max_blocks(std::size_t cut);

  void rebuild_grid();

  /// The blocks joint j may reach (may_reach; all of them without the index), in increasing
  /// index order.
  void find_candidates(std::size_t j, const PreparedJoint& pj);

  /// A block the plane does not cut lies on one side of it: its Chebyshev centre tells which.
  void flag_side(Block& b, const Joint& joint, const Plane& plane_local, LpSolver& solver);

  /// Whether the size limit would undo a split of block `b` by joint `joint` (its plane in the
  /// block's frame) and the pair may skip the cut LP: a piece between the plane and a parallel face
  /// of the block is thinner than the limit by the margin early_limits uses (the same test,
  /// moved before the LP). Cut or not, nothing changes then: an undone split keeps the block, and
  /// a plane that misses it keeps it too. Not for a boundary joint (a block it misses is flagged
  /// by its side), nor without the shortcuts (every pair then goes to the LP).
  bool undone_either_way(const Joint& joint, const Block& b, const Plane& plane,
                         Referee& referee) const;

  /// How far clear of min_inscribed_diameter a size settled without the child's own LP must be:
  /// twice the band in which limit_ball decides again exactly, plus 1e-7 of the limit.
  static double limit_margin(Referee& referee, double min_d);

  /// A child between `plane` and a parallel face of a block with `faces` (a joint of the same
  /// set) is no thicker than their distance apart: true if that is thinner than the limit by more
  /// than the margin and the geometry tolerance (far more than the LP's rounding), so that the
  /// child's LP would say so too.
  bool thin_slab(std::span<const Face> faces, const Plane& plane, Referee& referee) const;

  /// A copy of block b with room for one more face, and no more (Block's copy assignment keeps
  /// the room: a vector's copy keeps its storage when the copy fits).
  static Block piece(const Block& b);

  /// Splits block i by the plane of joint j (block frame). False if undone.
  bool split(std::size_t i, std::size_t j, const Plane& plane, Referee& referee);

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
                    Extremes& above);

  /// The size limit of a child early_limits left open, now that it exists (set_sphere has put its
  /// origin at the middle of its extents): false if it is surely too thin. The ball about the
  /// origin that touches the nearest face is inside it; if that is clear of the limit (as in
  /// early_limits), no LP (a shortcut: not with --no-shortcuts); otherwise its Chebyshev ball
  /// (eq. 18) decides, clear of the limit, or leaves early = -1 for within_limits. Either ball
  /// becomes the child's known ball if larger.
  bool settled_limits(const Block& b, Extremes& ext, bool open, double& early, Referee& referee);

  /// Size and shape limits (eq. 18): inscribed diameter and bounding / inscribed radius.
  /// `early`: the child's radius from early_limits, which passed the size limit, or -1. With it,
  /// the shape limit too is decided without an LP where R / r is clear of it (by 1e-6).
  bool within_limits(Block& b, double early, Referee& referee);
};

}  // namespace slice::cutting

#include "subdivision.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

#include "slice/decide.hpp"
#include "slice/lp.hpp"
#include "slice/polytope.hpp"

namespace slice::cutting {

/// A subdivision of up to this many blocks tests a joint against every block's sphere; a larger
/// one looks them up in a grid first.
constexpr std::size_t kScanMax = 2048;

std::string max_blocks_fix() {
  return "raise max_blocks ([options] max_blocks in the scene, or slice-cut --max-blocks) if "
         "the machine has the memory (about 1.4 kB a block at slice-cut's peak), or cut less: "
         "a larger spacing, fewer joints, a smaller domain";
}

bool Subdivision::set_sphere(const CutContext& ctx, LpSolver& solver, Block& b, LpCounts& lps,
                             Extremes& ext, const VertexExtremes& v, const Extremes* parent,
                             unsigned kept) {
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
  std::erase_if(b.faces,
                [&](const Face& f) { return f.normal.cwiseAbs().dot(h) < f.d - ctx.tol.geometry; });
  return true;
}

void Subdivision::cut_by(std::size_t j, Referee& referee) {
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

void Subdivision::frame_pair(const PreparedJoint& pj, std::size_t i) {
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

CutReject Subdivision::reject(std::size_t i, const Plane& plane) {
  return reject_cut(blocks[i].faces, plane, corners_, pair_lo_, pair_hi_, extremes[i].x,
                    pair_margin_, clip_);
}

void Subdivision::check_max_blocks(std::size_t cut) {
  // Tasks run in any order: which joint passes the limit first is not defined, so it is not
  // named (the same message for every thread count). Whether the limit is passed is.
  const std::int64_t limit = ctx_.max_blocks;
  if (ctx_.total->fetch_add(std::int64_t(cut)) + std::int64_t(cut) > limit)
    throw Error("/joints", "the cut passed max_blocks = " + std::to_string(limit) + " blocks",
                max_blocks_fix());
}

void Subdivision::rebuild_grid() {
  // Only for a subdivision of more than kScanMax blocks: one task (CutOptions::tasks = 0) or
  // large ones. The finest level has about two cells per block, at most 2^18 cells; rebuilt (one
  // entry per block) as the blocks multiply.
  const std::size_t cells = std::clamp<std::size_t>(blocks.size() * 2, 64, std::size_t(1) << 18);
  grid_.reset(lo_, hi_, cells);
  for (std::size_t i = 0; i < blocks.size(); ++i) grid_.insert(i, blocks[i].bsphere);
  grid_built_for_ = blocks.size();
}

void Subdivision::find_candidates(std::size_t j, const PreparedJoint& pj) {
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

void Subdivision::flag_side(Block& b, const Joint& joint, const Plane& plane_local,
                            LpSolver& solver) {
  const ChebyshevBall c = chebyshev_ball(solver, b.faces, ctx_.tol);
  ++lps.chebyshev;
  if (c.status != LpStatus::optimal) {
    ++lps.failed;
    return;
  }
  if (plane_local.distance(c.centre) * joint.boundary_side > 0) b.flags |= kBoundary;
}

bool Subdivision::undone_either_way(const Joint& joint, const Block& b, const Plane& plane,
                                    Referee& referee) const {
  const double min_d = ctx_.js.options.min_inscribed_diameter;
  if (!ctx_.opt.use_shortcuts || !ctx_.limits || !joint.limits ||
      joint.kind == JointKind::boundary || ctx_.opt.backend != LpBackend::native || min_d <= 0)
    return false;
  return thin_slab(b.faces, plane, referee);
}

double Subdivision::limit_margin(Referee& referee, double min_d) {
  return 2 * referee.limit_band(min_d) + 1e-7 * min_d;
}

bool Subdivision::thin_slab(std::span<const Face> faces, const Plane& plane,
                            Referee& referee) const {
  const double min_d = ctx_.js.options.min_inscribed_diameter;
  return parallel_slab_width(faces, plane) <
         min_d - limit_margin(referee, min_d) - ctx_.tol.geometry;
}

Block Subdivision::piece(const Block& b) {
  Block p;
  p.faces.reserve(b.faces.size() + 1);
  p = b;
  return p;
}

bool Subdivision::split(std::size_t i, std::size_t j, const Plane& plane, Referee& referee) {
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

bool Subdivision::early_limits(std::size_t i, const Plane& plane, Referee& referee,
                               std::array<double, 2>& early, std::array<bool, 2>& open,
                               Extremes& below, Extremes& above) {
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

bool Subdivision::settled_limits(const Block& b, Extremes& ext, bool open, double& early,
                                 Referee& referee) {
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

bool Subdivision::within_limits(Block& b, double early, Referee& referee) {
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
  return slice::within_limits(c.radius, b.bsphere[3], o.min_inscribed_diameter, o.max_aspect_ratio);
}

}  // namespace slice::cutting

#include "slice/cut.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include "slice/decide.hpp"
#include "slice/error.hpp"
#include "slice/estimate.hpp"
#include "slice/polytope.hpp"
#include "sphere_grid.hpp"

namespace slice {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// A joint prepared for cutting: its polygon in global coordinates and its bounding sphere.
struct PreparedJoint {
  Plane plane;               // global
  std::vector<Plane> edges;  // polygon edges as in-plane half-planes (global), empty: persistent
  Vec3 centre = Vec3::Zero();
  double radius = 0;                          // polygon's bounding sphere about centre
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // polygon's bounding box
};

PreparedJoint prepare(const Joint& j) {
  PreparedJoint p;
  p.plane = j.plane;
  p.centre = j.centre;
  if (j.persistent()) return p;
  const std::vector<Vec3> v = joint_polygon(j);
  for (const Vec2& uv : j.polygon_uv) p.radius = std::max(p.radius, uv.norm());
  p.lo = p.hi = v.front();
  for (std::size_t k = 0; k < v.size(); ++k) {
    const Vec3& a = v[k];
    const Vec3& b = v[(k + 1) % v.size()];
    // Counter-clockwise about n: the outward in-plane normal of edge a -> b is (b - a) x n.
    const Vec3 m = (b - a).cross(j.plane.normal).normalized();
    p.edges.push_back({m, m.dot(a)});
    p.lo = p.lo.cwiseMin(a);
    p.hi = p.hi.cwiseMax(a);
  }
  return p;
}

/// Moves a block's origin by `shift` (block frame): faces keep their planes.
void move_origin(Block& b, const Vec3& shift) {
  for (Face& f : b.faces) f.d -= f.normal.dot(shift);
  b.origin += shift;
}

class Cutter {
 public:
  Cutter(const JointSystem& js, const CutOptions& opt, const Progress& progress)
      : js_(js),
        opt_(opt),
        progress_(progress),
        tol_(Tolerances::from_scale(js.length_scale, js.options.tolerance)),
        referee_(opt.backend, tol_, opt.certify),
        solver_(referee_.solver()) {}

  CutResult run() {
    check_estimate();
    CutResult out;
    out.blocks.joints = js_;
    start_domain();
    const auto t0 = Clock::now();
    for (std::size_t j = 0; j < js_.joints.size(); ++j) {
      cut_by(j);
      if (progress_) progress_("cut", j + 1, js_.joints.size());
    }
    stats_.seconds_cut = seconds_since(t0);
    const auto t1 = Clock::now();
    finish();
    stats_.seconds_finish = seconds_since(t1);
    stats_.joints = js_.joints.size();
    stats_.decisions = referee_.counts();
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
  Tolerances tol_;
  Referee referee_;
  LpSolver& solver_;  // the referee's: failed LPs are solved again exactly
  std::vector<Block> blocks_;
  SphereGrid grid_;
  std::size_t grid_built_for_ = 0;
  std::vector<std::uint32_t> stamp_;  // last joint (+1) that visited a block in the grid
  std::vector<std::size_t> candidates_;
  CutStats stats_;
  Vec3 domain_lo_ = Vec3::Zero(), domain_hi_ = Vec3::Zero();

  std::int64_t max_blocks() const {
    return opt_.max_blocks > 0 ? opt_.max_blocks : js_.options.max_blocks;
  }

  static std::string max_blocks_fix() {
    return "raise max_blocks ([options] max_blocks in the scene, or slice-cut --max-blocks) if "
           "the machine has the memory (about 1.6 kB a block at slice-cut's peak), or cut less: "
           "a larger spacing, fewer joints, a smaller domain";
  }

  /// Refuses, before any work, a joint system whose persistent joints alone make more than
  /// max_blocks blocks.
  void check_estimate() const {
    const BlockEstimate e = estimate_blocks(js_);
    if (e.blocks() <= double(max_blocks())) return;
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "its persistent joints make %s%.0f blocks (1 + %lld planes + %.0f lines + %.0f "
                  "points inside the domain), more than max_blocks = %lld",
                  e.sampled ? "about " : "", e.blocks(), static_cast<long long>(e.planes), e.lines,
                  e.points, static_cast<long long>(max_blocks()));
    throw Error("/joints", buf, max_blocks_fix());
  }

  bool limits() const {
    return js_.options.min_inscribed_diameter > 0 || js_.options.max_aspect_ratio > 0;
  }

  void start_domain() {
    const PolytopeInfo info = analyse_polytope(js_.domain.planes, tol_.geometry);
    if (!info.bounded || !info.has_interior)
      throw Error("/domain", "the domain is empty or unbounded", "regenerate it with slice-joints");
    if (const std::string why = precision_problem(info.min, info.max, tol_.cut); !why.empty())
      throw Error("/domain", why, "move the scene nearer the origin or raise its tolerance");
    domain_lo_ = info.min;
    domain_hi_ = info.max;
    Block b;
    b.origin = info.interior_point;
    for (const Plane& p : js_.domain.planes) {
      const Plane l = to_local(p, b.origin);
      b.faces.push_back({l.normal, l.d, -1});
    }
    if (!set_sphere(b))
      throw Error("/domain", "the domain's extents LP failed", "check the domain");
    blocks_.push_back(std::move(b));
    rebuild_grid();
  }

  /// Extents (eq. 17): the bounding sphere, and the origin moved to the box centre so that
  /// the block's numbers stay small. False if an LP failed.
  bool set_sphere(Block& b) {
    const Extents e = extents(solver_, b.faces, tol_);
    stats_.lps.extents += 6;
    if (e.status != LpStatus::optimal) {
      ++stats_.lps.failed;
      return false;
    }
    move_origin(b, e.centre);
    b.bsphere << b.origin, e.radius;
    drop_faces_clear_of_box(b, (e.max - e.min) / 2);
    return true;
  }

  /// A face whose half-space holds the block's whole bounding box (half sizes h about the
  /// origin) cannot touch the block: dropping it changes no geometry and keeps the LPs small
  /// (without this, a block inherits every face of its ancestors: ~100 rows per LP on the
  /// Table 3 scene). Faces that touch the box but not the block are left to prune_blocks.
  void drop_faces_clear_of_box(Block& b, const Vec3& h) {
    std::erase_if(b.faces,
                  [&](const Face& f) { return f.normal.cwiseAbs().dot(h) < f.d - tol_.geometry; });
  }

  void rebuild_grid() {
    // The finest level has about two cells per block, at most 2^18 cells; rebuilt (one entry
    // per block) as the blocks multiply.
    const std::size_t cells = std::clamp<std::size_t>(blocks_.size() * 2, 64, std::size_t(1) << 18);
    grid_.reset(domain_lo_, domain_hi_, cells);
    for (std::size_t i = 0; i < blocks_.size(); ++i) grid_.insert(i, blocks_[i].bsphere);
    grid_built_for_ = blocks_.size();
  }

  /// The blocks joint j may reach, in increasing index order.
  void find_candidates(std::size_t j, const PreparedJoint& pj) {
    candidates_.clear();
    if (!opt_.use_index) {
      for (std::size_t i = 0; i < blocks_.size(); ++i) candidates_.push_back(i);
      return;
    }
    if (stamp_.size() < blocks_.size()) stamp_.resize(blocks_.size(), 0);
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
  }

  /// Could the joint reach block b? Spheres only (eq. 17 and Fig. 18): conservative.
  bool may_reach(const PreparedJoint& pj, const Block& b) const {
    const Vec3 c = b.bsphere.head<3>();
    const double r = b.bsphere[3];
    if (std::abs(pj.plane.distance(c)) >= r + tol_.cut) return false;
    if (!pj.edges.empty() && (c - pj.centre).norm() >= r + pj.radius + tol_.cut) return false;
    return true;
  }

  void cut_by(std::size_t j) {
    const Joint& joint = js_.joints[j];
    const PreparedJoint pj = prepare(joint);
    find_candidates(j, pj);
    const std::size_t before = blocks_.size();
    std::size_t tested = 0, cut = 0;
    std::vector<Plane> edges_local;
    for (const std::size_t i : candidates_) {
      Block& b = blocks_[i];
      if (b.flags & kBoundary) continue;  // boundary blocks are never cut again
      if (opt_.use_index && !may_reach(pj, b)) continue;
      const Plane plane = to_local(pj.plane, b.origin);
      edges_local.clear();
      for (const Plane& e : pj.edges) edges_local.push_back(to_local(e, b.origin));
      const CutTest t = referee_.cut(b.faces, plane, edges_local);
      ++stats_.lps.cut_test;
      ++tested;
      if (t.status != LpStatus::optimal) {
        ++stats_.lps.failed;  // the paper's "self-defence": no new data structure
        continue;
      }
      if (!t.cuts) {
        if (joint.kind == JointKind::boundary && pj.edges.empty()) flag_side(b, joint, plane);
        continue;
      }
      if (split(i, j, plane)) ++cut;
    }
    stats_.pairs_skipped += before - tested;
    if (std::int64_t(blocks_.size()) > max_blocks())
      throw Error("/joints",
                  "the cut passed max_blocks = " + std::to_string(max_blocks()) +
                      " blocks at joint " + std::to_string(j) + " of " +
                      std::to_string(js_.joints.size()),
                  max_blocks_fix());
    if (cut == 0) ++stats_.joints_missing;
    if (joint.kind == JointKind::boundary && pj.edges.empty()) {
      // A persistent boundary joint: every block wholly on the keep side becomes a boundary
      // block, also those its plane passes far from.
      for (Block& b : blocks_) {
        if (b.flags & kBoundary) continue;
        const double dist = pj.plane.distance(b.bsphere.head<3>());
        if (std::abs(dist) >= b.bsphere[3] + tol_.cut && dist * joint.boundary_side > 0)
          b.flags |= kBoundary;
      }
    }
    if (blocks_.size() >= 2 * grid_built_for_ && opt_.use_index) rebuild_grid();
  }

  /// A block the plane does not cut lies on one side of it: its Chebyshev centre tells which.
  void flag_side(Block& b, const Joint& joint, const Plane& plane_local) {
    const ChebyshevBall c = chebyshev_ball(solver_, b.faces, tol_);
    ++stats_.lps.chebyshev;
    if (c.status != LpStatus::optimal) {
      ++stats_.lps.failed;
      return;
    }
    if (plane_local.distance(c.centre) * joint.boundary_side > 0) b.flags |= kBoundary;
  }

  /// Splits block i by the plane of joint j (block frame). False if undone.
  bool split(std::size_t i, std::size_t j, const Plane& plane) {
    const Joint& joint = js_.joints[j];
    Block below = blocks_[i];  // n . x <= d
    Block above = blocks_[i];  // -n . x <= -d
    below.faces.push_back({plane.normal, plane.d, std::int64_t(j)});
    above.faces.push_back({-plane.normal, -plane.d, std::int64_t(j)});
    if (!set_sphere(below) || !set_sphere(above)) return false;
    // An exempt joint (limits = false, e.g. a construction joint outlining an excavation)
    // keeps its cuts: its thin pieces cluster with their neighbours across it.
    if (limits() && joint.limits && (!within_limits(below) || !within_limits(above))) {
      ++stats_.splits_undone;
      return false;
    }
    if (joint.kind == JointKind::boundary) {
      (joint.boundary_side > 0 ? above : below).flags |= kBoundary;
    }
    ++stats_.splits;
    blocks_[i] = std::move(below);
    blocks_.push_back(std::move(above));
    if (opt_.use_index) {
      grid_.update(i, blocks_[i].bsphere);
      grid_.insert(blocks_.size() - 1, blocks_.back().bsphere);
    }
    return true;
  }

  /// Size and shape limits (eq. 18): inscribed diameter and bounding / inscribed radius.
  bool within_limits(Block& b) {
    const auto& o = js_.options;
    const ChebyshevBall c =
        referee_.limit_ball(b.faces, o.min_inscribed_diameter, o.max_aspect_ratio, b.bsphere[3]);
    ++stats_.lps.chebyshev;
    if (c.status != LpStatus::optimal) {
      ++stats_.lps.failed;
      return false;
    }
    b.inradius = c.radius;
    return slice::within_limits(c.radius, b.bsphere[3], o.min_inscribed_diameter,
                                o.max_aspect_ratio);
  }

  void finish() {
    // Chebyshev centre: the origin of every block, its inradius.
    std::vector<Face> core;
    for (std::size_t i = 0; i < blocks_.size(); ++i) {
      Block& b = blocks_[i];
      const ChebyshevBall c = chebyshev_ball(solver_, b.faces, tol_);
      ++stats_.lps.chebyshev;
      SLICE_ASSERT(c.status == LpStatus::optimal && c.radius > 0);
      b.inradius = c.radius;
      move_origin(b, unique_centre(b, c, core));
      if (progress_ && (i % 1024 == 0 || i + 1 == blocks_.size()))
        progress_("centres", i + 1, blocks_.size());
    }
    // Removal zones: blocks whose centre is inside are removed (kept in the file, flagged).
    for (Block& b : blocks_) {
      for (const Region& z : js_.zones) {
        const bool inside = std::all_of(z.planes.begin(), z.planes.end(),
                                        [&](const Plane& p) { return p.distance(b.origin) < 0; });
        if (inside) b.flags |= kRemoved;
      }
      stats_.boundary += (b.flags & kBoundary) ? 1 : 0;
      stats_.removed += (b.flags & kRemoved) ? 1 : 0;
    }
    if (js_.options.fixed_faces) mark_fixed();
    find_clusters();
  }

  // [options] fixed_faces: a block that reaches a named face of the domain's bounding box, to
  // within the geometry tolerance, is fixed. Its extents (six LPs) only when faces are named.
  void mark_fixed() {
    for (Block& b : blocks_) {
      const Extents e = extents(solver_, b.faces, tol_);
      stats_.lps.extents += 6;
      SLICE_ASSERT(e.status == LpStatus::optimal);  // failed LPs were solved again exactly
      const Vec3 lo = b.origin + e.min, hi = b.origin + e.max;
      for (int k = 0; k < 6; ++k) {
        if (!(js_.options.fixed_faces & (1u << k))) continue;
        const int axis = k / 2;
        const bool touches = k % 2 == 0 ? lo[axis] <= domain_lo_[axis] + tol_.geometry
                                        : hi[axis] >= domain_hi_[axis] - tol_.geometry;
        if (touches) b.flags |= kFixed;
      }
      stats_.fixed += (b.flags & kFixed) ? 1 : 0;
    }
  }

  /// The Chebyshev centre is not unique (a box longer than wide has a segment of them) and each
  /// backend may return another point of that set, which would make zone membership depend on
  /// the backend. The centre used is the middle of the extents of the "core": the points where
  /// a ball of radius (1 - kCoreShrink) r* fits. That is one point whatever the backend (up to
  /// LP accuracy), and on a segment or a centrally symmetric set of centres, its middle.
  Vec3 unique_centre(const Block& b, const ChebyshevBall& c, std::vector<Face>& core) {
    constexpr double kCoreShrink = 1e-6;
    core = b.faces;
    for (Face& f : core) f.d -= (1 - kCoreShrink) * c.radius;
    const Extents e = extents(solver_, core, tol_);
    stats_.lps.chebyshev += 6;
    if (e.status != LpStatus::optimal) {
      ++stats_.lps.failed;
      return c.centre;
    }
    return e.centre;
  }

  // Clusters (DESIGN section 4): blocks touching across a construction face with positive
  // contact area, found at the end: two blocks with opposite faces of the same construction
  // joint whose other faces leave a region of the shared plane with positive area. A removed
  // block joins no cluster, so nothing kept is joined through one (kept blocks at a slope face
  // would otherwise chain through the removed air blocks into one clump).
  void find_clusters() {
    std::vector<std::size_t> parent(blocks_.size());
    std::iota(parent.begin(), parent.end(), 0);
    const auto root = [&](std::size_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    struct Side {
      std::size_t block, face;
    };
    std::vector<std::vector<Side>> below(js_.joints.size()), above(js_.joints.size());
    for (std::size_t i = 0; i < blocks_.size(); ++i) {
      const Block& b = blocks_[i];
      if (b.flags & kRemoved) continue;
      for (std::size_t f = 0; f < b.faces.size(); ++f) {
        const auto j = b.faces[f].joint;
        if (j < 0 || js_.joints[std::size_t(j)].kind != JointKind::construction) continue;
        const bool is_below = b.faces[f].normal.dot(js_.joints[std::size_t(j)].plane.normal) > 0;
        (is_below ? below : above)[std::size_t(j)].push_back({i, f});
      }
    }
    std::vector<Face> merged;
    for (std::size_t j = 0; j < js_.joints.size(); ++j) {
      for (const Side& a : below[j]) {
        const Block& ba = blocks_[a.block];
        for (const Side& c : above[j]) {
          const Block& bc = blocks_[c.block];
          if (root(a.block) == root(c.block)) continue;
          const double gap = (ba.bsphere.head<3>() - bc.bsphere.head<3>()).norm();
          if (gap >= ba.bsphere[3] + bc.bsphere[3]) continue;
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
          const Plane plane = to_local(js_.joints[j].plane, ba.origin);
          const CutTest t = referee_.cut(merged, plane, {});
          ++stats_.lps.contact;
          if (t.status == LpStatus::optimal && t.cuts) parent[root(a.block)] = root(c.block);
        }
      }
    }
    // Cluster ids 0, 1, ... in order of each cluster's first block; -1 for blocks on their own.
    std::vector<std::size_t> size(blocks_.size(), 0);
    for (std::size_t i = 0; i < blocks_.size(); ++i) ++size[root(i)];
    std::vector<std::int64_t> id(blocks_.size(), -1);
    std::int64_t next = 0;
    for (std::size_t i = 0; i < blocks_.size(); ++i) {
      const std::size_t r = root(i);
      if (size[r] < 2) continue;
      if (id[r] < 0) id[r] = next++;
      blocks_[i].cluster = id[r];
    }
    stats_.clusters = std::size_t(next);
  }
};

/// A file's block must be a solid: bounded (six extents LPs) with an interior (a Chebyshev
/// radius of at least a quarter of the geometry tolerance). A crafted or damaged blocks.h5 fails
/// here, before a wrong pruning is written.
void check_solid(LpSolver& solver, std::span<const Face> faces, const Tolerances& tol,
                 std::size_t index) {
  const std::string where = "/blocks block " + std::to_string(index);
  const char* fix =
      "the file is damaged or was not made by slice-cut; regenerate it with slice-cut";
  const Extents e = extents(solver, faces, tol);
  if (e.status != LpStatus::optimal)
    throw Error(where, "its faces do not bound a solid (extents LP " + to_string(e.status) + ")",
                fix);
  // The slicer makes no child thinner than the cut tolerance (inscribed diameter >= tol.cut,
  // radius >= tol / 2); a quarter of the tolerance leaves room for rounding.
  const double min_radius = 0.25 * tol.geometry;
  const ChebyshevBall c = chebyshev_ball(solver, faces, tol);
  if (c.status != LpStatus::optimal || c.radius < min_radius)
    throw Error(
        where,
        "its faces do not bound a solid (" +
            (c.status == LpStatus::optimal ? "inscribed radius " + std::to_string(c.radius) +
                                                 " below " + std::to_string(min_radius)
                                           : "Chebyshev LP " + to_string(c.status)) +
            ")",
        fix);
}

}  // namespace

CutResult cut_blocks(const JointSystem& js, const CutOptions& opt, const Progress& progress) {
  return Cutter(js, opt, progress).run();
}

PruneStats prune_blocks(BlockSystem& bs, LpBackend backend, const Progress& progress,
                        bool certify) {
  const auto t0 = Clock::now();
  PruneStats st;
  const Tolerances tol =
      Tolerances::from_scale(bs.joints.length_scale, bs.joints.options.tolerance);
  Referee referee(backend, tol, certify);
  for (std::size_t i = 0; i < bs.blocks.size(); ++i) {
    auto& faces = bs.blocks[i].faces;
    st.faces_before += faces.size();
    // Against the faces kept so far: of two identical faces, one stays.
    for (std::size_t f = 0; f < faces.size();) {
      const FaceRedundancy r = referee.redundancy(faces, f);
      ++st.lps;
      if (r.redundant)
        faces.erase(faces.begin() + std::ptrdiff_t(f));
      else
        ++f;  // also when unbounded (the other faces leave the block open there): needed
    }
    st.faces_after += faces.size();
    check_solid(referee.solver(), faces, tol, i);
    if (progress && (i % 1024 == 0 || i + 1 == bs.blocks.size()))
      progress("prune", i + 1, bs.blocks.size());
  }
  bs.pruned = true;
  bs.geometry.reset();  // faces changed: vertices and loops no longer match
  st.decisions = referee.counts();
  st.failed = st.decisions.failed;
  st.seconds = seconds_since(t0);
  return st;
}

}  // namespace slice

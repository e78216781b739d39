#pragma once
// Joint-block pairs that geometry settles without the cut test's LP (src/slice/cut_reject.cpp;
// issue 29). A joint cuts a block only if some point of its polygon (of its plane, for a
// persistent joint) lies more than tol.cut inside every face of the block: the cut test's LP
// (lp.hpp, cut_test) finds s* < -tol.cut. Each test here but the last proves the opposite, that
// the polygon misses the block by more than `margin` (reject_margin), so that s* > 0 and every
// backend, far from its threshold, answers "no cut"; surely_cuts proves a cut, with a point
// deeper than tol.cut by the margin. A test that cannot prove its answer says false and the LP
// decides: the blocks are those the LPs alone make.
//
// Everything is in the block's frame: the faces, the box [lo, hi] that holds the block (its
// extents), the joint's plane and its polygon's corners (counter-clockwise about the plane's
// normal, or none for a persistent joint).
#include <cstdint>
#include <span>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/tolerance.hpp"

namespace slice {

/// Which test settled a pair (none: the cut LP decides).
enum class CutReject : std::uint8_t { none, plane, box, faces };

/// The margin the tests keep: the cut tolerance, and 64 rounding errors of the coordinates
/// involved (up to `magnitude` in the global frame), which moving planes and corners between
/// the global and the block frame may cost.
double reject_margin(const Tolerances& tol, double magnitude);

/// The plane misses the box [lo, hi] grown by `margin`: no corner of the box is on its side.
bool plane_misses_box(const Plane& plane, const Vec3& lo, const Vec3& hi, double margin);

/// The polygon's own bounding box misses the box [lo, hi] grown by `margin` (no polygon: false).
bool polygon_misses_box(std::span<const Vec3> polygon, const Vec3& lo, const Vec3& hi,
                        double margin);

/// Buffers faces_miss_polygon reuses between calls (no allocation once grown).
struct ClipScratch {
  std::vector<Vec3> a, b;
  std::vector<double> dist;
  /// `a` holds the region (polygon, or plane square) clipped by every face grown by the margin:
  /// set by faces_miss_polygon when it answers false, cleared by reject_cut, used (and cleared)
  /// by surely_cuts, which then need not clip again.
  bool clipped = false;
};

/// The polygon (a persistent joint: its plane's part inside the box [lo, hi]) clipped by every
/// face grown by `margin` is empty (Sutherland-Hodgman): no point of it is inside the block.
bool faces_miss_polygon(std::span<const Face> faces, const Plane& plane,
                        std::span<const Vec3> polygon, const Vec3& lo, const Vec3& hi,
                        double margin, ClipScratch& scratch);

/// The converse, which settles a pair as cut (issue 29: nearly every pair past the tests above
/// is cut): a point of the polygon (persistent: of the plane) lies more than depth + margin
/// inside every face of the block and every edge of the polygon (`edges`, in-plane half-planes
/// as the cut LP takes them). The LP's s* is then below -depth - margin; with depth = tol.cut,
/// every backend answers "cut", and --certify, whose band is tol.cut, has nothing to decide
/// again. The point tried is the mean of the corners of the region clipped by the faces grown
/// by the margin (scratch.a if scratch.clipped, as reject_cut's faces test left it); false is no
/// answer (the LP decides).
bool surely_cuts(std::span<const Face> faces, const Plane& plane, std::span<const Vec3> polygon,
                 std::span<const Plane> edges, const Vec3& lo, const Vec3& hi, double depth,
                 double margin, ClipScratch& scratch);

/// Some of `points` lie below the plane and some above, farther than `margin`: if they are
/// points of the block, the plane meets it, and faces_miss_polygon cannot settle a persistent
/// joint (for a polygon this says nothing).
bool plane_splits_points(const Plane& plane, std::span<const Vec3> points, double margin);

/// A size-limit shortcut of the split itself (issue 29): the smaller of the widths, across the
/// plane, of the two pieces a block (its faces) splits into, measured to the block's faces
/// parallel to the plane (normals equal to +-plane.normal, bit for bit: joints of one set);
/// infinity without such a face. A piece's inscribed diameter is at most its width.
double parallel_slab_width(std::span<const Face> faces, const Plane& plane);

/// The prune's shortcut: face `f` surely touches its block with positive area, so the
/// redundancy LP (eq. 8) could only keep it. Some point p of the face's plane lies inside every
/// other face (by at least the prune tolerance), and from p the block goes on past the plane
/// along the normal, inside the others, for more than three prune tolerances: the LP's value is
/// then at least that far beyond d, outside the band in which a decision is checked again. The
/// first p tried is the foot of the block's origin; while another face cuts it off, p moves in
/// the plane away from the face that cuts it off most (a few steps). False is no answer (the LP
/// decides).
bool surely_irredundant(std::span<const Face> faces, std::size_t f, const Tolerances& tol);

/// A ball in a block's frame; radius <= 0: none.
struct Ball {
  Vec3 centre = Vec3::Zero();
  double radius = 0;
};

/// Another size-limit shortcut: the largest ball inside both `ball` and the half-space
/// n . x <= d (the half of a ball a plane cuts holds a ball of diameter r + its centre's depth),
/// its radius less `shrink`. If `ball` lies inside a block, the result lies inside the piece of
/// the block on that side, and bounds the piece's inscribed radius from below. Radius <= 0: none.
Ball ball_in_half_space(const Ball& ball, const Plane& half, double shrink);

/// The tests in order of cost: the plane against the box, the polygon's box against the box, the
/// polygon against the faces (for a persistent joint, unless its plane splits `inside`, points
/// of the block such as its extremes). The first that settles the pair, or none.
CutReject reject_cut(std::span<const Face> faces, const Plane& plane, std::span<const Vec3> polygon,
                     const Vec3& lo, const Vec3& hi, std::span<const Vec3> inside, double margin,
                     ClipScratch& scratch);

}  // namespace slice

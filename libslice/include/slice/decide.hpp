#pragma once
// No LP failure decides anything (issue 12). Every decision of the slicer (cut or not, a face
// redundant or not, a child within the size and shape limits or not) goes through a Referee:
//   - an LP the backend fails on is solved again by the exact backend (counted: `resolved`);
//   - a decision whose value lies within a band of its threshold is decided again exactly
//     (counted: `checked`, and `changed` if the exact answer differs). The band is a few
//     hundred rounding errors of the domain's scale by default (the answers a double-precision
//     solver cannot tell from the threshold), and the whole tolerance with `certify`.
// With the exact backend itself there is nothing to re-decide.
#include <memory>
#include <span>

#include "slice/lp.hpp"

namespace slice {

struct DecisionCounts {
  std::size_t resolved = 0;  // LPs the backend failed on, solved exactly
  std::size_t failed = 0;    // LPs the exact backend failed on too (never seen; a bug)
  std::size_t checked = 0;   // decisions within the band, decided again exactly
  std::size_t changed = 0;   // ... whose exact answer differed
  DecisionCounts& operator+=(const DecisionCounts& o);
};

/// The size and shape limits (eq. 18): 2 r >= min_diameter and R <= max_aspect r (0: no limit).
inline bool within_limits(double inradius, double bounding_radius, double min_diameter,
                          double max_aspect) {
  return !(min_diameter > 0 && 2 * inradius < min_diameter) &&
         !(max_aspect > 0 && bounding_radius > max_aspect * inradius);
}

class Referee {
 public:
  Referee(LpBackend backend, const Tolerances& tol, bool certify);
  ~Referee();
  Referee(const Referee&) = delete;
  Referee& operator=(const Referee&) = delete;

  /// The backend, with failed LPs solved again exactly: for LPs that decide nothing by a
  /// threshold (extents, Chebyshev centres).
  LpSolver& solver();
  const DecisionCounts& counts() const;

  /// cut_test, re-decided exactly if s* lies within the band of -tol.cut.
  CutTest cut(std::span<const Face> faces, const Plane& plane, std::span<const Plane> edges);
  /// face_redundancy, re-decided exactly if the value lies within the band of d + tol.prune.
  FaceRedundancy redundancy(std::span<const Face> faces, std::size_t index);
  /// chebyshev_ball for the limits: re-solved exactly if 2r lies within the band of
  /// `min_diameter` or R / r within the band of `max_aspect` (R: the bounding radius).
  ChebyshevBall limit_ball(std::span<const Face> faces, double min_diameter, double max_aspect,
                           double bounding_radius);
  /// The band about a limit (a diameter, or R / r times r) within which limit_ball decides
  /// again exactly; 0 with the exact backend, which decides nothing again.
  double limit_band(double limit) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slice

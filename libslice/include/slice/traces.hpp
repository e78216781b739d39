#pragma once
// Traces of joints on a mapping window (docs/scenes.md, [[sets]] `mapping`): what a geologist
// mapping an outcrop or a tunnel wall sees of a set, so that a set's size distribution can be
// calibrated against mapped trace lengths. A trace is the intersection of a joint (its polygon,
// or its whole plane if persistent) with the mapping plane, clipped to the window's rectangle.
#include <optional>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/scene.hpp"

namespace slice {

/// One trace in the window's (u, v) frame about its centre (u along the mapping plane's strike,
/// v up its dip line: orientation.hpp). An end is censored when the joint goes on beyond the
/// window's border there (always, for a persistent joint).
struct Trace {
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();
  bool a_censored = false, b_censored = false;
  double length() const { return (b - a).norm(); }
};

/// The trace of joint j on window w; nothing if the joint misses the window, lies parallel to
/// its plane, or leaves a trace no longer than `tol` (an absolute length).
std::optional<Trace> trace_on(const Joint& j, const TraceMapping& w, double tol);

/// The statistics of the traces of `joints` on window w (TraceStats).
TraceStats trace_stats(const std::vector<const Joint*>& joints, const TraceMapping& w, double tol);

}  // namespace slice

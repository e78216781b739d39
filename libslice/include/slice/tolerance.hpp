#pragma once
// Every tolerance of a run, from one length scale (DESIGN section 10).
namespace slice {

struct Tolerances {
  double length_scale = 1;  // L: the domain's bounding radius [scene unit]
  double cut = 1e-9;        // a cutting plane passes at least this far inside every face
  double prune = 1e-9;      // a face is redundant if max c . x <= e + prune
  double geometry = 1e-9;   // points closer than this to a plane are on it
  static Tolerances from_scale(double L, double rel) { return {L, rel * L, rel * L, rel * L}; }
};

}  // namespace slice

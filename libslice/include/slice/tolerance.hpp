#pragma once
// Every tolerance of a run, from one length scale (docs/design.md, "Tolerances and the length
// scale").
namespace slice {

struct Tolerances {
  double length_scale = 1;  // L: the domain's bounding radius [scene unit]
  double cut = 1e-9;        // a cutting plane passes at least this far inside every face
  double prune = 1e-9;      // a face is redundant if max c . x <= e + prune
  double geometry = 1e-9;   // points closer than this to a plane are on it
  /// The space the LPs work in: 3, or 2 for a section in (x, z) (docs/2d.md), where every face
  /// normal has y = 0, a polygon edge normal to y is left out, and the LPs have two variables
  /// (x, z) instead of three. Part of the tolerances because every LP takes them.
  int dimension = 3;
  static Tolerances from_scale(double L, double rel, int dimension = 3) {
    return {L, rel * L, rel * L, rel * L, dimension};
  }
};

}  // namespace slice

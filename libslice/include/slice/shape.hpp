#pragma once
// Block shape factors alpha and beta, and the six shape classes of the block shape diagram
// (Kalenchuk, Diederichs & McKinnon 2006, "Characterizing block geometry in jointed rockmasses",
// IJRMMS 43:1212-1225). Implemented in libslice/src/geometry/shape.cpp; docs/block-shape.md says
// where each definition was found and what could not be verified.
//
//   alpha = A * lbar / (7.7 V)   A the block's surface area, V its volume, lbar the mean length
//                                of the chords between all pairs of its vertices. 7.7 makes a
//                                cube's alpha 1 (6 * 1.28207 / 7.7 = 0.99902); it grows as the
//                                block flattens (shortening of the minor axis).
//   beta  = elongation index     of the modified method's public tool (MBSCT): from each end of
//                                the longest chord, the chords to the vertices that are at least
//                                as long as the median chord; the smallest squared cosine of
//                                the angle between two of them; the harmonic mean of both ends.
//                                0 .. 1, near 1 for a rod (elongation of the major axis).
// Both are stated in jsidhu45/Modified-block-shape-classification, MBSCT.py. Kalenchuk's own
// beta (BlockShape::beta_k) is computed beside it, as UnBlocks-gen's paper states it
// (docs/block-shape.md).
#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "slice/geometry.hpp"

namespace slice {

/// The classes of the block shape diagram: cubic, platy-cubic, platy, cubic-elongate,
/// elongate-platy, elongate. `none`: beta undefined (no end of the longest chord has two long
/// chords, a few thin tetrahedra), counted apart so that class volumes add up to the total.
enum class ShapeClass { C, PC, P, CE, EP, E, none };
inline constexpr std::array<ShapeClass, 7> kShapeClasses{
    ShapeClass::C,  ShapeClass::PC, ShapeClass::P,   ShapeClass::CE,
    ShapeClass::EP, ShapeClass::E,  ShapeClass::none};
const char* to_string(ShapeClass c);  // "C", "PC", ..., "none"

/// The class boundaries (MBSCT): beta > 0.75 E; 0.3 < beta <= 0.75: CE if alpha <= 3, else EP;
/// beta <= 0.3: C if alpha <= 2, PC if alpha <= 5, else P.
ShapeClass shape_class(double alpha, double beta);

/// The classes of UnBlocks-gen's diagram (install/plotTools.py, BlockShapeDistribution), on
/// Kalenchuk's beta (BlockShape::beta_k, 1 .. 10): beta_k >= 7 E; 4 <= beta_k < 7: CE if
/// alpha < 3, else EP; beta_k < 4: C if alpha < 2, PC if alpha < 5, else P. `none` if either is
/// NaN (docs/block-shape.md).
ShapeClass kalenchuk_class(double alpha, double beta_k);

struct BlockShape {
  double alpha = 0;
  double beta = 0;  // MBSCT's elongation index, 0 .. 1; NaN when undefined (class none)
  ShapeClass shape = ShapeClass::none;  // from alpha and the MBSCT beta
  // Kalenchuk's beta as UnBlocks-gen's paper states it (Rasmussen 2020, SoftwareX 12:100577,
  // eq. 5): 10 [sum (a . b)^2 / sum |a|^2 |b|^2]^2 over all pairs of the chords a, b longer than
  // the median chord, a = b included; 10/9 for a cube (or any isotropic set of long chords) up to
  // 10 for a rod. NaN when no chord is longer than the median (a regular tetrahedron).
  double beta_k = 0;
  ShapeClass shape_k = ShapeClass::none;  // kalenchuk_class(alpha, beta_k)
};

/// The shape of one convex polyhedron from its vertices (any frame: only differences count),
/// surface area and volume. Throws Error (naming `where`) for fewer than 4 vertices, a volume or
/// area that is not positive and finite, or a non-finite vertex. Ties (the longest chord, chords
/// equal to the median) are decided with a relative tolerance of 1e-9 of the longest chord, so
/// the result does not depend on the vertices' order, position or orientation.
BlockShape block_shape(std::span<const Vec3> vertices, double surface_area, double volume,
                       const std::string& where = "block");

/// The shape of every block of a block system's /geometry (blocks: its blocks, for the face
/// counts). Throws Error for a section (dimension 2: the factors are defined for polyhedra) and
/// for a block block_shape refuses, naming the block.
std::vector<BlockShape> block_shapes(const std::vector<Block>& blocks, const Geometry& g,
                                     int dimension = 3);

/// Counts and volumes by class (index: position in kShapeClasses), of the blocks `keep` selects
/// (all if empty); by BlockShape::shape (MBSCT's classes), or by BlockShape::shape_k
/// (UnBlocks-gen's classes on Kalenchuk's beta) if `kalenchuk`.
struct ShapeSummary {
  std::array<std::size_t, 7> count{};
  std::array<double, 7> volume{};
};
ShapeSummary summarise_shapes(const std::vector<BlockShape>& shapes,
                              const std::vector<double>& volume, const std::vector<bool>& keep = {},
                              bool kalenchuk = false);

}  // namespace slice

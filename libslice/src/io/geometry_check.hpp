#pragma once
// libslice/src/io/geometry_check.cpp: the values of /geometry against each other, for its
// reader and writers (geometry_file.cpp, issue 25 item 4). geometry_file.cpp checks shapes,
// indices, finite values and that the vertices lie on their faces; this checks what those leave
// open: loops, areas, volume, centroid and inertia, in O(size) (a reader runs it on
// million-block files).
#include <cstddef>
#include <cstdint>
#include <string>

#include "slice/geometry.hpp"

namespace slice {

// Where the geometry of a run of blocks starts in /geometry (its rows and offsets there): a
// Geometry of a run counts from 0, messages name the file's rows.
struct GeometryBase {
  std::size_t block = 0, face = 0;
  std::int64_t vertex = 0, face_vertex = 0;
  /// Past a run of `blocks` blocks with these many faces, vertices and loop entries.
  void advance(std::size_t blocks, std::size_t faces, std::size_t vertices,
               std::size_t face_vertices) {
    block += blocks;
    face += faces;
    vertex += std::int64_t(vertices);
    face_vertex += std::int64_t(face_vertices);
  }
};

/// What is wrong with the values of block b of the run `g` (the file's block base.block + b, its
/// first face the run's face row `face_row`), or "" if nothing, within the length tolerance
/// `tol` (geometry_file.cpp's vertex_tolerance): each loop visits a vertex once and runs
/// counter-clockwise seen from outside (right-handed about the face normal) and encloses the
/// face's stored area; the loops close; the stored volume, centroid and inertia are the ones
/// they give; the centroid lies inside the block. `section`: a 2-D file (docs/2d.md), whose
/// vertices and centroids have y = 0 and whose loops are edges (start, end). The shapes and
/// indices of `g` must have been checked.
std::string geometry_value_problem(const Geometry& g, const Block& blk, std::size_t b,
                                   std::size_t face_row, const GeometryBase& base, double tol,
                                   bool section);

}  // namespace slice

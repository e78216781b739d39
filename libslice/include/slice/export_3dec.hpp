#pragma once
// 3DEC models: the rigid blocks in 3DEC's ASCII grid format (".3dgrid", read by 3DEC's
// `block import filename "model.3dgrid"`), and a short command file that imports them.
//
// The grid file, as 3DEC's `block import` documents it: `*` comment lines; `G id x y z`
// gridpoints; `F id g1 g2 g3 ...` faces; `B id zone-id F f1 f2 ...` rigid blocks; `JS id b1-b2
// ...` joint-set IDs of block contacts. Here:
//   - one block per block of blocks.h5 that is not removed; its ID is its row in blocks.h5 + 1
//     (3DEC IDs are positive), so gaps mark the removed blocks; zone-id 1;
//   - every block has its own gridpoints and faces (3DEC creates a vertex for every point);
//     IDs count up from 1 in block order;
//   - a face's gridpoints go clockwise seen from outside the block (the right-hand rule gives
//     the inward normal): UDEC takes a block's corners clockwise, and the one public 3DEC
//     exporter at hand (BlockResearchGroup/compas_3dec's example geometry.dat) lists 3DEC
//     polyhedron faces so. /geometry's loops go the other way and are written backwards. No
//     3DEC was at hand to confirm it;
//   - JS lines: two kept blocks with faces on the same rock or boundary joint, facing each other
//     and overlapping with positive area, are a contact of that joint's set: JS id = set + 1,
//     and (number of sets + 1) for the scene's single [[joints]]; construction joints and domain
//     faces give none;
//   - numbers in their shortest exact form: the same blocks give the same bytes.
// The command file (".dat") imports the grid, puts boundary and fixed blocks in group
// "boundary" (fixed) and the blocks of cluster c in group "cluster-c", by ID ranges.
#include <cstddef>
#include <filesystem>

#include "slice/h5io.hpp"

namespace slice {

struct ThreeDecStats {
  std::size_t blocks = 0, faces = 0, gridpoints = 0;
  std::size_t contacts = 0;  // block pairs on JS lines
  std::size_t removed = 0;   // blocks left out
  std::size_t fixed = 0;     // in group "boundary"
  std::size_t clusters = 0;  // groups "cluster-c"
};

/// Writes `grid` and `commands` atomically (each through "<file>.partial"). Needs bs.geometry;
/// throws Error if it is missing, for a 2-D section (dimension 2: no 3DEC polyhedra), or if a
/// file cannot be written. The command file names the grid by its file name if both are in
/// one directory, else by its absolute path.
ThreeDecStats write_3dec(const std::filesystem::path& grid, const std::filesystem::path& commands,
                         const BlockSystem& bs);

}  // namespace slice

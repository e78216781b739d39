#pragma once
// UDEC models of a 2-D section (docs/2d.md, "UDEC"): the kept blocks of a section as UDEC 7
// commands, one `block create polygon x1,y1 x2,y2 ...` per block, UDEC's (x, y) being the
// section's (x, z). As Itasca documents the command (docs/2d.md cites the pages): the corners in
// clockwise order; /geometry's polygons go counter-clockwise and are written backwards. Block
// order: rows of blocks.h5, removed blocks left out; each block's row, and boundary, fixed and
// cluster marks, in a comment line before it. Scene text (its name) appears only in comment
// lines with control characters escaped: no text of the scene adds a line. Numbers in their
// shortest exact form: the same blocks give the same bytes.
#include <cstddef>
#include <filesystem>

#include "slice/h5io.hpp"

namespace slice {

struct UdecStats {
  std::size_t blocks = 0, vertices = 0;
  std::size_t removed = 0;  // blocks left out
};

/// Writes `out` atomically (through "<out>.partial"). Needs bs.geometry of a 2-D section; throws
/// Error naming `out` for a 3-D file (dimension 3), a file without /geometry, or one that cannot
/// be written.
UdecStats write_udec(const std::filesystem::path& out, const BlockSystem& bs);

}  // namespace slice

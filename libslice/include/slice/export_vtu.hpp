#pragma once
// VTK XML unstructured grids for ParaView (docs/design.md, "Exports") in VTK 9's file format:
// each array's data inline, base64 (well-formed XML: raw appended data stops ParaView 5.11 under
// Debian's current expat), compressed (LZ4 by default) in blocks of 32 KiB, 64-bit headers.
// Written as they are made, a chunk at a time, by the library's own writer (VTK's writer built a
// second copy of the grid: 1.85 GB at 964,156 blocks); VTK's reader and ParaView read them. Outputs
// are atomic ("<out>.partial", renamed when complete) and deterministic (the same blocks give the
// same bytes).
#include <cstddef>
#include <filesystem>
#include <string>

#include "slice/h5io.hpp"

namespace slice {

/// How the data of a VTU file is compressed. ParaView reads all three. At 964,156 blocks: lz4
/// 345 MB, zlib 210 MB, none 513 MB (base64); slice-export on 2 threads 3.4 s, 6.6 s, 2.3 s.
enum class VtuCompressor { lz4, zlib, none };
/// "lz4", "zlib", "none"; anything else throws Error naming `option`.
VtuCompressor parse_vtu_compressor(const std::string& text, const std::string& option);

/// The type of a VTU's cell arrays (connectivity, offsets and the polyhedra's faces and
/// faceoffsets): Int32 where every value fits (VTK reads either into its id type; half the
/// bytes of Int64), or always Int64.
enum class VtuIds { narrowest, int64 };

struct VtuStats {
  std::size_t cells = 0;  // blocks or joint polygons written
  std::size_t points = 0;
  std::size_t skipped = 0;  // removed blocks, or joints that do not meet the domain
};

/// blocks.vtu: one VTK_POLYHEDRON cell per block that is not removed, from /geometry (faces
/// counter-clockwise from outside, as VTK wants them; each block has its own points). Cell data:
/// block_id (int64: the row in blocks.h5), volume, inradius, cluster (int64, -1 = none),
/// boundary (uint8, 0/1), aspect_ratio (bounding-sphere radius / inscribed radius). VTK has no
/// face data for polyhedron cells, so face-level values stay in the HDF5 file. A section's blocks
/// (dimension 2, docs/2d.md) are VTK_POLYGON cells instead, their points in the polygon's
/// order (y = 0), with the same cell data and no face streams. Throws Error if
/// the system has no geometry (run slice-vertices) or the file cannot be written. `threads`:
/// for the compression (0: all cores); the bytes are the same for every count. `ids`: the type
/// of the cell arrays.
VtuStats write_blocks_vtu(const std::filesystem::path& out, const BlockSystem& bs,
                          VtuCompressor compressor = VtuCompressor::lz4, int threads = 0,
                          VtuIds ids = VtuIds::narrowest);

/// write_blocks_vtu of the blocks file `in` (geom.h5), the same bytes, without holding its
/// /geometry: it is checked run by run as read_blocks checks it, and its vertices and loops are
/// read again as the file is written (at 980,152 blocks slice-export peaks at 0.6 GB, not 1.0).
/// Refuses what read_blocks refuses, with the same Error, and a file without /geometry.
/// `joints`: if given, set to the file's joints.
VtuStats export_blocks_vtu(const std::filesystem::path& in, const std::filesystem::path& out,
                           VtuCompressor compressor = VtuCompressor::lz4, int threads = 0,
                           VtuIds ids = VtuIds::narrowest, JointSystem* joints = nullptr);

/// joints.vtu: one VTK_POLYGON cell per joint, its part inside the domain (a persistent joint is
/// its plane clipped to the domain; a polygon joint its polygon clipped to the domain). Joints
/// that do not meet the domain are left out. Cell data: joint_id (int64: the row in /joints),
/// set (int32, -1 = deterministic), kind (uint8: 0 rock, 1 construction, 2 boundary),
/// persistent (uint8), friction_angle [degrees], cohesion [Pa]. In a section (dimension 2)
/// each joint is a VTK_LINE instead: its line (persistent) or its segment between its
/// rectangle's ends, clipped to the domain, at y = 0.
VtuStats write_joints_vtu(const std::filesystem::path& out, const JointSystem& js,
                          VtuCompressor compressor = VtuCompressor::lz4);

}  // namespace slice

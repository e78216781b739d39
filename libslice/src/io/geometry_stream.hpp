#pragma once
// A geom.h5 read for an export that does not hold its /geometry (geometry_stream.cpp; the VTU
// export, export_vtu.cpp): /blocks whole, as read_blocks reads it, and /geometry run by run,
// each run checked as read_blocks checks it, handed over and dropped; its vertices and loops are
// read again, by rows, from the file kept open. At 980,152 blocks slice-export held 1.0 GB with
// read_blocks, 0.6 GB this way.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "geometry_check.hpp"
#include "slice/geometry.hpp"
#include "slice/h5io.hpp"

namespace slice {

class GeometryStream {
 public:
  /// The geometry of the n blocks from base.block on of `bs`, counting from 0 (GeometryBase).
  using Run = std::function<void(const BlockSystem& bs, const Geometry& run,
                                 const GeometryBase& base, std::size_t n)>;

  /// Opens `in` and reads it: each run of /geometry is checked, then handed to `run` (in block
  /// order, one at a time, on any thread) and dropped. Null, with nothing refused, where the file
  /// has no /geometry, has /stability or /contacts (read whole), or where anything turns up that
  /// read_blocks might refuse (a read or check error, or a run that fails its check with the
  /// tolerance of its own vertices, which the file's may pass): read_blocks then decides, and words
  /// the error.
  static std::unique_ptr<GeometryStream> open(const std::filesystem::path& in, const Run& run);
  ~GeometryStream();
  GeometryStream(const GeometryStream&) = delete;
  GeometryStream& operator=(const GeometryStream&) = delete;

  /// The joints and blocks, checked; no geometry.
  const BlockSystem& blocks() const;
  /// /geometry's offsets: block b's vertices are rows [vertex_offset[b], vertex_offset[b + 1]),
  /// face f's loop rows [face_vertex_offset[f], face_vertex_offset[f + 1]).
  const std::vector<std::int64_t>& vertex_offset() const;
  const std::vector<std::int64_t>& face_vertex_offset() const;
  /// Rows [lo, hi) of /geometry/vertices and of /geometry/face_vertices into `out` (resized).
  void read_vertices(std::size_t lo, std::size_t hi, std::vector<Vec3>& out) const;
  void read_face_vertices(std::size_t lo, std::size_t hi, std::vector<std::int64_t>& out) const;

 private:
  struct Impl;
  explicit GeometryStream(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace slice

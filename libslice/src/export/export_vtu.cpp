#include "slice/export_vtu.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "../io/geometry_stream.hpp"
#include "../threads.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/output.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"
#include "slice/vertices.hpp"
#include "vtu_file.hpp"

namespace slice {
namespace {

constexpr std::uint8_t kVtkLine = 3, kVtkPolygon = 7, kVtkPolyhedron = 42;  // VTK's cell types
constexpr std::size_t kChunkBytes = 1 << 20;  // values gathered before they go to the file

/// Exact text of a value for RangeMin / RangeMax.
std::string text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  vtu::ArraySpec spec(const char* type, std::string name) const {
    if (lo > hi) return {type, std::move(name)};
    return {type, std::move(name), 1, false, text(lo), text(hi)};
  }
};

/// Streams one array of `count` values of T: emit(k, out) appends the values of item k (a kept
/// block or joint) to out, for k in order; they go to the file a chunk at a time.
template <class T, class Emit>
void stream(vtu::File& f, std::size_t items, std::size_t count, Emit emit) {
  f.begin_array(count * sizeof(T));
  std::vector<T> buf;
  buf.reserve(kChunkBytes / sizeof(T) + 64);
  std::size_t sent = 0;
  for (std::size_t k = 0; k < items; ++k) {
    emit(k, buf);
    if (buf.size() * sizeof(T) >= kChunkBytes) {
      f.put(buf.data(), buf.size() * sizeof(T));
      sent += buf.size();
      buf.clear();
    }
  }
  f.put(buf.data(), buf.size() * sizeof(T));
  sent += buf.size();
  SLICE_ASSERT(sent == count);
  f.end_array();
}

}  // namespace

VtuCompressor parse_vtu_compressor(const std::string& text, const std::string& option) {
  if (text == "lz4") return VtuCompressor::lz4;
  if (text == "zlib") return VtuCompressor::zlib;
  if (text == "none") return VtuCompressor::none;
  throw Error(option, "is \"" + text + "\"", "use lz4 (fast), zlib (small) or none");
}

namespace {

/// blocks.vtu of the blocks of `bs` and the geometry `src` gives (MemorySource, FileSource):
/// their volumes, their vertices and loops by rows of /geometry, asked for in increasing order.
/// `points2`: the range of the squared magnitudes of the vertices of the blocks not removed.
template <class Source>
VtuStats write_vtu(const std::filesystem::path& out, const BlockSystem& bs, Source& src,
                   const Range& points2, VtuCompressor compressor, int threads, VtuIds ids) {
  const std::vector<std::int64_t>& vertex_offset = src.vertex_offset();
  const std::vector<std::int64_t>& face_vertex_offset = src.face_vertex_offset();
  // A section's block (docs/2d.md) is a polygon: its vertices are the polygon's points in order
  // (counter-clockwise in (x, z)), one VTK_POLYGON with no face stream.
  const bool section = bs.joints.dimension == 2;
  VtuStats st;
  // The kept blocks, their first face row, and the sizes and ranges the header states.
  std::vector<std::size_t> kept, face_row;
  std::size_t points = 0, conn = 0, stream_len = 0, row = 0;
  Range r_id, r_volume, r_inradius, r_cluster, r_boundary, r_fixed, r_aspect;
  const auto aspect = [](const Block& b) {
    return b.inradius > 0 ? b.bsphere[3] / b.inradius : 0.0;
  };
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    const std::size_t nf = blk.faces.size();
    if (blk.flags & kRemoved) {
      row += nf;
      ++st.skipped;
      continue;
    }
    kept.push_back(b);
    face_row.push_back(row);
    const auto nv = std::size_t(vertex_offset[b + 1] - vertex_offset[b]);
    points += nv;
    conn += nv;
    stream_len += 1 + nf + std::size_t(face_vertex_offset[row + nf] - face_vertex_offset[row]);
    row += nf;
    r_id.add(double(b));
    r_volume.add(src.volume(b));
    r_inradius.add(blk.inradius);
    r_cluster.add(double(blk.cluster));
    r_boundary.add((blk.flags & kBoundary) ? 1 : 0);
    r_fixed.add(is_fixed(blk) ? 1 : 0);
    r_aspect.add(aspect(blk));
  }
  const std::size_t cells = kept.size();
  // /stability (slice-stability) as cell data: ParaView colours blocks by factor of safety. A
  // block that cannot move (fos +inf in the file) has fos NaN here, ParaView's "no value" colour,
  // so that the colour scale spans the blocks that can.
  const StabilityResult* stab = bs.stability ? &bs.stability->result : nullptr;
  const auto vtu_fos = [&](std::size_t b) {
    const double v = stab->fos[b];
    return std::isinf(v) ? std::numeric_limits<double>::quiet_NaN() : v;
  };
  Range r_removable, r_mode, r_fos, r_generation, r_group;
  if (stab)
    for (const std::size_t b : kept) {
      r_removable.add(stab->removable[b]);
      r_mode.add(stab->mode[b]);
      r_fos.add(vtu_fos(b));
      r_generation.add(stab->generation[b]);
      r_group.add(double(stab->group[b]));
    }
  std::vector<vtu::ArraySpec> cell_data = {
      r_id.spec("Int64", "block_id"),          r_volume.spec("Float64", "volume"),
      r_inradius.spec("Float64", "inradius"),  r_cluster.spec("Int64", "cluster"),
      r_boundary.spec("UInt8", "boundary"),    r_fixed.spec("UInt8", "fixed"),
      r_aspect.spec("Float64", "aspect_ratio")};
  if (stab) {
    cell_data.push_back(r_removable.spec("UInt8", "removable"));
    cell_data.push_back(r_mode.spec("UInt8", "mode"));
    cell_data.push_back(r_fos.spec("Float64", "fos"));
    cell_data.push_back({"Float64", "direction", 3});
    cell_data.push_back(r_generation.spec("Int32", "generation"));
    cell_data.push_back(r_group.spec("Int64", "group"));
  }
  // The points' magnitudes: the roots of the extreme squares (the root is monotonic: the same
  // numbers as the extremes of the roots, one root each instead of one per point).
  Range r_points;
  if (points2.lo <= points2.hi) r_points = {std::sqrt(points2.lo), std::sqrt(points2.hi)};

  // The cells' point numbers and offsets as Int32 where every one fits (VtuIds): half the bytes
  // to compress, write and read of the larger arrays.
  const bool narrow =
      ids == VtuIds::narrowest &&
      std::max({points, conn, stream_len}) <= std::size_t(std::numeric_limits<std::int32_t>::max());
  const char* id_type = narrow ? "Int32" : "Int64";

  PartialFile part(out);
  vtu::File f(part.path(), out.string(), compressor);
  f.header(points, cells,
           {{"CellData", cell_data},
            {"Points", {[&] {
               auto a = r_points.spec("Float64", "Points");
               a.components = 3;
               return a;
             }()}},
            {"Cells",
             [&] {
               std::vector<vtu::ArraySpec> a = {
                   {id_type, "connectivity"}, {id_type, "offsets"}, {"UInt8", "types"}};
               if (!section) {
                 a.push_back({id_type, "faces", 1, true});
                 a.push_back({id_type, "faceoffsets", 1, true});
               }
               return a;
             }()}},
           "volume");
  tbb::task_arena arena(thread_count(threads));
  arena.execute([&] {
    const auto block = [&](std::size_t k) -> const Block& { return bs.blocks[kept[k]]; };
    stream<std::int64_t>(f, cells, cells,
                         [&](std::size_t k, auto& o) { o.push_back(std::int64_t(kept[k])); });
    stream<double>(f, cells, cells,
                   [&](std::size_t k, auto& o) { o.push_back(src.volume(kept[k])); });
    stream<double>(f, cells, cells,
                   [&](std::size_t k, auto& o) { o.push_back(block(k).inradius); });
    stream<std::int64_t>(f, cells, cells,
                         [&](std::size_t k, auto& o) { o.push_back(block(k).cluster); });
    stream<std::uint8_t>(f, cells, cells, [&](std::size_t k, auto& o) {
      o.push_back((block(k).flags & kBoundary) ? 1 : 0);
    });
    stream<std::uint8_t>(f, cells, cells,
                         [&](std::size_t k, auto& o) { o.push_back(is_fixed(block(k)) ? 1 : 0); });
    stream<double>(f, cells, cells, [&](std::size_t k, auto& o) { o.push_back(aspect(block(k))); });
    if (stab) {
      stream<std::uint8_t>(f, cells, cells,
                           [&](std::size_t k, auto& o) { o.push_back(stab->removable[kept[k]]); });
      stream<std::uint8_t>(f, cells, cells,
                           [&](std::size_t k, auto& o) { o.push_back(stab->mode[kept[k]]); });
      stream<double>(f, cells, cells,
                     [&](std::size_t k, auto& o) { o.push_back(vtu_fos(kept[k])); });
      stream<double>(f, cells, 3 * cells, [&](std::size_t k, auto& o) {
        const Vec3& d = stab->direction[kept[k]];
        o.insert(o.end(), {d.x(), d.y(), d.z()});
      });
      stream<std::int32_t>(f, cells, cells,
                           [&](std::size_t k, auto& o) { o.push_back(stab->generation[kept[k]]); });
      stream<std::int64_t>(f, cells, cells,
                           [&](std::size_t k, auto& o) { o.push_back(stab->group[kept[k]]); });
    }
    stream<double>(f, cells, 3 * points, [&](std::size_t k, auto& o) {
      const auto lo = std::size_t(vertex_offset[kept[k]]);
      const auto hi = std::size_t(vertex_offset[kept[k] + 1]);
      const Vec3* x = src.vertices(lo, hi);
      for (std::size_t v = 0; v < hi - lo; ++v) o.insert(o.end(), {x[v].x(), x[v].y(), x[v].z()});
    });
    // Each block has its own points, numbered in the order of its vertices; Id: the type of the
    // cells' arrays.
    const auto nv = [&](std::size_t k) {
      return vertex_offset[kept[k] + 1] - vertex_offset[kept[k]];
    };
    const auto cell_arrays = [&](auto id) {
      using Id = decltype(id);
      std::int64_t base = 0;
      stream<Id>(f, cells, conn, [&](std::size_t k, auto& o) {
        for (std::int64_t v = 0, n = nv(k); v < n; ++v) o.push_back(Id(base + v));
        base += nv(k);
      });
      base = 0;
      stream<Id>(f, cells, cells, [&](std::size_t k, auto& o) { o.push_back(Id(base += nv(k))); });
      stream<std::uint8_t>(f, cells, cells, [&](std::size_t, auto& o) {
        o.push_back(section ? kVtkPolygon : kVtkPolyhedron);
      });
      if (section) return;
      // Faces: per block its face count, then per face its vertex count and point ids.
      base = 0;
      stream<Id>(f, cells, stream_len, [&](std::size_t k, auto& o) {
        const std::size_t nf = block(k).faces.size();
        o.push_back(Id(nf));
        // The block's loops, from its first face's first entry (`first`).
        const auto first = face_vertex_offset[face_row[k]];
        const std::int64_t* loops =
            src.loops(std::size_t(first), std::size_t(face_vertex_offset[face_row[k] + nf]));
        for (std::size_t r = face_row[k]; r < face_row[k] + nf; ++r) {
          const auto lo = face_vertex_offset[r], hi = face_vertex_offset[r + 1];
          o.push_back(Id(hi - lo));
          for (auto v = lo; v < hi; ++v) o.push_back(Id(base + loops[v - first]));
        }
        base += nv(k);
      });
      std::int64_t end = 0;
      stream<Id>(f, cells, cells, [&](std::size_t k, auto& o) {
        const std::size_t nf = block(k).faces.size();
        end += 1 + std::int64_t(nf) +
               (face_vertex_offset[face_row[k] + nf] - face_vertex_offset[face_row[k]]);
        o.push_back(Id(end));
      });
    };
    if (narrow)
      cell_arrays(std::int32_t{});
    else
      cell_arrays(std::int64_t{});
  });
  f.finish();
  part.commit();
  st.cells = cells;
  st.points = points;
  return st;
}

/// Adds to `points2` the squared magnitudes of the vertices in `g` of the blocks not removed
/// (`blocks`: those `g` holds, its block 0 the first).
void add_points(Range& points2, std::span<const Block> blocks, const Geometry& g) {
  for (std::size_t b = 0; b < blocks.size(); ++b)
    if (!(blocks[b].flags & kRemoved))
      for (auto v = g.vertex_offset[b]; v < g.vertex_offset[b + 1]; ++v)
        points2.add(g.vertices[std::size_t(v)].squaredNorm());
}

/// The geometry of a BlockSystem that holds it.
class MemorySource {
 public:
  explicit MemorySource(const Geometry& g) : g_(g) {}
  const std::vector<std::int64_t>& vertex_offset() const { return g_.vertex_offset; }
  const std::vector<std::int64_t>& face_vertex_offset() const { return g_.face_vertex_offset; }
  double volume(std::size_t b) const { return g_.volume[b]; }
  const Vec3* vertices(std::size_t lo, std::size_t) const { return g_.vertices.data() + lo; }
  const std::int64_t* loops(std::size_t lo, std::size_t) const {
    return g_.face_vertices.data() + lo;
  }

 private:
  const Geometry& g_;
};

/// The geometry of a file read by a GeometryStream: the volumes kept, the vertices and loops read
/// again a window of rows at a time (at least kWindowRows, and all that is asked for).
class FileSource {
 public:
  FileSource(const GeometryStream& file, std::vector<double> volumes)
      : file_(file), volume_(std::move(volumes)) {}
  const std::vector<std::int64_t>& vertex_offset() const { return file_.vertex_offset(); }
  const std::vector<std::int64_t>& face_vertex_offset() const { return file_.face_vertex_offset(); }
  double volume(std::size_t b) const { return volume_[b]; }
  const Vec3* vertices(std::size_t lo, std::size_t hi) {
    return window(lo, hi, file_.vertex_offset().back(), vertices_, vertices_at_,
                  [&](std::size_t a, std::size_t b) { file_.read_vertices(a, b, vertices_); });
  }
  const std::int64_t* loops(std::size_t lo, std::size_t hi) {
    return window(lo, hi, file_.face_vertex_offset().back(), loops_, loops_at_,
                  [&](std::size_t a, std::size_t b) { file_.read_face_vertices(a, b, loops_); });
  }

 private:
  // 2^19 rows; 16,384 in a sanitizer build (SLICE_SMALL_RUNS), so its tests cross windows too.
  static constexpr std::size_t kWindowRows = 16 * kGeometryRun;
  /// Rows [lo, hi) of a dataset of `rows` rows, from the window `buf` (rows from `at`), read
  /// anew from lo on where they are not all in it.
  template <class T, class Read>
  static const T* window(std::size_t lo, std::size_t hi, std::int64_t rows, std::vector<T>& buf,
                         std::size_t& at, const Read& read) {
    if (lo < at || hi > at + buf.size()) {
      at = lo;
      read(lo, std::max(hi, std::min(std::size_t(rows), lo + kWindowRows)));
    }
    return buf.data() + (lo - at);
  }
  const GeometryStream& file_;
  std::vector<double> volume_;
  std::vector<Vec3> vertices_;
  std::vector<std::int64_t> loops_;
  std::size_t vertices_at_ = 0, loops_at_ = 0;
};

}  // namespace

VtuStats write_blocks_vtu(const std::filesystem::path& out, const BlockSystem& bs,
                          VtuCompressor compressor, int threads, VtuIds ids) {
  const Geometry& g = geometry_of(bs, out.string());
  Range points2;
  add_points(points2, bs.blocks, g);
  MemorySource src(g);
  return write_vtu(out, bs, src, points2, compressor, threads, ids);
}

VtuStats export_blocks_vtu(const std::filesystem::path& in, const std::filesystem::path& out,
                           VtuCompressor compressor, int threads, VtuIds ids, JointSystem* joints) {
  // The volumes of the blocks and the range of the squared magnitudes of the points of those not
  // removed, as the runs come in (in block order, one at a time).
  std::vector<double> volumes;
  Range points2;
  const auto stream = GeometryStream::open(
      in, [&](const BlockSystem& bs, const Geometry& run, const GeometryBase& base, std::size_t n) {
        volumes.insert(volumes.end(), run.volume.begin(), run.volume.end());
        add_points(points2, std::span(bs.blocks).subspan(base.block, n), run);
      });
  if (!stream) {
    // read_blocks decides: it refuses the file, or reads it whole (a run failed only its own
    // tolerance) and the export goes on from memory.
    const BlockSystem bs = read_blocks(in);
    if (joints) *joints = bs.joints;
    geometry_of(bs, in.string());
    return write_blocks_vtu(out, bs, compressor, threads, ids);
  }
  if (joints) *joints = stream->blocks().joints;
  FileSource src(*stream, std::move(volumes));
  return write_vtu(out, stream->blocks(), src, points2, compressor, threads, ids);
}

namespace {

/// Each joint's part inside the domain: rows (joint indices) and their points.
struct JointPieces {
  std::vector<std::size_t> rows;
  std::vector<std::vector<Vec3>> points;
  std::size_t skipped = 0;
};

/// Where a persistent joint is drawn: the centre of the domain's box (its vertices' bounding box;
/// a section's as its unit-thickness slab) and a half size that covers the whole domain.
struct JointCanvas {
  Vec3 centre;
  double half;
};
JointCanvas joint_canvas(const std::filesystem::path& out, const JointSystem& js, double tol) {
  const PolytopeInfo dom = analyse_polytope(solid_region(js.domain, js.dimension), tol);
  if (!dom.bounded || !dom.has_interior)
    throw Error(out.string(), "the domain is empty or unbounded",
                "regenerate it with slice-joints");
  return {(dom.min + dom.max) / 2, 2 * ((dom.max - dom.min).norm() / 2 + tol)};
}

/// 3-D: polygons (a persistent joint: a square of its plane around the domain's centre, larger
/// than the domain, clipped).
JointPieces joint_polygons(const std::filesystem::path& out, const JointSystem& js, double tol) {
  const auto [centre, half] = joint_canvas(out, js, tol);
  JointPieces pieces;
  for (std::size_t j = 0; j < js.joints.size(); ++j) {
    const Joint& jt = js.joints[j];
    std::vector<Vec3> poly = joint_polygon(jt);
    if (poly.empty()) {
      const JointFrame fr = plane_frame(jt.dip_deg, jt.dip_direction_deg);
      const Vec3 c = centre - jt.plane.distance(centre) * jt.plane.normal;
      poly = {c + half * (-fr.u - fr.v), c + half * (fr.u - fr.v), c + half * (fr.u + fr.v),
              c + half * (-fr.u + fr.v)};
    }
    for (const Plane& p : js.domain.planes) {
      poly = clip_polygon(poly, p);
      if (poly.size() < 3) break;
    }
    if (poly.size() < 3 || newell_normal(poly).norm() / 2 <= tol * tol) {
      ++pieces.skipped;
      continue;
    }
    pieces.rows.push_back(j);
    pieces.points.push_back(std::move(poly));
  }
  return pieces;
}

/// 2-D (docs/2d.md): segments of the section's lines (y = 0). A persistent joint is its line
/// through the domain, a segment joint the part of its line between its rectangle's ends, both
/// clipped to the domain. The domain has no faces normal to y: for analyse_polytope, which needs
/// a bounded region, it is closed by y = +-0.5 (the section's unit thickness).
JointPieces joint_segments(const std::filesystem::path& out, const JointSystem& js, double tol) {
  const auto [centre, half] = joint_canvas(out, js, tol);
  JointPieces pieces;
  for (std::size_t j = 0; j < js.joints.size(); ++j) {
    const Joint& jt = js.joints[j];
    const Vec3& n = jt.plane.normal;
    const Vec3 t = Vec3(n.z(), 0, -n.x()).normalized();  // along the line, in (x, z)
    Vec3 c = centre - jt.plane.distance(centre) * n;
    c.y() = 0;
    double lo = -half, hi = half;
    if (!jt.persistent()) {
      lo = std::numeric_limits<double>::infinity();
      hi = -lo;
      for (const Vec3& p : joint_polygon(jt)) {
        lo = std::min(lo, t.dot(p - c));
        hi = std::max(hi, t.dot(p - c));
      }
    }
    Vec3 a = c + lo * t, b = c + hi * t;
    bool inside = true;
    for (const Plane& p : js.domain.planes) {  // Cyrus-Beck: the segment against each face
      const double da = p.distance(a), db = p.distance(b);
      if (da > 0 && db > 0) {
        inside = false;
        break;
      }
      if (da > 0) a += (b - a) * (da / (da - db));
      if (db > 0) b += (a - b) * (db / (db - da));
    }
    if (!inside || (b - a).norm() <= tol) {
      ++pieces.skipped;
      continue;
    }
    pieces.rows.push_back(j);
    pieces.points.push_back({a, b});
  }
  return pieces;
}

}  // namespace

VtuStats write_joints_vtu(const std::filesystem::path& out, const JointSystem& js,
                          VtuCompressor compressor) {
  const double tol = js.options.tolerance * js.length_scale;
  const bool section = js.dimension == 2;
  const JointPieces pieces = section ? joint_segments(out, js, tol) : joint_polygons(out, js, tol);
  const auto& rows = pieces.rows;
  const auto& polys = pieces.points;
  VtuStats st;
  st.skipped = pieces.skipped;
  std::size_t points = 0;
  Range r_id, r_set, r_kind, r_persistent, r_friction, r_cohesion, r_points;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Joint& jt = js.joints[rows[k]];
    points += polys[k].size();
    r_id.add(double(rows[k]));
    r_set.add(jt.set);
    r_kind.add(static_cast<int>(jt.kind));
    r_persistent.add(jt.persistent() ? 1 : 0);
    r_friction.add(jt.friction_angle_deg);
    r_cohesion.add(jt.cohesion);
    for (const Vec3& x : polys[k]) r_points.add(x.norm());
  }
  const std::size_t cells = rows.size();
  PartialFile part(out);
  vtu::File f(part.path(), out.string(), compressor);
  auto pts = r_points.spec("Float64", "Points");
  pts.components = 3;
  f.header(
      points, cells,
      {{"CellData",
        {r_id.spec("Int64", "joint_id"), r_set.spec("Int32", "set"), r_kind.spec("UInt8", "kind"),
         r_persistent.spec("UInt8", "persistent"), r_friction.spec("Float64", "friction_angle"),
         r_cohesion.spec("Float64", "cohesion")}},
       {"Points", {pts}},
       {"Cells", {{"Int64", "connectivity"}, {"Int64", "offsets"}, {"UInt8", "types"}}}},
      "");
  const auto joint = [&](std::size_t k) -> const Joint& { return js.joints[rows[k]]; };
  stream<std::int64_t>(f, cells, cells,
                       [&](std::size_t k, auto& o) { o.push_back(std::int64_t(rows[k])); });
  stream<std::int32_t>(f, cells, cells, [&](std::size_t k, auto& o) { o.push_back(joint(k).set); });
  stream<std::uint8_t>(f, cells, cells, [&](std::size_t k, auto& o) {
    o.push_back(static_cast<std::uint8_t>(joint(k).kind));
  });
  stream<std::uint8_t>(f, cells, cells,
                       [&](std::size_t k, auto& o) { o.push_back(joint(k).persistent() ? 1 : 0); });
  stream<double>(f, cells, cells,
                 [&](std::size_t k, auto& o) { o.push_back(joint(k).friction_angle_deg); });
  stream<double>(f, cells, cells, [&](std::size_t k, auto& o) { o.push_back(joint(k).cohesion); });
  stream<double>(f, cells, 3 * points, [&](std::size_t k, auto& o) {
    for (const Vec3& x : polys[k]) o.insert(o.end(), {x.x(), x.y(), x.z()});
  });
  std::int64_t base = 0;
  stream<std::int64_t>(f, cells, points, [&](std::size_t k, auto& o) {
    for (std::size_t v = 0; v < polys[k].size(); ++v) o.push_back(base++);
  });
  base = 0;
  stream<std::int64_t>(f, cells, cells, [&](std::size_t k, auto& o) {
    o.push_back(base += std::int64_t(polys[k].size()));
  });
  stream<std::uint8_t>(f, cells, cells, [&](std::size_t, auto& o) {
    o.push_back(section ? kVtkLine : kVtkPolygon);
  });
  f.finish();
  part.commit();
  st.cells = cells;
  st.points = points;
  return st;
}

}  // namespace slice

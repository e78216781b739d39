#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "file_common.hpp"
#include "slice/tolerance.hpp"

// /geometry of blocks.h5 (slice-vertices): its checks, writer and reader.
namespace slice::h5file {

// How far a stored vertex may lie off its faces: slice-vertices keeps every vertex within the
// geometry tolerance of its block's half-spaces in the block frame; storing it in the global frame
// rounds each coordinate once more (half an ulp of the largest coordinate). A writer checks a run
// of blocks with the run's largest coordinate, no more than the file's: what it writes, a reader
// accepts.
double vertex_tolerance(const JointSystem& js, double coord) {
  const Tolerances tol = Tolerances::from_scale(js.length_scale, js.options.tolerance);
  return 2 * tol.geometry + 8 * std::numeric_limits<double>::epsilon() * coord;
}

double vertex_tolerance(const JointSystem& js, const std::vector<Vec3>& vertices) {
  double coord = 0;
  for (const Vec3& v : vertices) coord = std::max(coord, v.cwiseAbs().maxCoeff());
  return vertex_tolerance(js, coord);
}

namespace {

// Block b of the run `g` (the file's block base.block + b; its first face is the run's row
// `face_row`) against its faces: every vertex inside every face, and every vertex of a face's loop
// on that face's plane. A file whose vertices were edited, or taken from other blocks, fails here
// instead of exporting a wrong model.
void check_vertices_on_faces(const Checker& c, const Geometry& g, const Block& blk, std::size_t b,
                             std::size_t face_row, const GeometryBase& base, double tol) {
  const auto v0 = static_cast<std::size_t>(g.vertex_offset[b]);
  const auto v1 = static_cast<std::size_t>(g.vertex_offset[b + 1]);
  const auto fail = [&](std::size_t v, std::size_t f, double off, const char* how) {
    c.fail(at("/geometry/vertices", std::size_t(base.vertex) + v) + " " +
           row_text(g.vertices[v].data(), 3) + " lies " + num(off) + " " + how + " face " +
           str(base.face + face_row + f) + " of block " + str(base.block + b) + " (tolerance " +
           num(tol) + "): /geometry does not match /blocks");
  };
  for (std::size_t f = 0; f < blk.faces.size(); ++f) {
    const Face& fc = blk.faces[f];
    for (std::size_t v = v0; v < v1; ++v) {
      const double off = fc.normal.dot(g.vertices[v] - blk.origin) - fc.d;
      if (off > tol) fail(v, f, off, "outside");
    }
    const auto lo = static_cast<std::size_t>(g.face_vertex_offset[face_row + f]);
    const auto hi = static_cast<std::size_t>(g.face_vertex_offset[face_row + f + 1]);
    for (std::size_t k = lo; k < hi; ++k) {
      const std::int64_t local = g.face_vertices[k];
      const std::size_t v = v0 + std::size_t(local);  // in range: checked by the caller
      const double off = fc.normal.dot(g.vertices[v] - blk.origin) - fc.d;
      if (std::abs(off) > tol) fail(v, f, std::abs(off), "off the plane of");
    }
  }
}

// Block base.block + b of the run `g` (its first face the run's row `face`, which is advanced past
// its faces) against its faces.
void check_block_geometry(const Checker& c, const BlockSystem& bs, const Geometry& g,
                          const GeometryBase& base, double tol, bool section, std::size_t b,
                          std::size_t& face) {
  const std::size_t block = base.block + b;  // the file's row
  const Block& blk = bs.blocks[block];
  const std::int64_t nv = g.vertex_offset[b + 1] - g.vertex_offset[b];
  const std::size_t first_face = face;
  for (std::size_t f = 0; f < blk.faces.size(); ++f, ++face) {
    const std::size_t file_face = base.face + face;
    const auto lo = static_cast<std::size_t>(g.face_vertex_offset[face]);
    const auto hi = static_cast<std::size_t>(g.face_vertex_offset[face + 1]);
    // A 2-D block's face is an edge: its two ends (docs/2d.md).
    if (section ? hi - lo != 2 : hi - lo < 3)
      c.fail(at("/geometry/face_vertex_offset", file_face) + " gives face " + str(file_face) + " " +
             str(hi - lo) + " vertices; a face has " +
             (section ? "2 in a 2-D file (an edge)" : "at least 3"));
    for (std::size_t k = lo; k < hi; ++k)
      if (g.face_vertices[k] < 0 || g.face_vertices[k] >= nv)
        c.fail(at("/geometry/face_vertices", std::size_t(base.face_vertex) + k) + " is " +
               str(g.face_vertices[k]) + "; expected an index into block " + str(block) + "'s " +
               str(nv) + " vertices");
    c.finite(g.face_area[face], At{"/geometry/face_area", file_face});
    if (!(g.face_area[face] > 0))
      c.fail(at("/geometry/face_area", file_face) + " is " + num(g.face_area[face]) +
             "; a face has positive area");
    const double fr = g.face_joint_fraction[face];
    if (!(fr >= 0 && fr <= 1))
      c.fail(at("/geometry/face_joint_fraction", file_face) + " is " + num(fr) +
             "; expected a fraction in [0, 1]");
  }
  check_vertices_on_faces(c, g, blk, b, first_face, base, tol);
  c.finite(g.volume[b], At{"/geometry/volume", block});
  if (!(g.volume[b] > 0))
    c.fail(at("/geometry/volume", block) + " is " + num(g.volume[b]) +
           "; a block has positive volume");
  c.finite(g.centroid[b], At{"/geometry/centroid", block});
  for (const double x : g.inertia[b])
    if (!std::isfinite(x))
      c.fail(at("/geometry/inertia", block) + " is " + row_text(g.inertia[b].data(), 6));
  if (std::string why = geometry_value_problem(g, blk, b, first_face, base, tol, section);
      !why.empty())
    c.fail(why);
}
}  // namespace

// The geometry `g` of the n blocks from base.block on (all of /geometry if base is zero and n
// the block count) against the blocks it describes: CSR shapes, indices, finite and positive
// values.
void check_geometry(const Checker& c, const BlockSystem& bs, const Geometry& g,
                    const GeometryBase& base, std::size_t n, double tol, bool concurrent) {
  SLICE_ASSERT(base.block + n <= bs.blocks.size());
  const std::size_t faces = face_count(std::span(bs.blocks).subspan(base.block, n));
  const auto rows = [&](const std::string& name, std::size_t got, std::size_t want,
                        const std::string& because) {
    if (got != want)
      c.fail("/geometry/" + name + " has " + str(got) + " rows; expected " + str(want) + " (" +
             because + ")");
  };
  const auto offsets = [&](const std::string& name, const std::vector<std::int64_t>& off,
                           std::size_t count, const std::string& what, std::size_t flat,
                           std::size_t row0, std::int64_t value0) {
    rows(name, off.size(), count + 1, what + " + 1");
    for (std::size_t i = 0; i < off.size(); ++i)
      if ((i == 0 && off[0] != 0) || (i > 0 && off[i] < off[i - 1]))
        c.fail(at("/geometry/" + name, row0 + i) + " is " + str(value0 + off[i]) +
               "; offsets start at 0 and never decrease");
    if (off.back() != static_cast<std::int64_t>(flat))
      c.fail("/geometry/" + name + " ends at " + str(value0 + off.back()) +
             " but its flat dataset has " + str(value0 + std::int64_t(flat)) + " rows");
  };
  offsets("vertex_offset", g.vertex_offset, n, "blocks", g.vertices.size(), base.block,
          base.vertex);
  offsets("face_vertex_offset", g.face_vertex_offset, faces, "faces", g.face_vertices.size(),
          base.face, base.face_vertex);
  rows("volume", g.volume.size(), n, "blocks");
  rows("centroid", g.centroid.size(), n, "blocks");
  rows("inertia", g.inertia.size(), n, "blocks");
  rows("face_area", g.face_area.size(), faces, "faces");
  rows("face_joint_fraction", g.face_joint_fraction.size(), faces, "faces");

  for (std::size_t v = 0; v < g.vertices.size(); ++v)
    c.finite(g.vertices[v], At{"/geometry/vertices", std::size_t(base.vertex) + v});
  const bool section = bs.joints.dimension == 2;
  check_runs(
      std::span(bs.blocks).subspan(base.block, n),
      [&](std::size_t lo, std::size_t hi, std::size_t first_face) {
        std::size_t face = first_face;
        for (std::size_t b = lo; b < hi; ++b)
          check_block_geometry(c, bs, g, base, tol, section, b, face);
      },
      concurrent);
}

bool geometry_rows_pass(const BlockSystem& bs, const Geometry& g, std::size_t lo, std::size_t hi,
                        std::size_t face) {
  const auto v0 = std::size_t(g.vertex_offset[lo]), v1 = std::size_t(g.vertex_offset[hi]);
  double coord = 0;
  for (std::size_t v = v0; v < v1; ++v) {
    if (!g.vertices[v].allFinite()) return false;
    coord = std::max(coord, g.vertices[v].cwiseAbs().maxCoeff());
  }
  const double tol = vertex_tolerance(bs.joints, coord);
  const Checker c("", "");
  try {
    for (std::size_t b = lo; b < hi; ++b)
      check_block_geometry(c, bs, g, {}, tol, bs.joints.dimension == 2, b, face);
  } catch (const Error&) {
    return false;
  }
  return true;
}

// All of /geometry against the blocks.
void check_geometry(const Checker& c, const BlockSystem& bs) {
  const Geometry& g = *bs.geometry;
  check_geometry(c, bs, g, {}, bs.blocks.size(), vertex_tolerance(bs.joints, g.vertices));
}

namespace {

// Rows [lo, hi) of a vector of Vec3 or Inertia as the doubles they hold (no copy).
template <std::size_t N, class Row>
std::span<const double> as_doubles(const std::vector<Row>& rows, std::size_t lo, std::size_t hi) {
  static_assert(sizeof(Row) == N * sizeof(double), "rows must be N packed doubles");
  return lo == hi ? std::span<const double>()
                  : std::span<const double>(reinterpret_cast<const double*>(rows.data() + lo),
                                            N * (hi - lo));
}

// The doubles of a vector of Vec3 or Inertia, to be read into.
template <std::size_t N, class Row>
double* as_doubles(std::vector<Row>& rows) {
  static_assert(sizeof(Row) == N * sizeof(double), "rows must be N packed doubles");
  return reinterpret_cast<double*>(rows.data());
}

}  // namespace

GeometryWriter::GeometryWriter(const Group& root, const BlockSystem& bs)
    : g_(root.create_group("geometry")),
      faces_(face_count(bs.blocks)),
      vertex_offset_(g_.create_rows<std::int64_t>("vertex_offset", bs.blocks.size() + 1, 0)),
      // A polyhedron has at most 2F - 4 vertices and 2 (3F - 6) loop entries; a polygon F and 2F.
      vertices_(g_.create_growing_rows<double>("vertices", 3,
                                               bs.joints.dimension == 2 ? faces_ : 2 * faces_)),
      face_vertex_offset_(g_.create_rows<std::int64_t>("face_vertex_offset", faces_ + 1, 0)),
      face_vertices_(g_.create_growing_rows<std::int64_t>(
          "face_vertices", 0, bs.joints.dimension == 2 ? 2 * faces_ : 6 * faces_)),
      volume_(g_.create_rows<double>("volume", bs.blocks.size(), 0)),
      centroid_(g_.create_rows<double>("centroid", bs.blocks.size(), 3)),
      inertia_(g_.create_rows<double>("inertia", bs.blocks.size(), 6)),
      face_area_(g_.create_rows<double>("face_area", faces_, 0)),
      face_joint_fraction_(g_.create_rows<double>("face_joint_fraction", faces_, 0)),
      bs_(bs) {
  const std::int64_t zero = 0;
  vertex_offset_.append({&zero, 1});
  face_vertex_offset_.append({&zero, 1});
}

void GeometryWriter::append(const Geometry& geo, std::size_t first, std::size_t first_face,
                            std::size_t n) {
  const std::size_t faces = face_count(std::span(bs_.blocks).subspan(next_.block, n));
  const std::size_t v0 = std::size_t(geo.vertex_offset[first]);
  const std::size_t v1 = std::size_t(geo.vertex_offset[first + n]);
  const std::size_t fv0 = std::size_t(geo.face_vertex_offset[first_face]);
  const std::size_t fv1 = std::size_t(geo.face_vertex_offset[first_face + faces]);
  const auto rebased = [&](const std::vector<std::int64_t>& off, std::size_t lo, std::size_t count,
                           std::int64_t base) {
    offsets_.clear();
    for (std::size_t i = lo + 1; i <= lo + count; ++i) offsets_.push_back(base + off[i] - off[lo]);
    return std::span<const std::int64_t>(offsets_);
  };
  vertex_offset_.append(rebased(geo.vertex_offset, first, n, next_.vertex));
  vertices_.append(as_doubles<3>(geo.vertices, v0, v1));
  face_vertex_offset_.append(rebased(geo.face_vertex_offset, first_face, faces, next_.face_vertex));
  face_vertices_.append(std::span(geo.face_vertices).subspan(fv0, fv1 - fv0));
  volume_.append(std::span(geo.volume).subspan(first, n));
  centroid_.append(as_doubles<3>(geo.centroid, first, first + n));
  inertia_.append(as_doubles<6>(geo.inertia, first, first + n));
  face_area_.append(std::span(geo.face_area).subspan(first_face, faces));
  face_joint_fraction_.append(std::span(geo.face_joint_fraction).subspan(first_face, faces));
  next_.advance(n, faces, v1 - v0, fv1 - fv0);
}

void GeometryWriter::finish() {
  SLICE_ASSERT(next_.block == bs_.blocks.size() && next_.face == faces_);
  for (auto* w : {&vertex_offset_, &face_vertex_offset_, &face_vertices_}) w->finish();
  for (auto* w : {&vertices_, &volume_, &centroid_, &inertia_, &face_area_, &face_joint_fraction_})
    w->finish();
}
// bs.geometry (checked by the caller), in the runs compute_geometry would have handed over.
void write_geometry_group(const Group& root, const BlockSystem& bs) {
  const Geometry& geo = *bs.geometry;
  GeometryWriter w(root, bs);
  for (std::size_t b0 = 0; b0 < bs.blocks.size(); b0 += kGeometryRun)
    w.append(geo, b0, w.next().face, std::min(kGeometryRun, bs.blocks.size() - b0));
  w.finish();
}

GeometryRows::GeometryRows(const Group& root, const std::vector<Block>& blocks,
                           std::vector<std::int64_t>& vertex_offsets,
                           std::vector<std::int64_t>& face_vertex_offsets)
    : g(root.open_group("geometry")),
      vertex_offset(vertex_offsets),
      face_vertex_offset(face_vertex_offsets),
      vertices(g.open_rows<double>("vertices", 3)),
      face_vertices(g.open_rows<std::int64_t>("face_vertices", 0)),
      volume(g.open_rows<double>("volume", 0)),
      centroid(g.open_rows<double>("centroid", 3)),
      inertia(g.open_rows<double>("inertia", 6)),
      face_area(g.open_rows<double>("face_area", 0)),
      fraction(g.open_rows<double>("face_joint_fraction", 0)) {
  const std::size_t n = blocks.size();
  const std::size_t faces = face_count(blocks);
  const std::string per_block = "the rows of /blocks/origin";
  const std::string per_face = "the rows of /blocks/face_normal";
  vertex_offsets = g.read<std::int64_t>("vertex_offset");
  check_offsets(g, "vertex_offset", vertex_offset, n, "blocks", vertices.rows(),
                "/geometry/vertices");
  face_vertex_offsets = g.read<std::int64_t>("face_vertex_offset");
  check_offsets(g, "face_vertex_offset", face_vertex_offset, faces, "faces", face_vertices.rows(),
                "/geometry/face_vertices");
  expect_rows(g, "volume", volume.rows(), n, per_block);
  expect_rows(g, "centroid", centroid.rows(), n, per_block);
  expect_rows(g, "inertia", inertia.rows(), n, per_block);
  expect_rows(g, "face_area", face_area.rows(), faces, per_face);
  expect_rows(g, "face_joint_fraction", fraction.rows(), faces, per_face);
}

void GeometryRows::read(const GeometryBase& from, const GeometryBase& end, Geometry& out,
                        const GeometryBase& at) const {
  // rows [lo, hi) of `r` into `to`
  const auto rows = [](const auto& r, std::size_t lo, std::size_t hi, auto* to) {
    if (hi > lo) r.read(lo, hi - lo, to);
  };
  const auto v0 = std::size_t(from.vertex), v1 = std::size_t(end.vertex);
  const auto k0 = std::size_t(from.face_vertex), k1 = std::size_t(end.face_vertex);
  rows(vertices, v0, v1, as_doubles<3>(out.vertices) + 3 * std::size_t(at.vertex));
  rows(face_vertices, k0, k1, out.face_vertices.data() + std::size_t(at.face_vertex));
  rows(volume, from.block, end.block, out.volume.data() + at.block);
  rows(centroid, from.block, end.block, as_doubles<3>(out.centroid) + 3 * at.block);
  rows(inertia, from.block, end.block, as_doubles<6>(out.inertia) + 6 * at.block);
  rows(face_area, from.face, end.face, out.face_area.data() + at.face);
  rows(fraction, from.face, end.face, out.face_joint_fraction.data() + at.face);
}

GeometryBase GeometryRows::base(std::size_t block, std::size_t face) const {
  return {block, face, vertex_offset[block], face_vertex_offset[face]};
}

// /geometry, shapes checked against the blocks before anything is indexed; values are checked
// by check_geometry. Read in runs of kBatch blocks: `run_read(lo, hi, face)` is called once the
// rows of blocks [lo, hi) (block lo's first face the row `face`) are all in, for a caller that
// checks them while the next run is read (in `geo`, whose arrays are sized before the first).
void read_geometry_group(const Group& root, const std::vector<Block>& blocks, Geometry& geo,
                         const RunRead& run_read) {
  geo = Geometry();
  const GeometryRows rows(root, blocks, geo.vertex_offset, geo.face_vertex_offset);
  const std::size_t n = blocks.size();
  const std::size_t faces = face_count(blocks);
  // Into the rows of Vec3 and Inertia themselves: packed doubles (as_doubles).
  geo.vertices.resize(rows.vertices.rows());
  geo.face_vertices.resize(rows.face_vertices.rows());
  geo.volume.resize(n);
  geo.centroid.resize(n);
  geo.inertia.resize(n);
  geo.face_area.resize(faces);
  geo.face_joint_fraction.resize(faces);
  for (std::size_t b0 = 0, f0 = 0; b0 < n; b0 += kBatch) {
    const std::size_t b1 = std::min(n, b0 + kBatch);
    const std::size_t f1 = f0 + face_count(std::span(blocks).subspan(b0, b1 - b0));
    const GeometryBase from = rows.base(b0, f0);
    rows.read(from, rows.base(b1, f1), geo, from);
    if (run_read) run_read(b0, b1, f0);
    f0 = f1;
  }
}

}  // namespace slice::h5file

#pragma once
// What the three parts of libslice/src/io/ that read and write joints.h5 and blocks.h5 share
// (file_common.cpp: the root header, messages and read checks; joints_file.cpp: the joint groups
// both kinds hold; blocks_file.cpp: /blocks and the writer of blocks.h5; geometry_file.cpp:
// /geometry). Private to libslice/src/io/.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "geometry_check.hpp"
#include "h5/h5.hpp"
#include "slice/error.hpp"
#include "slice/geometry.hpp"
#include "slice/h5io.hpp"
#include "slice/output.hpp"
#include "slice/scene.hpp"

namespace slice::h5file {

namespace fs = std::filesystem;
using h5::Group;
using h5::RowWriter;

// A normal is a unit vector if ||n| - 1| <= this. Normalising in double leaves ~1e-16; 1e-9
// rejects a vector nobody normalised without rejecting rounding. Dimensionless.
inline constexpr double kUnitTolerance = 1e-9;

// The fix of a refused write: validation runs before the .partial is even created.
inline constexpr const char* kNotWritten = "nothing was written";
inline constexpr const char* kWriteFix =
    "check that the directory is writable and the disk is not full; nothing was written";
inline constexpr const char* kJointsFix = "regenerate it with slice-joints";
inline constexpr const char* kBlocksFix = "regenerate it with slice-cut";
inline constexpr const char* kGeometryFix =
    "regenerate it with slice-vertices";  // /geometry's writer

// Shortest text that reads back as the same double ("nan", "inf", "0.1").
std::string num(double v);
std::string row_text(const double* v, std::size_t n);
std::string at(const std::string& dataset, std::size_t row);

/// A row of a dataset, made into text only if a check fails: the checks run on every row of
/// files of millions of blocks, where building the label each time cost more than the check.
struct At {
  const char* dataset;
  std::size_t row;
  const char* suffix = "";
};
std::string text(const At& a);
const std::string& text(const std::string& s);

std::string str(std::int64_t v);
std::string str(std::size_t v);

// --- validation, shared by writers (before writing) and readers (after reading) --------------

class Checker {
 public:
  Checker(std::string where, std::string fix) : where_(std::move(where)), fix_(std::move(fix)) {}
  [[noreturn]] void fail(const std::string& what) const { throw Error(where_, what, fix_); }

  template <class Label>
  void finite(double v, const Label& label) const {
    if (!std::isfinite(v)) fail(text(label) + " is " + num(v));
  }
  template <int N, class Label>
  void finite(const Eigen::Matrix<double, N, 1>& v, const Label& label) const {
    if (!v.allFinite()) fail(text(label) + " is " + row_text(v.data(), N));
  }
  template <class Label>
  void unit(const Vec3& n, const Label& label) const {
    finite(n, label);
    if (std::abs(n.norm() - 1) > kUnitTolerance)
      fail(text(label) + " is " + row_text(n.data(), 3) + ", not a unit vector (length " +
           num(n.norm()) + ")");
  }
  template <class Label>
  void non_negative(double v, const Label& label) const {
    finite(v, label);
    if (v < 0) fail(text(label) + " is " + num(v) + "; it cannot be negative");
  }
  template <class Label>
  void side(std::int64_t v, const Label& label) const {
    if (v < -1 || v > 1) fail(text(label) + " is " + str(v) + "; expected -1, 0 or 1");
  }
  template <class Label>
  void kind(JointKind k, const Label& label) const {
    if (static_cast<std::size_t>(k) >= kJointKindNames.size())
      fail(text(label) + " is " + std::to_string(static_cast<unsigned>(k)) +
           "; expected 0 (rock), 1 (construction) or 2 (boundary)");
  }

 private:
  std::string where_;
  std::string fix_;
};

// The joint groups (joints_file.cpp), /blocks (blocks_file.cpp: and /geometry, if the system
// has it and `with_geometry`), /geometry (geometry_file.cpp).
void check_joints(const Checker& c, const JointSystem& js);
void check_blocks(const Checker& c, const BlockSystem& bs, bool with_geometry = true);
// How far a stored vertex may lie off its faces (geometry_file.cpp says why).
double vertex_tolerance(const JointSystem& js, const std::vector<Vec3>& vertices);
// The same for a largest coordinate `coord` (of the vertices at hand).
double vertex_tolerance(const JointSystem& js, double coord);
// The geometry `g` of the n blocks from base.block on against the blocks it describes.
// `concurrent`: as for check_runs.
void check_geometry(const Checker& c, const BlockSystem& bs, const Geometry& g,
                    const GeometryBase& base, std::size_t n, double tol, bool concurrent = true);
// All of /geometry against the blocks.
void check_geometry(const Checker& c, const BlockSystem& bs);

// The faces of some blocks: the rows they take in /blocks/face_normal and the per-face datasets.
std::size_t face_count(std::span<const Block> blocks);

// The per-block checks of millions of blocks, on the caller's threads (slice::with_threads):
// check(lo, hi, face) for the blocks [lo, hi) of `blocks`, in runs, `face` the row of block
// lo's first face. The failure of the first run in block order is the one thrown, so a file
// gets the same message on any number of threads. `concurrent` false: on this thread only (the
// writing thread, which runs beside the computation that has the threads).
void check_runs(std::span<const Block> blocks,
                const std::function<void(std::size_t, std::size_t, std::size_t)>& check,
                bool concurrent = true);

// /contacts and /stability (stability_file.cpp): checked against the blocks, written, read.
void check_stability(const Checker& c, const BlockSystem& bs);
void write_stability_groups(const Group& root, const BlockSystem& bs);
void read_stability_groups(const Group& root, BlockSystem& bs);

// --- writing ---------------------------------------------------------------------------------

void write_header(const Group& root, FileKind kind, const Provenance& prov, const JointSystem& js);
// /domain, /joints, /sets, /zones, /options and /rock (joints_file.cpp).
void write_joint_groups(const Group& root, const JointSystem& js);

// Written and read in runs of kBatch blocks, each dataset by rows: the flat arrays of a million
// blocks (about 310 MB at 1.0 m Table 3) are never held at once. Two geometry runs, also in a
// sanitizer build (kGeometryRun).
inline constexpr std::size_t kBatch = 2 * kGeometryRun;

// Writes /geometry run by run, in block order (write_blocks, BlocksFileWriter): the datasets are
// created in a fixed order, the per-block and per-face ones at their known length, vertices and
// face_vertices growing by whole chunks. So the bytes depend on the geometry and on where the runs
// start, which is why every writer cuts a held geometry into runs of kGeometryRun blocks as
// compute_geometry hands them over.
class GeometryWriter {
 public:
  GeometryWriter(const Group& root, const BlockSystem& bs);

  /// Where the next run starts in the file.
  const GeometryBase& next() const { return next_; }

  /// Appends n blocks of `geo`, from its block `first` whose first face is its face row
  /// `first_face`: a whole geometry, or (0, 0) a run of its own.
  void append(const Geometry& geo, std::size_t first, std::size_t first_face, std::size_t n);

  void finish();

 private:
  Group g_;
  std::size_t faces_;
  RowWriter<std::int64_t> vertex_offset_;
  RowWriter<double> vertices_;
  RowWriter<std::int64_t> face_vertex_offset_, face_vertices_;
  RowWriter<double> volume_, centroid_, inertia_, face_area_, face_joint_fraction_;
  const BlockSystem& bs_;
  GeometryBase next_;
  std::vector<std::int64_t> offsets_;
};
// bs.geometry (checked by the caller), in the runs compute_geometry would have handed over.
void write_geometry_group(const Group& root, const BlockSystem& bs);

// "<out>.partial" created with its header and joint groups; `commit` closes and renames it.
struct OpenFile {
  OpenFile(const fs::path& out, FileKind kind, const Provenance& prov, const JointSystem& js,
           const WriteOptions& opt)
      : part(out), f(h5::File::create(part.path(), {out.string(), kWriteFix, opt.compress})) {
    write_header(f.root(), kind, prov, js);
    write_joint_groups(f.root(), js);
  }
  void commit() {
    f.close();
    part.commit();
  }
  PartialFile part;
  h5::File f;
};

// Validated by the caller; writes to "<out>.partial" and renames it onto `out`.
template <class Body>
void write_file(const fs::path& out, FileKind kind, const Provenance& prov, const JointSystem& js,
                const WriteOptions& opt, const Body& body) {
  OpenFile file(out, kind, prov, js, opt);
  body(file.f.root());
  file.commit();
}

// --- reading ---------------------------------------------------------------------------------

[[noreturn]] void fail(const Group& g, const std::string& what);
// A dataset must have `want` rows, as another dataset (`because`) says.
void expect_rows(const Group& g, const std::string& name, std::size_t got, std::size_t want,
                 const std::string& because);
// Dataset `name` of `g`, `cols` values a row, which must have `want` rows (expect_rows).
template <class T>
std::vector<T> read_rows(const Group& g, const std::string& name, std::size_t want,
                         const std::string& because, std::size_t cols = 1) {
  std::vector<T> v = cols == 1 ? g.read<T>(name) : g.read<T>(name, cols);
  expect_rows(g, name, v.size() / cols, want, because);
  return v;
}
// CSR offsets: n + 1 entries, starting at 0, never decreasing, ending at the flat length.
void check_offsets(const Group& g, const std::string& name, const std::vector<std::int64_t>& off,
                   std::size_t n, const std::string& n_what, std::size_t flat,
                   const std::string& flat_name);
Vec3 vec3(const std::vector<double>& v, std::size_t row);
FileHeader read_root_header(const Group& root);
void expect_kind(const Group& root, FileKind want);
// The joint groups both kinds hold (joints_file.cpp).
JointSystem read_joint_groups(const Group& root);
// /blocks, its shapes checked (blocks_file.cpp); `pruned` its attribute.
std::vector<Block> read_blocks_group(const Group& root, bool& pruned);
// /geometry opened for reading, its shapes checked against the blocks (geometry_file.cpp): the
// offsets, read whole into the caller's vectors, and the other datasets, read by rows.
struct GeometryRows {
  GeometryRows(const Group& root, const std::vector<Block>& blocks,
               std::vector<std::int64_t>& vertex_offsets,
               std::vector<std::int64_t>& face_vertex_offsets);
  /// Where block `block` (its first face `face`) starts in the file.
  GeometryBase base(std::size_t block, std::size_t face) const;
  /// The file's rows [from, end) of every dataset but the offsets into `out`, from its rows `at`
  /// (the arrays of `out` sized to hold them).
  void read(const GeometryBase& from, const GeometryBase& end, Geometry& out,
            const GeometryBase& at) const;

  Group g;
  const std::vector<std::int64_t>&vertex_offset, &face_vertex_offset;
  h5::RowReader<double> vertices;
  h5::RowReader<std::int64_t> face_vertices;
  h5::RowReader<double> volume, centroid, inertia, face_area, fraction;
};
// /geometry into `geo`, shapes checked against the blocks (geometry_file.cpp), read in runs of
// kBatch blocks; run_read(lo, hi, face) once the rows of blocks [lo, hi) are in (`face`: the row
// of block lo's first face). The arrays of `geo` have their sizes before the first call.
using RunRead = std::function<void(std::size_t, std::size_t, std::size_t)>;
void read_geometry_group(const Group& root, const std::vector<Block>& blocks, Geometry& geo,
                         const RunRead& run_read = {});
// Whether blocks [lo, hi) of the whole /geometry `g` (its shapes checked, those rows in; `face`:
// block lo's first face row) pass check_geometry's checks of values with the tolerance of their
// own vertices. That is no more than the file's, so what passes here passes check_geometry; what
// fails here may not (check_geometry decides, and says why).
bool geometry_rows_pass(const BlockSystem& bs, const Geometry& g, std::size_t lo, std::size_t hi,
                        std::size_t face);

}  // namespace slice::h5file

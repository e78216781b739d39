#include "geometry_stream.hpp"

#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <optional>
#include <span>

#include "../threads.hpp"
#include "file_common.hpp"

namespace slice {

using namespace h5file;

struct GeometryStream::Impl {
  explicit Impl(const fs::path& in) : f(h5::File::open(in, {in.string(), kBlocksFix})) {}
  h5::File f;
  BlockSystem bs;
  std::vector<std::int64_t> vertex_offset, face_vertex_offset;
  std::optional<GeometryRows> rows;
};

namespace {

/// The run of blocks [from.block, end.block) of `rows` into `run` (its arrays resized, its
/// offsets counting from 0).
void read_run(const GeometryRows& rows, const GeometryBase& from, const GeometryBase& end,
              Geometry& run) {
  const auto rebased = [](const std::vector<std::int64_t>& off, std::size_t lo, std::size_t hi,
                          std::vector<std::int64_t>& out) {
    out.resize(hi - lo + 1);
    for (std::size_t i = lo; i <= hi; ++i) out[i - lo] = off[i] - off[lo];
  };
  const std::size_t n = end.block - from.block, faces = end.face - from.face;
  rebased(rows.vertex_offset, from.block, end.block, run.vertex_offset);
  rebased(rows.face_vertex_offset, from.face, end.face, run.face_vertex_offset);
  run.vertices.resize(std::size_t(end.vertex - from.vertex));
  run.face_vertices.resize(std::size_t(end.face_vertex - from.face_vertex));
  run.volume.resize(n);
  run.centroid.resize(n);
  run.inertia.resize(n);
  run.face_area.resize(faces);
  run.face_joint_fraction.resize(faces);
  rows.read(from, end, run, {});
}

}  // namespace

std::unique_ptr<GeometryStream> GeometryStream::open(const fs::path& in, const Run& run) {
  std::unique_ptr<Impl> m;
  try {
    m = std::make_unique<Impl>(in);
    expect_kind(m->f.root(), FileKind::blocks);
    m->bs.joints = read_joint_groups(m->f.root());
    m->bs.blocks = read_blocks_group(m->f.root(), m->bs.pruned);
    // A file with /stability is read whole (read_blocks): its per-block arrays are carried too.
    if (!m->f.root().exists("geometry") || m->f.root().exists("stability") ||
        m->f.root().exists("contacts"))
      return nullptr;
    m->rows.emplace(m->f.root(), m->bs.blocks, m->vertex_offset, m->face_vertex_offset);
  } catch (const Error&) {
    return nullptr;
  }
  const BlockSystem& bs = m->bs;
  const GeometryRows& rows = *m->rows;
  // As read_blocks: the blocks checked on the other threads while this one reads /geometry; each
  // run checked (on every thread) and handed over while the next is read.
  std::atomic<bool> failed{false};
  const auto unless_refused = [&failed](const auto& body) {
    try {
      body();
    } catch (const Error&) {
      failed = true;
    }
  };
  tbb::task_group checking, values;
  checking.run(
      [&] { unless_refused([&] { check_blocks(Checker(in.string(), kBlocksFix), bs, false); }); });
  Geometry runs[2];
  try {
    const std::size_t n = bs.blocks.size();
    for (std::size_t b0 = 0, f0 = 0, k = 0; b0 < n && !failed; b0 += kBatch, ++k) {
      const std::size_t b1 = std::min(n, b0 + kBatch);
      const std::size_t f1 = f0 + face_count(std::span(bs.blocks).subspan(b0, b1 - b0));
      const GeometryBase from = rows.base(b0, f0);
      Geometry& g = runs[k % 2];  // the run before last used it: handed over already
      unless_refused([&] { read_run(rows, from, rows.base(b1, f1), g); });
      values.wait();  // the run before: checked and handed over
      if (failed) break;
      values.run([&, from, count = b1 - b0, g = &g] {
        unless_refused([&] {
          check_geometry(Checker("", ""), bs, *g, from, count,
                         vertex_tolerance(bs.joints, g->vertices));
        });
        if (!failed) run(bs, *g, from, count);
      });
      f0 = f1;
    }
    values.wait();
    checking.wait();
  } catch (...) {
    abandon(values);
    abandon(checking);
    throw;
  }
  if (failed) return nullptr;
  return std::unique_ptr<GeometryStream>(new GeometryStream(std::move(m)));
}

GeometryStream::GeometryStream(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GeometryStream::~GeometryStream() = default;

const BlockSystem& GeometryStream::blocks() const { return impl_->bs; }
const std::vector<std::int64_t>& GeometryStream::vertex_offset() const {
  return impl_->vertex_offset;
}
const std::vector<std::int64_t>& GeometryStream::face_vertex_offset() const {
  return impl_->face_vertex_offset;
}

void GeometryStream::read_vertices(std::size_t lo, std::size_t hi, std::vector<Vec3>& out) const {
  out.resize(hi - lo);
  if (hi > lo) impl_->rows->vertices.read(lo, hi - lo, out.front().data());
}

void GeometryStream::read_face_vertices(std::size_t lo, std::size_t hi,
                                        std::vector<std::int64_t>& out) const {
  out.resize(hi - lo);
  if (hi > lo) impl_->rows->face_vertices.read(lo, hi - lo, out.data());
}

}  // namespace slice

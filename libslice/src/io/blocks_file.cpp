#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <future>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "../prefetch.hpp"
#include "../threads.hpp"
#include "file_common.hpp"

// /blocks; the writers (write_blocks, BlocksFileWriter) and the reader of blocks.h5.
namespace slice::h5file {

namespace {

// A face that names a joint lies on that joint's plane: it was cut by it (or by its sliver
// rule's merge, which keeps the faces). Its normal is the joint's or the opposite, and its plane
// the joint's, within the geometry tolerance (and the rounding of moving it to the block's
// origin). A face naming another plane's joint would give a contact of a block with itself in
// 3DEC, or a joint's properties on the wrong face.
// `planes`: the joints' planes, apart from the joints (a face's joint is a random access).
void check_face_on_joint(const Checker& c, const JointSystem& js, const std::vector<Plane>& planes,
                         const Block& blk, const Face& f, std::size_t face_row) {
  const Plane& plane = planes[std::size_t(f.joint)];
  const double cosine = f.normal.dot(plane.normal);
  const double side = cosine < 0 ? -1 : 1;
  const double eps = std::numeric_limits<double>::epsilon();
  const double off = side * f.d + plane.normal.dot(blk.origin) - plane.d;
  const double tol = js.options.tolerance * js.length_scale +
                     8 * eps * (blk.origin.cwiseAbs().sum() + std::abs(f.d) + std::abs(plane.d));
  const bool parallel =
      (f.normal - side * plane.normal).cwiseAbs().maxCoeff() <= js.options.tolerance;
  if (parallel && std::abs(off) <= tol) return;
  const std::string what = at("/blocks/face_joint", face_row) + " is " + str(f.joint) +
                           ", but face " + str(face_row) + " does not lie on joint " +
                           str(f.joint) + "'s plane: ";
  if (!parallel)
    c.fail(what + "its normal " + row_text(f.normal.data(), 3) + " is not the joint's " +
           row_text(plane.normal.data(), 3) + " or the opposite");
  c.fail(what + "it lies " + num(std::abs(off)) + " from it (tolerance " + num(tol) + ")");
}

// Block b of the file (its first face is row face_row, which is advanced past its faces).
void check_block(const Checker& c, const BlockSystem& bs, const std::vector<Plane>& planes,
                 bool section, std::size_t b, std::size_t& face_row) {
  const auto joints = static_cast<std::int64_t>(bs.joints.joints.size());
  const Block& blk = bs.blocks[b];
  c.finite(blk.origin, At{"/blocks/origin", b});
  if (section && blk.origin.y() != 0)
    c.fail(at("/blocks/origin", b) + " has y = " + num(blk.origin.y()) +
           "; a 2-D file (root attribute dimension 2) has y = 0 everywhere");
  for (const Face& f : blk.faces) {
    c.unit(f.normal, At{"/blocks/face_normal", face_row});
    if (section && f.normal.y() != 0)
      c.fail(at("/blocks/face_normal", face_row) + " has y = " + num(f.normal.y()) +
             "; a 2-D file (root attribute dimension 2) has y = 0 everywhere");
    c.finite(f.d, At{"/blocks/face_d", face_row});
    if (f.joint < -1 || f.joint >= joints)
      c.fail(at("/blocks/face_joint", face_row) + " is " + str(f.joint) +
             "; expected -1 (domain face) or a joint index below " + str(joints) +
             " (the rows of /joints/normal)");
    if (f.joint >= 0) check_face_on_joint(c, bs.joints, planes, blk, f, face_row);
    ++face_row;
  }
  c.non_negative(blk.inradius, At{"/blocks/inradius", b});
  c.finite(blk.bsphere, At{"/blocks/bsphere", b});
  c.non_negative(blk.bsphere[3], At{"/blocks/bsphere", b, " radius"});
  if (blk.cluster < -1)
    c.fail(at("/blocks/cluster", b) + " is " + str(blk.cluster) +
           "; expected -1 (none) or a cluster id");
  // Any of the three bits may come together: slice-cut flags a boundary block or one on a
  // fixed_faces face as removed when its centre lies in a zone (a gallery reaching the base or a
  // fixed side), and slice-extract keeps such blocks as they are. Other bits mean nothing.
  constexpr unsigned kDefined = kBoundary | kRemoved | kFixed;
  if (blk.flags & ~kDefined)
    c.fail(at("/blocks/flags", b) + " is " + str(std::int64_t(blk.flags)) +
           "; only bits 0 (boundary), 1 (removed) and 2 (fixed) are defined, so it is 0 to " +
           str(std::int64_t(kDefined)));
}

}  // namespace

void check_blocks(const Checker& c, const BlockSystem& bs, bool with_geometry) {
  check_joints(c, bs.joints);
  std::vector<Plane> planes;
  planes.reserve(bs.joints.joints.size());
  for (const Joint& j : bs.joints.joints) planes.push_back(j.plane);
  const bool section = bs.joints.dimension == 2;
  check_runs(bs.blocks, [&](std::size_t lo, std::size_t hi, std::size_t face_row) {
    for (std::size_t b = lo; b < hi; ++b) {
      prefetch_faces_ahead(bs.blocks, b);
      // The planes of the joints of block b + 2 (whose faces came in two blocks ago): the
      // joints of neighbouring blocks are far apart in the joints' order.
      if (b + 2 < hi)
        for (const Face& f : bs.blocks[b + 2].faces)
          if (f.joint >= 0 && std::size_t(f.joint) < planes.size())
            prefetch(&planes[std::size_t(f.joint)]);
      check_block(c, bs, planes, section, b, face_row);
    }
  });
  if (with_geometry && bs.geometry) check_geometry(c, bs);
}

namespace {

void write_blocks_group(const Group& root, const BlockSystem& bs) {
  const std::size_t n = bs.blocks.size();
  const std::size_t faces = face_count(bs.blocks);
  const Group g = root.create_group("blocks");
  g.write_attribute<std::int64_t>("pruned", bs.pruned ? 1 : 0);
  auto origin = g.create_rows<double>("origin", n, 3);
  auto face_offset = g.create_rows<std::int64_t>("face_offset", n + 1, 0);
  auto face_normal = g.create_rows<double>("face_normal", faces, 3);
  auto face_d = g.create_rows<double>("face_d", faces, 0);
  auto face_joint = g.create_rows<std::int64_t>("face_joint", faces, 0);
  auto inradius = g.create_rows<double>("inradius", n, 0);
  auto bsphere = g.create_rows<double>("bsphere", n, 4);
  auto flags = g.create_rows<std::uint8_t>("flags", n, 0);
  auto cluster = g.create_rows<std::int64_t>("cluster", n, 0);
  // In runs of kBatch blocks: a run's rows are gathered on the other threads while this one
  // writes the run before (HDF5 writes on one thread only).
  struct Run {
    std::size_t b0 = 0, b1 = 0;
    std::vector<double> o, fn, fd, ir, bsph;
    std::vector<std::int64_t> off, fj, cl;
    std::vector<std::uint8_t> fl;
  };
  // Run r from block b0, whose first face is the file's row `base`.
  const auto gather = [&](Run& r, std::size_t b0, std::int64_t base) {
    r.b0 = b0;
    r.b1 = std::min(n, b0 + kBatch);
    const std::size_t m = r.b1 - r.b0;
    // face_offset has a leading 0 in the first run only.
    const std::size_t lead = b0 == 0 ? 1 : 0;
    r.off.resize(m + lead);
    if (lead) r.off[0] = 0;
    std::int64_t row = 0;  // within the run
    for (std::size_t i = 0; i < m; ++i)
      r.off[lead + i] = row += std::int64_t(bs.blocks[b0 + i].faces.size());
    const auto nf = static_cast<std::size_t>(row);
    r.o.resize(3 * m), r.ir.resize(m), r.bsph.resize(4 * m), r.fl.resize(m), r.cl.resize(m);
    r.fn.resize(3 * nf), r.fd.resize(nf), r.fj.resize(nf);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m, 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          prefetch_faces_ahead(bs.blocks, b0 + i);
                          const Block& b = bs.blocks[b0 + i];
                          for (int k = 0; k < 3; ++k) r.o[3 * i + k] = b.origin[k];
                          std::size_t f =
                              static_cast<std::size_t>(r.off[lead + i]) - b.faces.size();
                          for (const Face& face : b.faces) {
                            for (int k = 0; k < 3; ++k) r.fn[3 * f + k] = face.normal[k];
                            r.fd[f] = face.d;
                            r.fj[f] = face.joint;
                            ++f;
                          }
                          r.ir[i] = b.inradius;
                          for (int k = 0; k < 4; ++k) r.bsph[4 * i + k] = b.bsphere[k];
                          r.fl[i] = b.flags;
                          r.cl[i] = b.cluster;
                        }
                      });
    for (std::size_t i = lead; i < r.off.size(); ++i) r.off[i] += base;
  };
  const auto put = [&](const Run& r) {
    origin.append(r.o);
    face_offset.append(r.off);
    face_normal.append(r.fn);
    face_d.append(r.fd);
    face_joint.append(r.fj);
    inradius.append(r.ir);
    bsphere.append(r.bsph);
    flags.append(r.fl);
    cluster.append(r.cl);
  };
  Run runs[2];
  if (n == 0) {
    runs[0].off = {0};
    face_offset.append(runs[0].off);
  }
  tbb::task_group gathering;  // the next run, while this thread writes one
  try {
    if (n > 0) gather(runs[0], 0, 0);
    for (std::size_t b0 = 0, k = 0; b0 < n; b0 += kBatch, ++k) {
      if (b0 + kBatch < n)
        gathering.run([&gather, run = &runs[(k + 1) % 2], next = b0 + kBatch,
                       base = runs[k % 2].off.back()] { gather(*run, next, base); });
      put(runs[k % 2]);
      gathering.wait();
    }
  } catch (...) {
    abandon(gathering);  // the write's error is the one to report
    throw;
  }
  for (auto* w : {&origin, &face_normal, &face_d, &inradius, &bsphere}) w->finish();
  for (auto* w : {&face_offset, &face_joint, &cluster}) w->finish();
  flags.finish();
}

// Rows [lo, hi) of a dataset into `buf`.
template <class T>
void read_run(const h5::RowReader<T>& r, std::size_t lo, std::size_t hi, std::size_t width,
              std::vector<T>& buf) {
  buf.resize((hi - lo) * width);
  r.read(lo, hi - lo, buf.data());
}

}  // namespace

std::vector<Block> read_blocks_group(const Group& root, bool& pruned) {
  const Group g = root.open_group("blocks");
  const auto pruned_value = g.read_attribute<std::int64_t>("pruned");
  if (pruned_value != 0 && pruned_value != 1)
    fail(g, "/blocks attribute pruned is " + str(pruned_value) + "; expected 0 or 1");
  pruned = pruned_value == 1;

  const auto origin = g.open_rows<double>("origin", 3);
  const std::size_t n = origin.rows();
  const std::string because = "the rows of /blocks/origin";
  const auto offset = g.read<std::int64_t>("face_offset");
  const auto face_normal = g.open_rows<double>("face_normal", 3);
  const std::size_t faces = face_normal.rows();
  check_offsets(g, "face_offset", offset, n, "blocks", faces, "/blocks/face_normal");
  const std::string face_because = "the rows of /blocks/face_normal";
  const auto face_d = g.open_rows<double>("face_d", 0);
  expect_rows(g, "face_d", face_d.rows(), faces, face_because);
  const auto face_joint = g.open_rows<std::int64_t>("face_joint", 0);
  expect_rows(g, "face_joint", face_joint.rows(), faces, face_because);
  const auto inradius = g.open_rows<double>("inradius", 0);
  expect_rows(g, "inradius", inradius.rows(), n, because);
  const auto bsphere = g.open_rows<double>("bsphere", 4);
  expect_rows(g, "bsphere", bsphere.rows(), n, because);
  const auto flags = g.open_rows<std::uint8_t>("flags", 0);
  expect_rows(g, "flags", flags.rows(), n, because);
  const auto cluster = g.open_rows<std::int64_t>("cluster", 0);
  expect_rows(g, "cluster", cluster.rows(), n, because);

  // In runs of kBatch blocks: the flat arrays are never held whole. A run's rows become blocks
  // on the other threads while this one reads the next run (HDF5 reads on one thread only).
  std::vector<Block> blocks(n);
  struct Run {
    std::size_t b0 = 0, b1 = 0, f0 = 0;
    std::vector<double> o, fn, fd, ir, bsph;
    std::vector<std::int64_t> fj, cl;
    std::vector<std::uint8_t> fl;
  };
  const auto make_blocks = [&](const Run& r) {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(r.b0, r.b1, 1024),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t b = range.begin(); b != range.end(); ++b) {
            Block& blk = blocks[b];
            const std::size_t i = b - r.b0;
            blk.origin = vec3(r.o, i);
            const auto k0 = static_cast<std::size_t>(offset[b]) - r.f0;
            const auto k1 = static_cast<std::size_t>(offset[b + 1]) - r.f0;
            blk.faces.reserve(k1 - k0);
            for (std::size_t k = k0; k < k1; ++k)
              blk.faces.push_back({vec3(r.fn, k), r.fd[k], r.fj[k]});
            blk.inradius = r.ir[i];
            blk.bsphere = {r.bsph[4 * i], r.bsph[4 * i + 1], r.bsph[4 * i + 2], r.bsph[4 * i + 3]};
            blk.flags = r.fl[i];
            blk.cluster = r.cl[i];
          }
        });
  };
  Run runs[2];
  tbb::task_group making;  // at most one run's make_blocks at a time
  try {
    for (std::size_t b0 = 0, k = 0; b0 < n; b0 += kBatch, ++k) {
      Run& r = runs[k % 2];  // the run before last used it: made already
      r.b0 = b0;
      r.b1 = std::min(n, b0 + kBatch);
      r.f0 = static_cast<std::size_t>(offset[r.b0]);
      const auto f1 = static_cast<std::size_t>(offset[r.b1]);
      read_run(origin, r.b0, r.b1, 3, r.o);
      read_run(face_normal, r.f0, f1, 3, r.fn);
      read_run(face_d, r.f0, f1, 1, r.fd);
      read_run(face_joint, r.f0, f1, 1, r.fj);
      read_run(inradius, r.b0, r.b1, 1, r.ir);
      read_run(bsphere, r.b0, r.b1, 4, r.bsph);
      read_run(flags, r.b0, r.b1, 1, r.fl);
      read_run(cluster, r.b0, r.b1, 1, r.cl);
      making.wait();
      making.run([&make_blocks, run = &r] { make_blocks(*run); });
    }
    making.wait();
  } catch (...) {
    abandon(making);  // the read's error is the one to report
    throw;
  }
  return blocks;
}

}  // namespace slice::h5file

namespace slice {

const Geometry& geometry_of(const BlockSystem& bs, const std::string& where) {
  if (!bs.geometry)
    throw Error(where, "the blocks have no vertices (no /geometry)",
                "run slice-vertices on the blocks file first");
  return *bs.geometry;
}

using namespace h5file;

void write_blocks(const fs::path& out, const BlockSystem& bs, const Provenance& prov,
                  const WriteOptions& opt) {
  // The blocks (and geometry) are checked on the other threads while this one writes /blocks to
  // the .partial file, which becomes `out` only if they pass. A check's error comes first, as
  // when it ran first. /geometry is written after the check: its writer indexes by its offsets.
  tbb::task_group checking;
  checking.run([&] {
    check_blocks(Checker(out.string(), kNotWritten), bs);
    check_stability(Checker(out.string(), kNotWritten), bs);
  });
  std::optional<OpenFile> file;
  std::exception_ptr write_error;
  try {
    file.emplace(out, FileKind::blocks, prov, bs.joints, opt);
    write_blocks_group(file->f.root(), bs);
  } catch (...) {
    write_error = std::current_exception();
  }
  checking.wait();
  if (write_error) std::rethrow_exception(write_error);
  if (bs.geometry) write_geometry_group(file->f.root(), bs);
  if (bs.stability) write_stability_groups(file->f.root(), bs);
  file->commit();
}

// The bytes of a run's arrays.
std::size_t run_bytes(const Geometry& g) {
  return g.vertices.size() * sizeof(Vec3) + g.centroid.size() * sizeof(Vec3) +
         g.inertia.size() * sizeof(Inertia) +
         (g.vertex_offset.size() + g.face_vertex_offset.size() + g.face_vertices.size()) *
             sizeof(std::int64_t) +
         (g.volume.size() + g.face_area.size() + g.face_joint_fraction.size()) * sizeof(double);
}

// The runs of /geometry the writing thread has not taken yet hold at most this many bytes (or
// one run): a sink that would pass it waits. Uncompressed, the thread keeps up once /blocks is
// written (about 7 runs of Table 3 at 1.0 m queue meanwhile); deflate is slower than the
// geometry, and without a bound the whole of it would wait in memory.
constexpr std::size_t kQueuedBytes = std::size_t(256) << 20;

struct BlocksFileWriter::Impl {
  Impl(const BlockSystem& b, std::string n) : bs(b), name(std::move(n)) {}
  const BlockSystem& bs;
  std::string name;
  std::optional<OpenFile> file;
  std::future<void> writing;  // the header, joints, /blocks, then the runs of /geometry
  tbb::task_group checking;   // /blocks, on the caller's threads, meanwhile
  std::mutex mutex;
  std::condition_variable ready;  // a run came, or no more will
  std::condition_variable taken;  // the writing thread took a run, or stopped
  std::deque<Geometry> runs;      // given by the sink, not yet taken
  std::size_t queued_bytes = 0;   // their run_bytes
  GeometryBase given;             // where the next run given starts in the file
  bool streamed = false;          // geometry_sink() was asked for
  bool closed = false;            // no more runs will come
  bool abandoned = false;         // destroyed unfinished: write no more
  bool stopped = false;           // the writing thread ended (its error, if any, in `writing`)

  // The writing thread: /blocks, then each run as it comes, checked against its blocks.
  void write() {
    h5::silence_thread();  // a full disk: one error line, not HDF5's 41 lines of stack
    try {
      write_all();
    } catch (...) {
      stop();
      throw;
    }
    stop();
  }

  void write_all() {
    const Group& root = file->f.root();
    write_blocks_group(root, bs);
    std::optional<GeometryWriter> geo;
    for (;;) {
      Geometry run;
      {
        std::unique_lock lock(mutex);
        ready.wait(lock, [&] { return !runs.empty() || closed; });
        if (runs.empty()) break;
        run = std::move(runs.front());
        runs.pop_front();
        queued_bytes -= run_bytes(run);
      }
      taken.notify_one();
      if (!geo) geo.emplace(root, bs);
      geo->append(run, 0, 0, run.volume.size());  // checked by give()
    }
    if (abandoned) return;
    if (streamed && !geo) geo.emplace(root, bs);  // no blocks: empty datasets
    if (geo) geo->finish();
    if (!streamed && bs.geometry) write_geometry_group(root, bs);  // checked by finish()
  }

  // Queues a run, waiting while the queue is full; drops it once the thread has stopped.
  void give(Geometry&& run) {
    // Checked against its blocks here, on the giver's thread (compute_geometry's, beside the
    // next run's computing), so that the writing thread only writes and keeps up.
    const std::size_t n = run.volume.size();
    check_geometry(Checker(name, kNotWritten), bs, run, given, n,
                   vertex_tolerance(bs.joints, run.vertices), false);
    given.advance(n, face_count(std::span(bs.blocks).subspan(given.block, n)), run.vertices.size(),
                  run.face_vertices.size());
    const std::size_t bytes = run_bytes(run);
    {
      std::unique_lock lock(mutex);
      taken.wait(lock, [&] {
        return stopped || abandoned || queued_bytes == 0 || queued_bytes + bytes <= kQueuedBytes;
      });
      if (stopped || abandoned) return;
      runs.push_back(std::move(run));
      queued_bytes += bytes;
    }
    ready.notify_one();
  }

  void stop() {
    {
      std::lock_guard lock(mutex);
      stopped = true;
      runs.clear();
      queued_bytes = 0;
    }
    taken.notify_all();
  }

  void close() {
    {
      std::lock_guard lock(mutex);
      closed = true;
    }
    ready.notify_one();
  }
};

BlocksFileWriter::BlocksFileWriter(const fs::path& out, const BlockSystem& bs,
                                   const Provenance& prov, const WriteOptions& opt, Blocks blocks)
    : impl_(std::make_unique<Impl>(bs, out.string())) {
  // A bad output path fails here, before any work; the large /blocks group is written meanwhile,
  // and checked on the caller's threads (finish() waits for the check before the file is
  // renamed onto `out`).
  impl_->file.emplace(out, FileKind::blocks, prov, bs.joints, opt);
  impl_->writing = std::async(std::launch::async, [&m = *impl_] { m.write(); });
  if (blocks == Blocks::made)
    impl_->checking.run([&m = *impl_] { check_blocks(Checker(m.name, kNotWritten), m.bs, false); });
}

BlocksFileWriter::~BlocksFileWriter() {
  abandon(impl_->checking);
  if (!impl_->writing.valid()) return;
  {
    // Unfinished: the runs not yet written are not wanted.
    std::lock_guard lock(impl_->mutex);
    impl_->runs.clear();
    impl_->queued_bytes = 0;
    impl_->abandoned = true;
  }
  impl_->taken.notify_all();
  impl_->close();
  impl_->writing.wait();
}

GeometrySink BlocksFileWriter::geometry_sink() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->streamed = true;
  }
  return [&m = *impl_](std::size_t first, Geometry&& part) {
    (void)first;  // runs come in block order: the writer counts the blocks
    m.give(std::move(part));
  };
}

void BlocksFileWriter::finish() {
  Impl& m = *impl_;
  m.checking.wait();
  if (m.bs.geometry && !m.streamed) check_geometry(Checker(m.name, kNotWritten), m.bs);
  m.close();
  m.writing.get();
  m.file->commit();
}

BlockSystem read_blocks(const fs::path& in) {
  const h5::File f = h5::File::open(in, {in.string(), kBlocksFix});
  expect_kind(f.root(), FileKind::blocks);
  BlockSystem bs;
  bs.joints = read_joint_groups(f.root());
  bs.blocks = read_blocks_group(f.root(), bs.pruned);
  const auto blocks_checked = [&] { check_blocks(Checker(in.string(), kBlocksFix), bs, false); };
  const auto stability = [&] {
    read_stability_groups(f.root(), bs);
    check_stability(Checker(in.string(), "run slice-stability on the geom.h5 again"), bs);
  };
  if (!f.root().exists("geometry")) {
    blocks_checked();
    stability();
    return bs;
  }
  // The blocks are checked on the other threads while this one reads /geometry, and then each
  // run of /geometry as it comes in. Errors come in the order they would one after the other: a
  // read error, then the blocks', then /geometry's (check_geometry's, whose message names the
  // first bad row: a run that fails its own check, or whose values are off, sends it there).
  tbb::task_group checking, values;
  checking.run(blocks_checked);
  std::atomic<bool> rows_failed{false};
  const auto check_run = [&](std::size_t lo, std::size_t hi, std::size_t face) {
    // In pieces for both threads once the reading is over (face: the piece's first face row).
    constexpr std::size_t kPiece = 4096;
    for (std::size_t b = lo; b < hi; b += kPiece) {
      const std::size_t e = std::min(hi, b + kPiece);
      values.run([&, b, e, face] {
        if (!rows_failed && !geometry_rows_pass(bs, *bs.geometry, b, e, face)) rows_failed = true;
      });
      face += face_count(std::span(bs.blocks).subspan(b, e - b));
    }
  };
  bs.geometry.emplace();
  try {
    read_geometry_group(f.root(), bs.blocks, *bs.geometry, check_run);
  } catch (const Error& e) {  // slice-vertices wrote /geometry, not slice-cut
    abandon(values);
    abandon(checking);
    if (e.fix() != kBlocksFix) throw;
    throw Error(e.where(), e.problem(), kGeometryFix);
  } catch (...) {
    abandon(values);
    abandon(checking);
    throw;
  }
  try {
    checking.wait();
  } catch (...) {
    abandon(values);
    throw;
  }
  values.wait();
  if (rows_failed) check_geometry(Checker(in.string(), kGeometryFix), bs);
  stability();
  return bs;
}

}  // namespace slice

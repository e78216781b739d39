#include "slice/cut.hpp"

#include <oneapi/tbb/combinable.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#ifdef __linux__
#include <sys/mman.h>
#include <unistd.h>
#endif
#include <exception>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <vector>

#include "../prefetch.hpp"
#include "../threads.hpp"
#include "bodies.hpp"
#include "reach.hpp"
#include "referees.hpp"
#include "slice/decide.hpp"
#include "slice/error.hpp"
#include "slice/estimate.hpp"
#include "slice/mesh.hpp"
#include "slice/polytope.hpp"
#include "subdivision.hpp"

namespace slice {
namespace {

using namespace cutting;

/// Sizes `v` (empty) to n blocks. A fresh array's pages are first faulted in on every thread:
/// the kernel zeroing them is most of its cost (1e6 blocks: 0.2-0.3 s on one thread here).
void resize_prefaulted(std::vector<Block>& v, std::size_t n) {
  v.reserve(n);
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t chunk = page * 1024;
  const auto at = reinterpret_cast<std::uintptr_t>(v.data());
  const std::uintptr_t lo = (at + page - 1) / page * page,
                       hi = (at + n * sizeof(Block)) / page * page;
  if (page > 0 && hi > lo)
    tbb::parallel_for(lo, hi, chunk, [&](std::uintptr_t a) {
      // On failure (a kernel before 5.14) the pages fault in below, as without this.
      static_cast<void>(
          madvise(reinterpret_cast<void*>(a), std::min(chunk, hi - a), MADV_POPULATE_WRITE));
    });
#endif
  v.resize(n);
}

// ---- Threads (issue 15) ------------------------------------------------------------------------
// The subdivision is sequential by nature, yet once a joint has split a block, what happens to
// each piece later depends only on that piece and on the joints that reach it. So the cut is a
// tree of tasks (oneTBB task groups): a task cuts its blocks by its joints in order until it
// holds CutOptions::tasks blocks, then hands them, in kGroups spatially compact groups, to child
// tasks, each given the task's remaining joints that reach one of its blocks' spheres. Whether
// and where a task splits depends only on its own blocks, never on the threads. The blocks are
// then put back in the order one sequential subdivision makes them (SplitOrder), so blocks.h5 is
// the same bytes for every thread count; the figures a run reports add up over the tasks, so they
// are the same too.

void add(LpCounts& a, const LpCounts& b) {
  a.cut_test += b.cut_test;
  a.extents += b.extents;
  a.chebyshev += b.chebyshev;
  a.redundancy += b.redundancy;
  a.contact += b.contact;
  a.failed += b.failed;
  a.vertex_extremes += b.vertex_extremes;
}

/// A node of the task tree: a subdivision, the joints it is to cut by and, once it has split,
/// the child tasks that hold its blocks.
struct Task {
  Task(const CutContext& ctx, std::vector<Block> roots, std::vector<Extremes> extremes,
       const Vec3& lo, const Vec3& hi)
      : sub(ctx, std::move(roots), std::move(extremes), lo, hi) {}
  Subdivision sub;
  std::vector<std::size_t> joints;              // increasing
  std::vector<std::size_t> from;                // per root: its number in the parent task
  std::vector<std::unique_ptr<Task>> children;  // empty for a leaf
};

constexpr std::size_t kGroups = 8;       // child tasks per split
constexpr std::size_t kNone = SIZE_MAX;  // no parent

/// A 30-bit Morton code of a point of the box [lo, hi]: sorting by it keeps neighbours together.
std::uint32_t morton(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  std::uint32_t code = 0;
  std::uint32_t q[3];
  for (int k = 0; k < 3; ++k) {
    const double t = (p[k] - lo[k]) / std::max(hi[k] - lo[k], 1e-300);
    q[k] = std::uint32_t(std::clamp(t, 0.0, 1.0) * 1023.0);
  }
  for (int bit = 9; bit >= 0; --bit)
    for (int k = 0; k < 3; ++k) code = (code << 1) | ((q[k] >> bit) & 1u);
  return code;
}

/// The order one thread makes blocks in: at each joint, the blocks it splits in increasing
/// (global) number, each keeping its number for the side below and appending the side above.
/// `tasks` lists the tree parents first; parent[t] is t's parent (kNone for the root, whose
/// block 0 is the domain, global block 0).
///
/// Each block made has an id: 0 for the domain, 1 + e for the piece above of the e-th split (the
/// tasks' events counted in task order; a task's k-th split appended its block roots + k). A
/// task's root is a block of its parent, made at an earlier joint. The ids of the blocks split
/// are found on every thread and bucketed by joint; only the numbering is one pass, joint after
/// joint (a piece's number needs the numbers of the blocks split at the same joint).
class SplitOrder {
 public:
  SplitOrder(const std::vector<Task*>& tasks, const std::vector<std::size_t>& parent,
             std::size_t joints)
      : tasks_(tasks), parent_(parent), first_(tasks.size() + 1, 0), splits_at_(joints, 0) {
    for (std::size_t t = 0; t < tasks.size(); ++t)
      first_[t + 1] = first_[t] + tasks[t]->sub.events.size();
    for_each_task([&](std::size_t t) {
      for (const SplitEvent& e : tasks_[t]->sub.events)
        std::atomic_ref(splits_at_[e.joint]).fetch_add(1, std::memory_order_relaxed);
    });
    // The splits by joint, each as (id of the block split, event). Their order within a joint
    // depends on the threads; sorting them by the block's number (unique there) does not.
    std::vector<std::size_t> cursor(joints, 0);
    for (std::size_t j = 0; j + 1 < joints; ++j) cursor[j + 1] = cursor[j] + splits_at_[j];
    std::vector<std::size_t> end = cursor;
    struct Split {
      std::size_t key, event;
    };
    std::vector<Split> by_joint(first_.back());
    for_each_task([&](std::size_t t) {
      const auto& events = tasks_[t]->sub.events;
      for (std::size_t k = 0; k < events.size(); ++k) {
        const SplitEvent& e = events[k];
        SLICE_ASSERT(e.child == roots(t) + k);
        const std::size_t at =
            std::atomic_ref(end[e.joint]).fetch_add(1, std::memory_order_relaxed);
        by_joint[at] = {id(t, e.block), first_[t] + k};
      }
    });
    number_.assign(first_.back() + 1, 0);
    std::size_t next = 1;
    for (std::size_t j = 0; j < joints; ++j) {
      const auto lo = by_joint.begin() + std::ptrdiff_t(cursor[j]);
      const auto hi = lo + std::ptrdiff_t(splits_at_[j]);
      for (auto s = lo; s != hi; ++s) s->key = number_[s->key];
      std::sort(lo, hi, [](const Split& a, const Split& b) { return a.key < b.key; });
      for (auto s = lo; s != hi; ++s) number_[1 + s->event] = next++;
    }
  }

  /// Splits made at each joint.
  const std::vector<std::size_t>& splits_at() const { return splits_at_; }
  /// The global number of block i of task t.
  std::size_t number(std::size_t t, std::size_t i) const { return number_[id(t, i)]; }

  /// Calls f(t) for every task t, on every thread.
  template <typename F>
  void for_each_task(F&& f) const {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tasks_.size()),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t t = range.begin(); t != range.end(); ++t) f(t);
                      });
  }

 private:
  const std::vector<Task*>& tasks_;
  const std::vector<std::size_t>& parent_;
  std::vector<std::size_t> first_;      // per task, its first event (task order), then all
  std::vector<std::size_t> splits_at_;  // by joint
  std::vector<std::size_t> number_;     // by id

  /// The blocks task t started with: the domain for the root, else those it was handed.
  std::size_t roots(std::size_t t) const {
    return parent_[t] == kNone ? 1 : tasks_[t]->from.size();
  }
  std::size_t id(std::size_t t, std::size_t i) const {
    while (parent_[t] != kNone && i < tasks_[t]->from.size()) {
      i = tasks_[t]->from[i];
      t = parent_[t];
    }
    const std::size_t r = roots(t);
    return i < r ? 0 : 1 + first_[t] + (i - r);
  }
};

class Cutter {
 public:
  Cutter(const JointSystem& js, const CutOptions& opt, const Progress& progress)
      : js_(js),
        opt_(opt),
        progress_(progress),
        ctx_{js,
             opt,
             Tolerances::from_scale(js.length_scale, js.options.tolerance, js.dimension),
             opt.max_blocks > 0 ? opt.max_blocks : js.options.max_blocks,
             js.options.min_inscribed_diameter > 0 || js.options.max_aspect_ratio > 0,
             nullptr},
        referees_(opt.backend, ctx_.tol, opt.certify),
        arena_(threads_for(opt.backend, opt.threads)) {}

  CutResult run() {
    check_estimate();
    CutResult out;
    out.blocks.joints = js_;
    arena_.execute([&] {
      const auto t0 = Clock::now();
      subdivide();
      stats_.seconds_cut = seconds_since(t0);
      const auto t1 = Clock::now();
      finish();
      stats_.seconds_finish = seconds_since(t1);
    });
    stats_.joints = js_.joints.size();
    stats_.decisions = referees_.counts();
    stats_.lps.failed += stats_.decisions.failed;
    stats_.blocks = blocks_.size();
    out.blocks.blocks = std::move(blocks_);
    out.stats = stats_;
    return out;
  }

 private:
  const JointSystem& js_;
  const CutOptions& opt_;
  const Progress& progress_;
  CutContext ctx_;
  Referees referees_;
  tbb::task_arena arena_;
  std::mutex progress_mutex_;
  std::atomic<std::size_t> done_{0}, assigned_{0};  // joint-task pairs, for the progress bar
  std::vector<PreparedJoint> prepared_;             // by joint number
  std::vector<Block> blocks_;
  CutStats stats_;
  Vec3 domain_lo_ = Vec3::Zero(), domain_hi_ = Vec3::Zero();

  void report(std::string_view stage, std::size_t done, std::size_t total) {
    if (!progress_) return;
    const std::lock_guard lock(progress_mutex_);
    progress_(stage, done, total);
  }

  /// Refuses, before any work, a joint system whose persistent joints alone make more than
  /// max_blocks blocks.
  void check_estimate() const {
    const BlockEstimate e = estimate_blocks(js_);
    if (e.blocks() <= double(ctx_.max_blocks)) return;
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "its persistent joints make %s%.0f blocks (1 + %lld planes + %.0f lines + %.0f "
                  "points inside the domain), more than max_blocks = %lld",
                  e.sampled ? "about " : "", e.blocks(), static_cast<long long>(e.planes), e.lines,
                  e.points, static_cast<long long>(ctx_.max_blocks));
    throw Error("/joints", buf, max_blocks_fix());
  }

  Block domain_block(Extremes& ext) {
    // A 2-D section is analysed as its unit-thickness slab; its blocks have no y faces.
    const PolytopeInfo info =
        analyse_polytope(solid_region(js_.domain, js_.dimension), ctx_.tol.geometry);
    if (!info.bounded || !info.has_interior)
      throw Error("/domain", "the domain is empty or unbounded", "regenerate it with slice-joints");
    if (const std::string why = precision_problem(info.min, info.max, ctx_.tol.cut); !why.empty())
      throw Error("/domain", why, "move the scene nearer the origin or raise its tolerance");
    domain_lo_ = info.min;
    domain_hi_ = info.max;
    Block b;
    b.origin = info.interior_point;
    for (const Plane& p : js_.domain.planes) {
      const Plane l = to_local(p, b.origin);
      b.faces.push_back({l.normal, l.d, -1});
    }
    LpSolver& solver = referees_.local().solver();
    if (!Subdivision::set_sphere(ctx_, solver, b, stats_.lps, ext,
                                 vertex_extremes(solver, b.faces, 0x3fu, ctx_.tol)))
      throw Error("/domain", "the domain's extents LP failed", "check the domain");
    return b;
  }

  /// The whole cut: the task tree from the domain, then the blocks in sequential order.
  void subdivide() {
    const std::size_t joints = js_.joints.size();
    std::vector<Block> domain;
    std::vector<Extremes> extremes(1);
    domain.push_back(domain_block(extremes[0]));  // sets domain_lo_, domain_hi_
    Task root(ctx_, std::move(domain), std::move(extremes), domain_lo_, domain_hi_);
    root.joints.resize(joints);
    std::iota(root.joints.begin(), root.joints.end(), std::size_t(0));
    std::atomic<std::int64_t> total{1};
    ctx_.total = &total;
    prepared_.resize(joints);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, joints, 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t j = range.begin(); j != range.end(); ++j)
                          prepared_[j] = prepare(js_.joints[j]);
                      });
    ctx_.prepared = &prepared_;
    assigned_ = joints;
    run_task(root);
    ctx_.total = nullptr;
    ctx_.prepared = nullptr;
    std::vector<PreparedJoint>().swap(prepared_);

    // The tree, parents first.
    std::vector<Task*> tasks{&root};
    std::vector<std::size_t> parent{kNone};
    for (std::size_t t = 0; t < tasks.size(); ++t)
      for (auto& c : tasks[t]->children) {
        tasks.push_back(c.get());
        parent.push_back(t);
      }

    // The block array, made while the splits are numbered.
    std::size_t count = 1;
    for (const Task* t : tasks) count += t->sub.events.size();
    tbb::task_group allocation;
    allocation.run([&] { resize_prefaulted(blocks_, count); });
    const SplitOrder order(tasks, parent, joints);

    // Figures: as if one subdivision had run. A joint-block pair is skipped unless the cut LP
    // saw it; there were as many blocks at joint j as the domain and the earlier splits make.
    std::vector<std::uint8_t> cut(joints, 0);
    for (const Task* t : tasks) {
      const Subdivision& s = t->sub;
      add(stats_.lps, s.lps);
      stats_.splits += s.splits;
      stats_.splits_undone += s.splits_undone;
      stats_.pairs_skipped -= s.tested;
      stats_.rejected_plane += s.rejected[std::size_t(CutReject::plane)];
      stats_.rejected_box += s.rejected[std::size_t(CutReject::box)];
      stats_.rejected_faces += s.rejected[std::size_t(CutReject::faces)];
      stats_.settled_by_limit += s.settled_by_limit;
      stats_.cut_without_lp += s.cut_without_lp;
      for (const std::size_t j : s.joints_that_cut) cut[j] = 1;
    }
    std::size_t made = 1;  // blocks before joint j
    for (std::size_t j = 0; j < joints; ++j) {
      stats_.pairs_skipped += made;
      made += order.splits_at()[j];
      stats_.joints_missing += cut[j] ? 0 : 1;
    }

    allocation.wait();
    order.for_each_task([&](std::size_t t) {
      if (!tasks[t]->children.empty()) return;  // its blocks went to its children
      auto& blocks = tasks[t]->sub.blocks;
      for (std::size_t i = 0; i < blocks.size(); ++i)
        blocks_[order.number(t, i)] = std::move(blocks[i]);
      std::vector<Block>().swap(blocks);  // the peak: keep one copy of the block array
    });
  }

  /// Cuts the task's blocks by its joints until it holds opt.tasks blocks; then its children
  /// do the rest, concurrently.
  void run_task(Task& task) {
    const std::size_t split_at = std::max<std::size_t>(opt_.tasks, 2);
    std::size_t k = 0;
    {
      Referee& referee = referees_.local();
      while (k < task.joints.size()) {
        // Two joints ahead the prepared polygon, one ahead its corners and edges (heap arrays
        // of their own, found through the polygon loaded the turn before).
        if (k + 2 < task.joints.size()) prefetch_joint(task.joints[k + 2]);
        if (k + 1 < task.joints.size()) prefetch_polygon(task.joints[k + 1]);
        task.sub.cut_by(task.joints[k++], referee);
        if (opt_.tasks > 0 && task.sub.blocks.size() >= split_at && k < task.joints.size()) break;
      }
    }
    done_ += k;
    report("cut", done_, assigned_);
    if (k < task.joints.size()) hand_out(task, k);
    std::vector<std::size_t>().swap(task.joints);
    if (task.children.empty()) {
      task.sub.release_index();
      return;
    }
    tbb::task_group group;
    for (auto& c : task.children) group.run([this, c = c.get()] { run_task(*c); });
    group.wait();
  }

  /// Starts loading what the reach tests read of joint j: the task's joints are in no order,
  /// and their prepared polygons (about 160 bytes each) fill more than the cache.
  static constexpr std::size_t kPrefetchJoints = 6;
  void prefetch_joint(std::size_t j) const {
    const auto* p = reinterpret_cast<const char*>(&prepared_[j]);
    prefetch(p);
    prefetch(p + 64);
    prefetch(p + sizeof(PreparedJoint) - 1);
    prefetch(&js_.joints[j].kind);
  }

  /// The same for its corners and edges (heap arrays of their own, found through the prepared
  /// polygon: best loaded a turn before, by prefetch_joint).
  void prefetch_polygon(std::size_t j) const {
    const PreparedJoint& pj = prepared_[j];
    for (const auto* v :
         {static_cast<const void*>(pj.corners.data()), static_cast<const void*>(pj.edges.data())}) {
      if (!v) continue;
      prefetch(v);
      prefetch(static_cast<const char*>(v) + 64);
    }
  }

  /// Hands the task's blocks, in kGroups groups of neighbours (Morton order of their spheres'
  /// centres), to as many child tasks, each with those of joints [k, ...) that may reach one of
  /// its blocks: every joint without the index, and every persistent boundary joint (it also
  /// flags blocks it does not reach). Later pieces of a block lie inside its box, so no other
  /// joint can cut them.
  void hand_out(Task& task, std::size_t k) {
    Subdivision& sub = task.sub;
    const std::size_t n = sub.blocks.size();
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::vector<std::uint32_t> code(n);
    for (std::size_t i = 0; i < n; ++i)
      code[i] = morton(sub.blocks[i].bsphere.head<3>(), sub.lo(), sub.hi());
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return code[a] < code[b]; });
    const std::size_t groups = std::min(kGroups, n);
    std::vector<std::size_t> group_of(n);
    for (std::size_t g = 0; g < groups; ++g)
      for (std::size_t r = g * n / groups; r < (g + 1) * n / groups; ++r) group_of[order[r]] = g;

    // The groups' blocks (in their order in the task) and spheres.
    std::vector<std::vector<std::size_t>> members(groups);
    for (std::size_t i = 0; i < n; ++i) members[group_of[i]].push_back(i);
    std::vector<SphereGroup> spheres(groups);
    GroupBoxes boxes;
    for (std::size_t g = 0; g < groups; ++g) {
      for (const std::size_t i : members[g]) spheres[g].add(sub.blocks[i].bsphere);
      boxes.set(g, spheres[g].lo(), spheres[g].hi());
    }

    // The joints of each group: the groups each joint may reach (bits), on every thread (the
    // root's hand-out tests all the joints).
    static_assert(kGroups <= 8 && kGroups <= GroupBoxes::kMax);
    std::vector<std::uint8_t> reached(task.joints.size() - k, 0);
    // Isolated: a thread waiting here runs only these tests, not another task (whose children
    // would then wait for it).
    tbb::this_task_arena::isolate([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, reached.size(), 1024),
          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t m = range.begin(); m != range.end(); ++m) {
              if (m + kPrefetchJoints < range.end())
                prefetch_joint(task.joints[k + m + kPrefetchJoints]);
              const std::size_t j = task.joints[k + m];
              const Joint& joint = js_.joints[j];
              const bool all =
                  !opt_.use_index || (joint.kind == JointKind::boundary && joint.persistent());
              if (all) {
                reached[m] = std::uint8_t((1u << groups) - 1);
                continue;
              }
              // The groups' boxes first, then the spheres of those they pass.
              const PreparedJoint& pj = prepared_[j];
              const ReachQuery q(pj, ctx_.tol.cut);
              for (unsigned bits = boxes.may_reach(pj, ctx_.tol.cut); bits; bits &= bits - 1) {
                const auto g = std::size_t(std::countr_zero(bits));
                if (spheres[g].any_reached(q)) reached[m] |= std::uint8_t(1u << g);
              }
            }
          });
    });
    std::vector<std::vector<std::size_t>> lists(groups);
    for (std::size_t m = 0; m < reached.size(); ++m)
      for (std::size_t g = 0; g < groups; ++g)
        if (reached[m] >> g & 1u) lists[g].push_back(task.joints[k + m]);
    // The progress bar's total: the pairs handed out replace the task's unprocessed ones.
    for (const auto& l : lists) assigned_ += l.size();
    assigned_ -= task.joints.size() - k;

    // The children: each group's blocks and its box.
    for (std::size_t g = 0; g < groups; ++g) {
      std::vector<Block> roots;
      std::vector<Extremes> extremes;
      for (const std::size_t i : members[g]) {
        roots.push_back(std::move(sub.blocks[i]));
        extremes.push_back(sub.extremes[i]);
      }
      auto child = std::make_unique<Task>(ctx_, std::move(roots), std::move(extremes),
                                          spheres[g].lo().cwiseMax(sub.lo()),
                                          spheres[g].hi().cwiseMin(sub.hi()));
      child->from = std::move(members[g]);
      child->joints = std::move(lists[g]);
      task.children.push_back(std::move(child));
    }
    sub.release();
  }

  void finish() {
    tbb::task_group trim;
#ifdef __GLIBC__
    // The tasks' many small arrays are freed now; give their pages back before the blocks are
    // pruned and written (1.0 m Table 3 scene: peak RSS 1.75 GB -> 1.62 GB), on one thread while
    // the others find the centres.
    trim.run([] { malloc_trim(0); });
#endif
    // Chebyshev centre: the origin of every block, its inradius. Blocks are independent.
    std::atomic<std::size_t> done{0};
    tbb::combinable<LpCounts> lps;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        LpSolver& solver = referees_.local().solver();
                        LpCounts& mine = lps.local();
                        std::vector<Face> core;
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          prefetch_faces_ahead(blocks_, i);
                          Block& b = blocks_[i];
                          const ChebyshevBall c = chebyshev_ball(solver, b.faces, ctx_.tol);
                          ++mine.chebyshev;
                          SLICE_ASSERT(c.status == LpStatus::optimal && c.radius > 0);
                          b.inradius = c.radius;
                          move_origin(b, unique_centre(b, c, core, solver, mine));
                        }
                        const std::size_t n = done += range.size();
                        report("centres", n, blocks_.size());
                      });
    trim.wait();
    lps.combine_each([&](const LpCounts& c) { add(stats_.lps, c); });
    // Removal zones: blocks whose centre is inside are removed (kept in the file, flagged).
    std::vector<MeshInside> meshes;
    for (const TriangleMesh& m : js_.zone_meshes) meshes.emplace_back(m);
    std::atomic<std::size_t> boundary{0}, removed{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::size_t on_boundary = 0, inside_zone = 0;
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          Block& b = blocks_[i];
                          if (in_zone(b.origin, meshes)) b.flags |= kRemoved;
                          on_boundary += (b.flags & kBoundary) ? 1 : 0;
                          inside_zone += (b.flags & kRemoved) ? 1 : 0;
                        }
                        boundary += on_boundary;
                        removed += inside_zone;
                      });
    stats_.boundary += boundary;
    stats_.removed += removed;
    if (js_.options.fixed_faces) mark_fixed();
    // Clusters, and the slivers exempt cuts leave (bodies.hpp): removed with an excavation, or
    // joined to a neighbour.
    const BodyStats b = form_bodies(blocks_, js_, referees_.local(), ctx_.tol);
    stats_.clusters = b.clusters;
    stats_.lps.contact += b.contact_lps;
    stats_.lps.extents += b.reach_lps;
    stats_.lps.failed += b.failed;
    stats_.removed += b.slivers_removed;
    stats_.slivers_removed = b.slivers_removed;
    stats_.slivers_joined = b.slivers_joined;
    stats_.slivers_left = b.slivers_left;
  }

  /// Whether a block's centre `x` is inside a removal zone (`meshes`: the mesh zones').
  bool in_zone(const Vec3& x, const std::vector<MeshInside>& meshes) const {
    for (const Region& z : js_.zones)
      if (std::all_of(z.planes.begin(), z.planes.end(),
                      [&](const Plane& p) { return p.distance(x) < 0; }))
        return true;
    return std::any_of(meshes.begin(), meshes.end(),
                       [&](const MeshInside& inside) { return inside(x); });
  }

  // [options] fixed_faces: a block that reaches a named face of the domain's bounding box, to
  // within the geometry tolerance, is fixed. Its extents (six LPs) only when faces are named.
  void mark_fixed() {
    std::atomic<std::size_t> lp_count{0}, vertex_count{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks_.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        LpSolver& solver = referees_.local().solver();
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          Block& b = blocks_[i];
                          const Extents e = extents(solver, b.faces, ctx_.tol);
                          // Failed LPs were solved again exactly.
                          SLICE_ASSERT(e.status == LpStatus::optimal);
                          lp_count += static_cast<std::size_t>(e.lps);
                          vertex_count += static_cast<std::size_t>(e.at_vertices);
                          const Vec3 lo = b.origin + e.min, hi = b.origin + e.max;
                          for (int k = 0; k < 6; ++k) {
                            if (!(js_.options.fixed_faces & (1u << k))) continue;
                            const int axis = k / 2;
                            const bool touches =
                                k % 2 == 0 ? lo[axis] <= domain_lo_[axis] + ctx_.tol.geometry
                                           : hi[axis] >= domain_hi_[axis] - ctx_.tol.geometry;
                            if (touches) b.flags |= kFixed;
                          }
                        }
                      });
    stats_.lps.extents += lp_count;
    stats_.lps.vertex_extremes += vertex_count;
    for (const Block& b : blocks_) stats_.fixed += (b.flags & kFixed) ? 1 : 0;
  }

  /// The Chebyshev centre is not unique (a box longer than wide has a segment of them) and each
  /// backend may return another point of that set, which would make zone membership depend on
  /// the backend. The centre used is the middle of the extents of the "core": the points where
  /// a ball of radius (1 - kCoreShrink) r* fits. That is one point whatever the backend (up to
  /// LP accuracy), and on a segment or a centrally symmetric set of centres, its middle.
  Vec3 unique_centre(const Block& b, const ChebyshevBall& c, std::vector<Face>& core,
                     LpSolver& solver, LpCounts& lps) const {
    constexpr double kCoreShrink = 1e-6;
    core = b.faces;
    for (Face& f : core) f.d -= (1 - kCoreShrink) * c.radius;
    const Extents e = extents(solver, core, ctx_.tol);
    lps.chebyshev += static_cast<std::size_t>(e.lps);
    lps.vertex_extremes += static_cast<std::size_t>(e.at_vertices);
    if (e.status != LpStatus::optimal) {
      ++lps.failed;
      return c.centre;
    }
    return e.centre;
  }
};

}  // namespace

CutResult cut_blocks(const JointSystem& js, const CutOptions& opt, const Progress& progress) {
  return Cutter(js, opt, progress).run();
}

}  // namespace slice

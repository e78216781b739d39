// slice/h5io.hpp, the /geometry group of blocks.h5 (written by slice-vertices): exact round
// trips, byte-identical reruns, and the refusals of the writer and the reader.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "io/file_common.hpp"
#include "io/geometry_check.hpp"
#include "io/geometry_stream.hpp"
#include "io/h5/h5.hpp"
#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/export_vtu.hpp"
#include "slice/h5io.hpp"
#include "slice/scene.hpp"
#include "slice/vertices.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;

namespace {

// Two joints, one a polygon (fractions below 1), a zone; pruned and with geometry.
slice::BlockSystem sample() {
  const std::string scene =
      "[domain]\nbox = { min = [0, 0, 0], max = [4, 3, 2] }\n"
      "[[joints]]\ndip = 60\ndip_direction = 30\npoint = [2, 1.5, 1]\n"
      "[[joints]]\ndip = 10\ndip_direction = 200\npoint = [1, 1, 1.2]\n"
      "polygon_uv = [[-1, -1], [1, -1], [1, 1], [-1, 1]]\n";
  auto r = slice::cut_blocks(slice::generate_joints(slice::parse_scene(scene, "s.toml")), {});
  slice::prune_blocks(r.blocks, slice::LpBackend::native);
  slice::compute_geometry(r.blocks);
  return std::move(r.blocks);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const slice::Error& e) {
    return e.what();
  }
  return "(no error)";
}

void check_same(const slice::Geometry& a, const slice::Geometry& b) {
  CHECK(a.vertex_offset == b.vertex_offset);
  CHECK(a.vertices == b.vertices);
  CHECK(a.face_vertex_offset == b.face_vertex_offset);
  CHECK(a.face_vertices == b.face_vertices);
  CHECK(a.volume == b.volume);
  CHECK(a.centroid == b.centroid);
  CHECK(a.inertia == b.inertia);
  CHECK(a.face_area == b.face_area);
  CHECK(a.face_joint_fraction == b.face_joint_fraction);
}

}  // namespace

TEST_CASE("/geometry reads back exactly what was written", "[h5io][geometry]") {
  test::TempDir dir;
  const auto bs = sample();
  REQUIRE(bs.geometry);
  REQUIRE(bs.blocks.size() >= 3);
  bool bridge = false;
  for (const double f : bs.geometry->face_joint_fraction) bridge = bridge || f < 1;
  CHECK(bridge);  // the sample has a rock bridge, so fractions are not all 1
  slice::write_blocks(dir / "g.h5", bs, {});
  const auto back = slice::read_blocks(dir / "g.h5");
  REQUIRE(back.geometry);
  check_same(*bs.geometry, *back.geometry);

  SECTION("and the same content gives the same bytes") {
    slice::write_blocks(dir / "g2.h5", back, {});
    CHECK(test::read_bytes(dir / "g.h5") == test::read_bytes(dir / "g2.h5"));
  }
  SECTION("a file without /geometry reads back without it") {
    auto plain = bs;
    plain.geometry.reset();
    slice::write_blocks(dir / "p.h5", plain, {});
    CHECK_FALSE(slice::read_blocks(dir / "p.h5").geometry);
  }
  SECTION("pruning again drops the geometry (the faces may change)") {
    auto again = back;
    slice::prune_blocks(again, slice::LpBackend::native);
    CHECK_FALSE(again.geometry);
  }
}

TEST_CASE("the writer refuses geometry that does not match the blocks", "[h5io][geometry]") {
  test::TempDir dir;
  auto bs = sample();
  auto& g = *bs.geometry;
  std::string expect;
  SECTION("vertex_offset too short") {
    g.vertex_offset.pop_back();
    expect = "/geometry/vertex_offset has";
  }
  SECTION("a face with two vertices") {
    g.face_vertex_offset[1] = g.face_vertex_offset[0] + 2;
    expect = "/geometry/face_vertex_offset row 0 gives face 0 2 vertices";
  }
  SECTION("a vertex index past the block's vertices") {
    g.face_vertices[0] = g.vertex_offset[1];
    expect = "/geometry/face_vertices row 0 is";
  }
  SECTION("NaN volume") {
    g.volume[1] = std::numeric_limits<double>::quiet_NaN();
    expect = "/geometry/volume row 1 is nan";
  }
  SECTION("zero face area") {
    g.face_area[2] = 0;
    expect = "/geometry/face_area row 2 is 0";
  }
  SECTION("a fraction above 1") {
    g.face_joint_fraction[3] = 1.5;
    expect = "/geometry/face_joint_fraction row 3 is 1.5";
  }
  SECTION("an infinite inertia") {
    g.inertia[0][4] = std::numeric_limits<double>::infinity();
    expect = "/geometry/inertia row 0 is";
  }
  // Issue 25 item 4: values that are finite and in range, but not the block's.
  SECTION("a reversed face loop") {
    std::reverse(g.face_vertices.begin() + g.face_vertex_offset[1],
                 g.face_vertices.begin() + g.face_vertex_offset[2]);
    expect = "the loop of face 1 of block 0";
  }
  SECTION("a loop with a repeated vertex") {
    g.face_vertices[1] = g.face_vertices[0];
    expect = "the loop of face 0 of block 0";
  }
  SECTION("a volume 1e-6 off") {
    g.volume[1] *= 1 + 1e-6;
    expect = "/geometry/volume row 1 is";
  }
  SECTION("a centroid outside its block") {
    g.centroid[1].z() += 10;
    expect = "/geometry/centroid row 1";
  }
  SECTION("an inertia 1e-4 off") {
    g.inertia[0][0] *= 1 + 1e-4;
    expect = "/geometry/inertia row 0 column 0 (xx)";
  }
  CAPTURE(expect);
  const std::string msg = error_of([&] { slice::write_blocks(dir / "g.h5", bs, {}); });
  CHECK_THAT(msg, Contains("g.h5: " + expect) && Contains("nothing was written"));
  CHECK(std::filesystem::is_empty(dir.path()));
}

TEST_CASE("the reader refuses a spoiled /geometry and names the file and dataset",
          "[h5io][geometry]") {
  test::TempDir dir;
  const auto p = dir / "g.h5";
  slice::write_blocks(p, sample(), {});
  std::string expect;
  {
    slice::h5::File f = slice::h5::File::open(p, {p.string(), ""}, true);
    const auto g = f.root().open_group("geometry");
    SECTION("missing dataset") {
      g.remove("volume");
      expect = "missing dataset /geometry/volume";
    }
    SECTION("too few centroids") {
      auto c = g.read<double>("centroid", 3);
      c.resize(c.size() - 3);
      g.remove("centroid");
      g.write<double>("centroid", c, 3);
      expect = "/geometry/centroid has";
    }
    SECTION("an index out of range") {
      auto fv = g.read<std::int64_t>("face_vertices");
      fv[5] = -1;
      g.remove("face_vertices");
      g.write<std::int64_t>("face_vertices", fv);
      expect = "/geometry/face_vertices row 5 is -1";
    }
    SECTION("offsets that do not end at the flat length") {
      auto off = g.read<std::int64_t>("vertex_offset");
      off.back() += 1;
      g.remove("vertex_offset");
      g.write<std::int64_t>("vertex_offset", off);
      expect = "/geometry/vertex_offset ends at";
    }
    f.close();
  }
  CAPTURE(expect);
  const std::string msg = error_of([&] { slice::read_blocks(p); });
  CHECK_THAT(msg, Contains(p.string()) && Contains(expect));
}

namespace {

// n^3 unit cubes in a grid, pruned, no geometry yet: more blocks than one run of kGeometryRun,
// with the joints (and options) of sample().
slice::BlockSystem cubes(int n) {
  slice::BlockSystem bs;
  bs.joints = sample().joints;
  bs.pruned = true;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        slice::Block b;
        b.origin = {i + 0.5, j + 0.5, k + 0.5};
        for (int axis = 0; axis < 3; ++axis)
          for (const double sign : {-1.0, 1.0}) {
            slice::Face f;
            f.normal = sign * slice::Vec3::Unit(axis);
            f.d = 0.5;
            b.faces.push_back(f);
          }
        b.inradius = 0.5;
        b.bsphere << b.origin, std::sqrt(0.75);
        bs.blocks.push_back(b);
      }
  return bs;
}

/// The side of the smallest grid of cubes with more than `run` blocks: two runs of `run` (the
/// library's runs are powers of two from 1,024, so n^3 stays within 2 x run).
int side_past(std::size_t run) {
  int n = 1;
  while (std::size_t(n) * std::size_t(n) * std::size_t(n) <= run) ++n;
  return n;
}

}  // namespace

TEST_CASE("/geometry streamed run by run while it is computed gives write_blocks' bytes",
          "[h5io][geometry]") {
  test::TempDir dir;
  // Catch2 runs the test case again from the top for each value of `compress` and each section
  // (six times); the grid and its geometry computed whole are the same every time, so they are
  // made once. Their size is not a choice: the test needs two runs of kGeometryRun blocks
  // (35,937 blocks; 1,331 in a sanitizer build, whose runs are shorter).
  static const slice::BlockSystem grid = cubes(side_past(slice::kGeometryRun));
  static const slice::BlockSystem held = [] {
    auto h = grid;
    slice::compute_geometry(h, {}, 1);
    return h;
  }();
  REQUIRE(grid.blocks.size() > slice::kGeometryRun);
  REQUIRE(grid.blocks.size() <= 2 * slice::kGeometryRun);
  const bool compress = GENERATE(false, true);
  CAPTURE(compress);
  slice::write_blocks(dir / "held.h5", held, {}, {compress});

  {
    slice::BlocksFileWriter w(dir / "streamed.h5", grid, {}, {compress});
    const slice::GeometrySink sink = w.geometry_sink();
    std::size_t runs = 0;
    const auto st = slice::compute_geometry(
        grid,
        [&](std::size_t first, slice::Geometry&& run) {
          CHECK(first == runs * slice::kGeometryRun);
          ++runs;
          sink(first, std::move(run));
        },
        {}, 2);
    CHECK(runs == 2);
    CHECK(st.vertices == 8 * grid.blocks.size());
    w.finish();
  }
  CHECK(test::read_bytes(dir / "streamed.h5") == test::read_bytes(dir / "held.h5"));
  const auto back = slice::read_blocks(dir / "streamed.h5");
  REQUIRE(back.geometry);
  check_same(*held.geometry, *back.geometry);

  SECTION("held geometry given to the writer without a sink: the same bytes") {
    slice::BlocksFileWriter w(dir / "late.h5", held, {}, {compress});
    w.finish();
    CHECK(test::read_bytes(dir / "late.h5") == test::read_bytes(dir / "held.h5"));
  }
  SECTION("blocks read back (checked by the reader, not again by the writer): the same bytes") {
    const auto back_blocks = slice::read_blocks(dir / "held.h5");
    auto read = back_blocks;
    read.geometry.reset();
    slice::BlocksFileWriter w(dir / "read.h5", read, {}, {compress},
                              slice::BlocksFileWriter::Blocks::read);
    slice::compute_geometry(read, w.geometry_sink(), {}, 2);
    w.finish();
    CHECK(test::read_bytes(dir / "read.h5") == test::read_bytes(dir / "held.h5"));
  }
  SECTION("a run that does not match its blocks: an error naming the file's row, nothing written") {
    const std::string msg = error_of([&] {
      slice::BlocksFileWriter w(dir / "bad.h5", grid, {}, {compress});
      const slice::GeometrySink sink = w.geometry_sink();
      slice::compute_geometry(
          grid,
          [&](std::size_t first, slice::Geometry&& run) {
            if (first > 0) run.volume[5] = -1;  // block kGeometryRun + 5
            sink(first, std::move(run));
          },
          {}, 2);
      w.finish();
    });
    CHECK_THAT(msg, Contains("bad.h5: /geometry/volume row " +
                             std::to_string(slice::kGeometryRun + 5) + " is -1") &&
                        Contains("nothing was written"));
    CHECK_FALSE(std::filesystem::exists(dir / "bad.h5"));
  }
}

TEST_CASE("the reader checks /geometry run by run as it reads and decides as a whole check does",
          "[h5io][geometry]") {
  test::TempDir dir;
  // 68,921 cubes (2,197 in a sanitizer build): two runs of the reader (kBatch blocks each). The
  // last cube is moved far out, so that the file's vertex tolerance (its largest coordinate's) is
  // wider than the first run's. Made once: Catch2 runs the test case again from the top for each of
  // its seven sections, and the grid with its geometry is the same every time.
  static const slice::BlockSystem grid = [] {
    auto bs = cubes(side_past(slice::h5file::kBatch));
    bs.blocks.back().origin += slice::Vec3(1e7, 0, 0);
    bs.blocks.back().bsphere.head<3>() += slice::Vec3(1e7, 0, 0);
    slice::compute_geometry(bs, {}, 2);
    return bs;
  }();
  REQUIRE(grid.blocks.size() > slice::h5file::kBatch);
  REQUIRE(grid.blocks.size() <= 2 * slice::h5file::kBatch);
  const slice::Geometry& g = *grid.geometry;
  double first_run = 0, file = 0;
  for (std::size_t v = 0; v < g.vertices.size(); ++v) {
    const double c = g.vertices[v].cwiseAbs().maxCoeff();
    file = std::max(file, c);
    if (v < std::size_t(g.vertex_offset[slice::h5file::kBatch])) first_run = std::max(first_run, c);
  }
  const double run_tol = slice::h5file::vertex_tolerance(grid.joints, first_run);
  const double file_tol = slice::h5file::vertex_tolerance(grid.joints, file);
  REQUIRE(file_tol > 1.5 * run_tol);
  // Vertex 0 of block 1 (a corner of the cube (0, 0, 1)), moved along x off its x face.
  const auto written = [&](double dx) {
    auto bs = grid;
    bs.geometry->vertices[std::size_t(g.vertex_offset[1])].x() += dx;
    slice::write_blocks(dir / "g.h5", bs, {});
    return dir / "g.h5";
  };
  // The file with vertex `row` moved out by twice the file's tolerance, past the writer's own
  // check: spoiled in the file.
  const auto spoil = [&](std::size_t row) {
    slice::write_blocks(dir / "g.h5", grid, {});
    slice::h5::File f = slice::h5::File::open(dir / "g.h5", {"g.h5", ""}, true);
    const auto geo = f.root().open_group("geometry");
    auto v = geo.read<double>("vertices", 3);
    v[3 * row] -= 2 * file_tol;
    geo.remove("vertices");
    geo.write<double>("vertices", v, 3);
    f.close();
  };
  SECTION("the right /geometry reads back unchanged") {
    const auto back = slice::read_blocks(written(0));
    REQUIRE(back.geometry);
    check_same(g, *back.geometry);
  }
  SECTION("off by more than the run's tolerance, less than the file's: accepted") {
    const double dx = -0.5 * (run_tol + file_tol);
    const auto p = written(dx);  // the writer checks the whole with the file's tolerance too
    const auto back = slice::read_blocks(p);
    REQUIRE(back.geometry);
    CHECK(back.geometry->vertices[std::size_t(g.vertex_offset[1])].x() ==
          g.vertices[std::size_t(g.vertex_offset[1])].x() + dx);
  }
  SECTION("off by more than the file's tolerance: refused, naming the vertex row") {
    const std::size_t row = std::size_t(g.vertex_offset[1]);
    spoil(row);
    const std::string msg = error_of([&] { slice::read_blocks(dir / "g.h5"); });
    CHECK_THAT(msg, Contains("/geometry/vertices row " + std::to_string(row)) &&
                        Contains("outside face") && Contains("of block 1 "));
  }
  // The VTU export's reader (io/geometry_stream.hpp): the same runs and checks, nothing held.
  const auto vtu_of_read_blocks = [&](const std::filesystem::path& p) {
    slice::write_blocks_vtu(dir / "held.vtu", slice::read_blocks(p));
    return test::read_bytes(dir / "held.vtu");
  };
  SECTION("streamed for the VTU export: the runs and rows read_blocks reads, the same VTU") {
    const auto p = written(0);
    slice::Geometry joined;
    joined.vertex_offset = {0};
    joined.face_vertex_offset = {0};
    std::size_t runs = 0;
    const auto stream =
        slice::GeometryStream::open(p, [&](const slice::BlockSystem& bs, const slice::Geometry& run,
                                           const slice::GeometryBase& base, std::size_t n) {
          CHECK(bs.blocks.size() == grid.blocks.size());
          CHECK(base.block == runs * slice::h5file::kBatch);
          CHECK(base.block == joined.volume.size());
          CHECK(base.vertex == joined.vertex_offset.back());
          ++runs;
          const auto append = [](auto& to, const auto& from) {
            to.insert(to.end(), from.begin(), from.end());
          };
          for (std::size_t b = 1; b <= n; ++b)
            joined.vertex_offset.push_back(base.vertex + run.vertex_offset[b]);
          for (std::size_t f = 1; f < run.face_vertex_offset.size(); ++f)
            joined.face_vertex_offset.push_back(base.face_vertex + run.face_vertex_offset[f]);
          append(joined.vertices, run.vertices);
          append(joined.face_vertices, run.face_vertices);
          append(joined.volume, run.volume);
          append(joined.centroid, run.centroid);
          append(joined.inertia, run.inertia);
          append(joined.face_area, run.face_area);
          append(joined.face_joint_fraction, run.face_joint_fraction);
        });
    REQUIRE(stream);
    CHECK(runs == 2);
    check_same(g, joined);
    CHECK(stream->vertex_offset() == g.vertex_offset);
    CHECK(stream->face_vertex_offset() == g.face_vertex_offset);
    std::vector<slice::Vec3> v;
    std::vector<std::int64_t> fv;
    stream->read_vertices(8, 20, v);
    CHECK(v == std::vector<slice::Vec3>(g.vertices.begin() + 8, g.vertices.begin() + 20));
    stream->read_face_vertices(5, g.face_vertices.size(), fv);
    CHECK(fv == std::vector<std::int64_t>(g.face_vertices.begin() + 5, g.face_vertices.end()));
    // More vertices than one window of the export's reads (export_vtu.cpp's kWindowRows, 16
    // runs): it reads several.
    REQUIRE(g.vertices.size() > 16 * slice::kGeometryRun);
    slice::JointSystem js;
    const auto st = slice::export_blocks_vtu(p, dir / "streamed.vtu", slice::VtuCompressor::lz4, 2,
                                             slice::VtuIds::narrowest, &js);
    CHECK(st.cells == grid.blocks.size());
    CHECK(js.joints.size() == grid.joints.joints.size());
    CHECK(test::read_bytes(dir / "streamed.vtu") == vtu_of_read_blocks(p));
  }
  SECTION(
      "streamed, a run off by more than its own tolerance but within the file's: the file "
      "read whole, the same VTU") {
    const auto p = written(-0.5 * (run_tol + file_tol));
    CHECK_FALSE(slice::GeometryStream::open(p, {}));
    slice::export_blocks_vtu(p, dir / "streamed.vtu");
    CHECK(test::read_bytes(dir / "streamed.vtu") == vtu_of_read_blocks(p));
  }
  SECTION("streamed, spoiled past the file's tolerance or without /geometry: read_blocks' error") {
    const std::size_t row = std::size_t(g.vertex_offset[1]);
    spoil(row);
    const std::string msg = error_of([&] { slice::read_blocks(dir / "g.h5"); });
    CHECK_THAT(msg, Contains("/geometry/vertices row " + std::to_string(row)));
    CHECK(error_of([&] { slice::export_blocks_vtu(dir / "g.h5", dir / "x.vtu"); }) == msg);
    auto bare = grid;
    bare.geometry.reset();
    slice::write_blocks(dir / "bare.h5", bare, {});
    CHECK_THAT(error_of([&] { slice::export_blocks_vtu(dir / "bare.h5", dir / "x.vtu"); }),
               Contains("bare.h5") && Contains("no /geometry") && Contains("slice-vertices"));
    CHECK_FALSE(std::filesystem::exists(dir / "x.vtu"));
  }
  SECTION("bad values in both runs: the first bad block is named") {
    const std::size_t second = slice::h5file::kBatch + 7;
    for (const std::size_t spoiled : {std::size_t(3), second}) {
      slice::write_blocks(dir / "g.h5", grid, {});
      slice::h5::File f = slice::h5::File::open(dir / "g.h5", {"g.h5", ""}, true);
      const auto geo = f.root().open_group("geometry");
      auto vol = geo.read<double>("volume");
      vol[second] = 2;  // a unit cube
      vol[spoiled] = 2;
      geo.remove("volume");
      geo.write<double>("volume", vol);
      f.close();
      const std::string msg = error_of([&] { slice::read_blocks(dir / "g.h5"); });
      CHECK_THAT(msg, Contains("/geometry/volume row " + std::to_string(spoiled) + " is 2"));
    }
  }
}

TEST_CASE("the value checks take each face's tolerance from its edges' lengths",
          "[h5io][geometry]") {
  // A unit cube turned 45 degrees about z: the edges of its side faces are not along the axes
  // (the check's first, cheaper pass takes an edge's largest component for its length).
  slice::BlockSystem bs;
  bs.joints = sample().joints;
  bs.pruned = true;
  slice::Block b;
  const double c = std::sqrt(0.5);
  for (const slice::Vec3& n : {slice::Vec3(c, c, 0), slice::Vec3(-c, c, 0), slice::Vec3(-c, -c, 0),
                               slice::Vec3(c, -c, 0), slice::Vec3(0, 0, 1), slice::Vec3(0, 0, -1)})
    b.faces.push_back({n, 0.5, -1});
  b.inradius = 0.5;
  b.bsphere << 0, 0, 0, std::sqrt(0.75);
  bs.blocks.push_back(b);
  slice::compute_geometry(bs);
  slice::Geometry g = *bs.geometry;
  const double tol = 1e-3;
  REQUIRE(slice::geometry_value_problem(g, b, 0, 0, {}, tol, false).empty());
  // Face 0's perimeter is 4; its edges' largest components sum to 2 + sqrt(2) = 3.41.
  const double area = g.face_area[0];
  g.face_area[0] = area + 3.8 * tol;  // within tol x perimeter
  CHECK(slice::geometry_value_problem(g, b, 0, 0, {}, tol, false).empty());
  g.face_area[0] = area - 3.8 * tol;
  CHECK(slice::geometry_value_problem(g, b, 0, 0, {}, tol, false).empty());
  g.face_area[0] = area + 4.2 * tol;  // beyond it
  CHECK_THAT(slice::geometry_value_problem(g, b, 0, 0, {}, tol, false),
             Contains("/geometry/face_area row 0 is") && Contains("(tolerance 0.004)"));
}

// slice-export --format vtu: the files read back with VTK's own XML reader give the blocks and
// volumes of /geometry, and the joints clipped to the domain.
#include "slice/export_vtu.hpp"

#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLParser.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <catch2/catch.hpp>

#include "slice/h5io.hpp"
#include "slice/polytope.hpp"
#include "slice/vertices.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"
#include "support/vtu_read.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::read_vtu;
using test::run_tool;

namespace {

/// A cell's volume from its faces as VTK gives them (divergence theorem over a fan of each
/// face). VTK 9.1's own tetrahedralisation of polyhedra (vtkCellSizeFilter) drops tetrahedra of
/// thin cells (a rock-slope block of 9.79 m3 comes out as 5.46), so the faces are integrated,
/// relative to the cell's first point (global coordinates would cancel digits).
double cell_volume(vtkCell* cell) {
  Vec3 o;
  cell->GetPoints()->GetPoint(0, o.data());
  double v = 0;
  for (int f = 0; f < cell->GetNumberOfFaces(); ++f) {
    vtkPoints* p = cell->GetFace(f)->GetPoints();
    Vec3 a, b, c;
    p->GetPoint(0, a.data());
    for (vtkIdType k = 1; k + 1 < p->GetNumberOfPoints(); ++k) {
      p->GetPoint(k, b.data());
      p->GetPoint(k + 1, c.data());
      v += (a - o).dot((b - o).cross(c - o)) / 6;
    }
  }
  return v;
}

}  // namespace

TEST_CASE("blocks.vtu reads back with VTK: cells, data and volumes", "[tools][export][vtu]") {
  const std::string scene = GENERATE(as<std::string>{}, "cube-3sets.toml", "rock-slope.toml",
                                     "table3-persistent.toml", "tunnel.toml");
  CAPTURE(scene);
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, scene, test::Stage::geometry);
  const std::string vtu = (tmp / "blocks.vtu").string(), jvtu = (tmp / "joints.vtu").string();
  const auto r = run_tool("slice-export", {geom, "--format", "vtu", "-o", vtu, "--joints", jvtu});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto bs = slice::read_blocks(geom);
  const auto& g = *bs.geometry;

  const auto grid = read_vtu(vtu);
  std::size_t kept = 0;
  for (const auto& b : bs.blocks) kept += (b.flags & slice::kRemoved) ? 0 : 1;
  REQUIRE(std::size_t(grid->GetNumberOfCells()) == kept);
  auto* ids = grid->GetCellData()->GetArray("block_id");
  auto* volume = grid->GetCellData()->GetArray("volume");
  auto* boundary = grid->GetCellData()->GetArray("boundary");
  auto* cluster = grid->GetCellData()->GetArray("cluster");
  auto* aspect = grid->GetCellData()->GetArray("aspect_ratio");
  auto* inradius = grid->GetCellData()->GetArray("inradius");
  REQUIRE((ids && volume && boundary && cluster && aspect && inradius));
  std::size_t bad = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    REQUIRE(grid->GetCellType(c) == VTK_POLYHEDRON);
    const auto b = std::size_t(ids->GetTuple1(c));
    REQUIRE(b < bs.blocks.size());
    const auto& blk = bs.blocks[b];
    CHECK_FALSE(blk.flags & slice::kRemoved);
    CHECK(volume->GetTuple1(c) == g.volume[b]);
    CHECK(inradius->GetTuple1(c) == blk.inradius);
    CHECK(cluster->GetTuple1(c) == double(blk.cluster));
    CHECK(boundary->GetTuple1(c) == ((blk.flags & slice::kBoundary) ? 1 : 0));
    CHECK_THAT(aspect->GetTuple1(c), WithinRel(blk.bsphere[3] / blk.inradius, 1e-15));
    const double v = cell_volume(grid->GetCell(c));
    if (std::abs(v - g.volume[b]) > 1e-9 * g.volume[b]) {
      ++bad;
      UNSCOPED_INFO("block " << b << ": VTK's faces give " << v << ", /geometry " << g.volume[b]);
    }
  }
  CHECK(bad == 0);

  // joints.vtu: the joints inside the domain, every point inside the domain.
  const auto joints = read_vtu(jvtu);
  const auto& js = bs.joints;
  const double tol = js.options.tolerance * js.length_scale;
  CHECK(joints->GetNumberOfCells() > 0);
  CHECK(std::size_t(joints->GetNumberOfCells()) <= js.joints.size());
  auto* jid = joints->GetCellData()->GetArray("joint_id");
  auto* set = joints->GetCellData()->GetArray("set");
  auto* kind = joints->GetCellData()->GetArray("kind");
  REQUIRE((jid && set && kind));
  for (vtkIdType c = 0; c < joints->GetNumberOfCells(); ++c) {
    const auto j = std::size_t(jid->GetTuple1(c));
    REQUIRE(j < js.joints.size());
    CHECK(set->GetTuple1(c) == js.joints[j].set);
    CHECK(kind->GetTuple1(c) == double(static_cast<int>(js.joints[j].kind)));
    vtkCell* cell = joints->GetCell(c);
    REQUIRE(cell->GetCellType() == VTK_POLYGON);
    for (vtkIdType k = 0; k < cell->GetNumberOfPoints(); ++k) {
      Vec3 x;
      cell->GetPoints()->GetPoint(k, x.data());
      CHECK(std::abs(js.joints[j].plane.distance(x)) <= tol);
      for (const auto& p : js.domain.planes) CHECK(p.distance(x) <= tol);
    }
  }
  if (scene == "cube-3sets.toml") {  // 27 persistent joints, each a 10 m x 10 m square
    REQUIRE(joints->GetNumberOfCells() == 27);
    for (vtkIdType c = 0; c < 27; ++c) {
      std::vector<Vec3> poly;
      vtkCell* cell = joints->GetCell(c);
      for (vtkIdType k = 0; k < cell->GetNumberOfPoints(); ++k) {
        Vec3 x;
        cell->GetPoints()->GetPoint(k, x.data());
        poly.push_back(x);
      }
      CHECK_THAT(slice::newell_normal(poly).norm() / 2, WithinRel(100, 1e-12));
    }
  }
}

TEST_CASE("slice-export vtu: reruns give the same bytes -- bad input is refused",
          "[tools][export][vtu]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "rock-slope.toml", test::Stage::geometry);
  const std::string a = (tmp / "a.vtu").string(), b = (tmp / "b.vtu").string();
  REQUIRE(run_tool("slice-export", {geom, "-o", a}).exit_code == 0);
  REQUIRE(run_tool("slice-export", {geom, "-o", b}).exit_code == 0);
  CHECK(test::read_bytes(a) == test::read_bytes(b));

  SECTION("blocks without /geometry") {
    const auto r = run_tool("slice-export", {(tmp / "blocks.h5").string(), "-o", a});
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("blocks.h5") && Contains("slice-vertices"));
  }
  SECTION("an unknown format") {
    const auto r = run_tool("slice-export", {geom, "--format", "stl", "-o", a});
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("stl"));
  }
  SECTION("a missing output directory leaves nothing behind") {
    const auto r = run_tool("slice-export", {geom, "-o", (tmp / "no" / "x.vtu").string()});
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("does not exist"));
  }
}

TEST_CASE("slice-export vtu: every compressor reads back the same -- an unknown one is refused",
          "[tools][export][vtu]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "rock-slope.toml", test::Stage::geometry);
  std::vector<double> volumes[3];
  const char* names[] = {"lz4", "zlib", "none"};
  const char* classes[] = {"vtkLZ4DataCompressor", "vtkZLibDataCompressor", nullptr};
  for (int k = 0; k < 3; ++k) {
    CAPTURE(names[k]);
    const std::string vtu = (tmp / (std::string(names[k]) + ".vtu")).string();
    const auto r = run_tool("slice-export", {geom, "-o", vtu, "--vtu-compressor", names[k]});
    REQUIRE(r.exit_code == 0);
    const std::string bytes = test::read_bytes(vtu);
    const auto header = bytes.substr(0, 400);
    if (classes[k])
      CHECK_THAT(header, Contains(std::string("compressor=\"") + classes[k]));
    else
      CHECK_THAT(header, !Contains("compressor="));
    const auto grid = read_vtu(vtu);
    auto* v = grid->GetCellData()->GetArray("volume");
    REQUIRE(v != nullptr);
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) volumes[k].push_back(v->GetTuple1(c));
  }
  CHECK(volumes[0].size() > 10);
  CHECK(volumes[0] == volumes[1]);
  CHECK(volumes[0] == volumes[2]);
  const auto r =
      run_tool("slice-export", {geom, "-o", (tmp / "x.vtu").string(), "--vtu-compressor", "lzma"});
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains("--vtu-compressor") && Contains("lzma") && Contains("lz4"));
  CHECK_FALSE(test::fs::exists(tmp / "x.vtu"));
}

TEST_CASE("slice-export vtu: blocks and joints are well-formed XML text from end to end",
          "[tools][export][vtu]") {
  // Raw binary data in the file (appended, as VTK's writer puts it by default) stop ParaView
  // 5.11's reader with Debian 12's current expat; the data are base64 in each DataArray.
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "rock-slope.toml", test::Stage::geometry);
  for (const char* c : {"lz4", "zlib", "none"}) {
    CAPTURE(c);
    const std::string blocks = (tmp / "blocks.vtu").string(),
                      joints = (tmp / "joints.vtu").string();
    REQUIRE(
        run_tool("slice-export", {geom, "-o", blocks, "--joints", joints, "--vtu-compressor", c})
            .exit_code == 0);
    for (const std::string& file : {blocks, joints}) {
      CAPTURE(file);
      const std::string bytes = test::read_bytes(file);
      const auto binary = std::find_if(bytes.begin(), bytes.end(),
                                       [](char b) { return b != '\n' && (b < 0x20 || b > 0x7e); });
      CHECK(binary == bytes.end());
      CHECK_THAT(bytes, !Contains("AppendedData") && !Contains("format=\"appended\""));
      std::size_t inline_arrays = 0;  // DataArrays with their data inline, as base64
      for (auto at = bytes.find("format=\"binary\""); at != std::string::npos;
           at = bytes.find("format=\"binary\"", at + 1))
        ++inline_arrays;
      CHECK(inline_arrays >= (file == blocks ? 13u : 9u));
      // VTK's plain XML parser (expat, no stop at appended data) reads the whole file.
      vtkNew<vtkXMLParser> parser;
      parser->SetFileName(file.c_str());
      CHECK(parser->Parse() == 1);
      CHECK(read_vtu(file)->GetNumberOfCells() > 10);
    }
  }
}

TEST_CASE("slice-export vtu: the same bytes on 1 and 2 threads, for every compressor",
          "[tools][export][vtu][threads]") {
  // 21,108 blocks: every array spans several batches of compressed blocks.
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "table3-persistent.toml", test::Stage::geometry);
  for (const char* c : {"lz4", "zlib", "none"}) {
    CAPTURE(c);
    const std::string one = (tmp / "one.vtu").string(), two = (tmp / "two.vtu").string();
    REQUIRE(run_tool("slice-export", {geom, "-o", one, "--vtu-compressor", c, "--threads", "1"})
                .exit_code == 0);
    REQUIRE(run_tool("slice-export", {geom, "-o", two, "--vtu-compressor", c, "--threads", "2"})
                .exit_code == 0);
    CHECK(test::read_bytes(one) == test::read_bytes(two));
    CHECK(read_vtu(two)->GetNumberOfCells() == 21108);
  }
}

TEST_CASE("slice-export vtu: a model whose blocks are all removed gives an empty grid",
          "[tools][export][vtu]") {
  test::TempDir tmp;
  const std::string scene = test::read_bytes(test::data_path("cube-3sets.toml")) +
                            "\n[[zones]]\nbox = { min = [-1, -1, -1], max = [11, 11, 11] }\n";
  test::write_text(tmp / "all.toml", scene);
  const auto j = (tmp / "j.h5").string(), b = (tmp / "b.h5").string(), g = (tmp / "g.h5").string();
  REQUIRE(run_tool("slice-joints", {(tmp / "all.toml").string(), "-o", j}).exit_code == 0);
  REQUIRE(run_tool("slice-cut", {j, "-o", b, "--prune"}).exit_code == 0);
  REQUIRE(run_tool("slice-vertices", {b, "-o", g}).exit_code == 0);
  for (const char* c : {"lz4", "zlib", "none"}) {
    CAPTURE(c);
    const std::string vtu = (tmp / (std::string(c) + ".vtu")).string();
    const auto r = run_tool("slice-export", {g, "-o", vtu, "--vtu-compressor", c});
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.err, Contains("0 blocks (1000 removed left out)"));
    const auto grid = read_vtu(vtu);
    CHECK(grid->GetNumberOfCells() == 0);
    CHECK(grid->GetNumberOfPoints() == 0);
    CHECK(grid->GetCellData()->GetArray("volume") != nullptr);
  }
}

TEST_CASE("blocks.vtu: Int32 cell arrays where they fit, read back as the Int64 ones",
          "[export][vtu]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "rock-slope.toml", test::Stage::geometry);
  const auto bs = slice::read_blocks(geom);
  const std::string narrow = (tmp / "narrow.vtu").string(), wide = (tmp / "wide.vtu").string();
  slice::write_blocks_vtu(narrow, bs);  // slice-export's choice
  slice::write_blocks_vtu(wide, bs, slice::VtuCompressor::lz4, 0, slice::VtuIds::int64);
  // The XML names each array's type; the block ids and clusters are Int64 in both.
  const auto header = [](const std::string& file) { return test::read_bytes(file); };
  for (const std::string name : {"connectivity", "offsets", "faces", "faceoffsets"}) {
    CAPTURE(name);
    // The polyhedra's arrays say they hold ids (IdType="1").
    const std::string id = name.starts_with("face") ? " IdType=\"1\"" : "";
    CHECK_THAT(header(narrow), Contains("type=\"Int32\"" + id + " Name=\"" + name + "\""));
    CHECK_THAT(header(wide), Contains("type=\"Int64\"" + id + " Name=\"" + name + "\""));
  }
  CHECK_THAT(header(narrow), Contains("type=\"Int64\" Name=\"block_id\""));
  const auto a = read_vtu(narrow), b = read_vtu(wide);
  REQUIRE(a->GetNumberOfCells() == b->GetNumberOfCells());
  REQUIRE(a->GetNumberOfCells() > 10);
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c) {
    vtkCell* x = a->GetCell(c);
    vtkCell* y = b->GetCell(c);
    REQUIRE(x->GetNumberOfPoints() == y->GetNumberOfPoints());
    REQUIRE(x->GetNumberOfFaces() == y->GetNumberOfFaces());
    for (vtkIdType k = 0; k < x->GetNumberOfPoints(); ++k)
      CHECK(x->GetPointId(k) == y->GetPointId(k));
    for (int f = 0; f < x->GetNumberOfFaces(); ++f) {
      REQUIRE(x->GetFace(f)->GetNumberOfPoints() == y->GetFace(f)->GetNumberOfPoints());
      for (vtkIdType k = 0; k < x->GetFace(f)->GetNumberOfPoints(); ++k)
        CHECK(x->GetFace(f)->GetPointId(k) == y->GetFace(f)->GetPointId(k));
    }
    CHECK(cell_volume(x) == cell_volume(y));
  }
}

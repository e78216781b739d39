// The exports of a 2-D section (docs/2d.md), on sections made in code (tests/support/section.hpp):
// blocks.vtu and joints.vtu read back with VTK's own reader give the polygons, areas and joint
// lines; the YADE model of prisms runs in Debian's real YADE (yade -n -x) and its bodies stay in
// the section; PotentialBlock and 3DEC exports of a section are refused.
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "slice/export_3dec.hpp"
#include "slice/export_vtu.hpp"
#include "slice/export_yade.hpp"
#include "slice/vertices.hpp"
#include "support/section.hpp"
#include "support/support.hpp"
#include "support/vtu_read.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::read_vtu;

namespace {

// A 20 m x 10 m section cut by `lines` random lines, with geometry.
test::Section random_section(std::uint64_t seed, int lines) {
  std::uint64_t state = seed;
  std::vector<slice::Joint> joints;
  for (int k = 0; k < lines; ++k)
    joints.push_back(test::section_joint(
        360 * test::uniform(state), Vec3(20 * test::uniform(state), 0, 10 * test::uniform(state))));
  auto sec = test::cut_section(test::section_system(Vec3(0, 0, 0), Vec3(20, 0, 10), joints), 0.05);
  slice::compute_geometry(sec.bs);
  return sec;
}

}  // namespace

TEST_CASE("2-D: blocks.vtu of a section reads back with VTK as its polygons",
          "[tools][export][vtu][2d]") {
  const auto seed = GENERATE(range(1u, 6u));
  const auto compressor = GENERATE(slice::VtuCompressor::lz4, slice::VtuCompressor::none);
  CAPTURE(seed, int(compressor));
  auto sec = random_section(seed, 10);
  auto& bs = sec.bs;
  REQUIRE(bs.blocks.size() > 5);
  bs.blocks[1].flags |= slice::kRemoved;  // left out
  bs.blocks[2].flags |= slice::kBoundary;
  bs.blocks[3].cluster = 7;
  const auto& g = *bs.geometry;
  test::TempDir tmp;
  const std::string vtu = (tmp / "blocks.vtu").string();
  const auto st = slice::write_blocks_vtu(vtu, bs, compressor, 2);
  CHECK(st.skipped == 1);
  CHECK_FALSE(test::fs::exists(vtu + ".partial"));
  // slice-export's way, from the file without holding /geometry: the same bytes.
  slice::write_blocks(tmp / "geom.h5", bs, {});
  slice::export_blocks_vtu(tmp / "geom.h5", tmp / "streamed.vtu", compressor, 1);
  CHECK(test::read_bytes(tmp / "streamed.vtu") == test::read_bytes(vtu));

  const auto grid = read_vtu(vtu);
  REQUIRE(std::size_t(grid->GetNumberOfCells()) == bs.blocks.size() - 1);
  CHECK(st.cells == bs.blocks.size() - 1);
  auto* ids = grid->GetCellData()->GetArray("block_id");
  auto* volume = grid->GetCellData()->GetArray("volume");
  auto* boundary = grid->GetCellData()->GetArray("boundary");
  auto* cluster = grid->GetCellData()->GetArray("cluster");
  REQUIRE(ids);
  REQUIRE(volume);
  REQUIRE(boundary);
  REQUIRE(cluster);
  REQUIRE(grid->GetCellData()->GetArray("inradius"));
  REQUIRE(grid->GetCellData()->GetArray("fixed"));
  REQUIRE(grid->GetCellData()->GetArray("aspect_ratio"));
  double total = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    CAPTURE(c);
    const auto b = std::size_t(ids->GetTuple1(c));
    REQUIRE(b < bs.blocks.size());
    CHECK(b != 1);
    vtkCell* cell = grid->GetCell(c);
    REQUIRE(cell->GetCellType() == VTK_POLYGON);
    const auto v0 = std::size_t(g.vertex_offset[b]);
    const auto nv = std::size_t(g.vertex_offset[b + 1]) - v0;
    REQUIRE(std::size_t(cell->GetNumberOfPoints()) == nv);
    REQUIRE(nv == sec.polygons[b].size());
    // The points are the polygon's, in its order (counter-clockwise in (x, z)), at y = 0.
    std::vector<Vec3> pts(nv);
    for (std::size_t k = 0; k < nv; ++k) {
      cell->GetPoints()->GetPoint(vtkIdType(k), pts[k].data());
      CHECK(pts[k] == g.vertices[v0 + k]);
      CHECK(pts[k].y() == 0);
    }
    const double area = test::twice_area_xz(pts) / 2;
    CHECK(area > 0);
    CHECK_THAT(area, WithinRel(test::twice_area_xz(sec.polygons[b]) / 2, 1e-9));
    CHECK(volume->GetTuple1(c) == g.volume[b]);
    CHECK_THAT(area, WithinRel(g.volume[b], 1e-9));  // about the global origin: digits lost
    CHECK(boundary->GetTuple1(c) == (b == 2 ? 1 : 0));
    CHECK(cluster->GetTuple1(c) == (b == 3 ? 7 : -1));
    total += area;
  }
  CHECK_THAT(total + g.volume[1], WithinRel(200, 1e-12));  // the domain, the removed block too
}

TEST_CASE("2-D: joints.vtu of a section has one line per joint, clipped to the domain",
          "[tools][export][vtu][2d]") {
  // Box [0, 20] x [0, 10]: z = 3 (persistent) crosses it whole; a line rising at 30 degrees
  // through (10, 5) leaves at z = 0 and z = 10; x = 5 as a segment from z = -2 to z = 4 keeps z in
  // [0, 4]; a segment of it inside the box stays whole; z = 12 misses the box.
  const double t30 = std::tan(30 * M_PI / 180);
  const auto x5 = test::section_joint(0, Vec3(5, 0, 0));
  const std::vector<slice::Joint> joints = {
      test::section_joint(90, Vec3(0, 0, 3)),
      test::section_joint(120, Vec3(10, 0, 5)),  // normal (-1/2, sqrt 3/2): slope tan 30
      test::segment_joint(x5, Vec3(5, 0, -2), Vec3(5, 0, 4)),
      test::segment_joint(x5, Vec3(5, 0, 6), Vec3(5, 0, 7)),
      test::section_joint(90, Vec3(0, 0, 12))};
  const auto js = test::section_system(Vec3(0, 0, 0), Vec3(20, 0, 10), joints);
  const std::vector<std::pair<Vec3, Vec3>> want = {{{0, 0, 3}, {20, 0, 3}},
                                                   {{10 - 5 / t30, 0, 0}, {10 + 5 / t30, 0, 10}},
                                                   {{5, 0, 0}, {5, 0, 4}},
                                                   {{5, 0, 6}, {5, 0, 7}}};
  test::TempDir tmp;
  const std::string vtu = (tmp / "joints.vtu").string();
  const auto st = slice::write_joints_vtu(vtu, js);
  CHECK(st.cells == 4);
  CHECK(st.skipped == 1);
  const auto grid = read_vtu(vtu);
  REQUIRE(grid->GetNumberOfCells() == 4);
  auto* ids = grid->GetCellData()->GetArray("joint_id");
  auto* persistent = grid->GetCellData()->GetArray("persistent");
  REQUIRE(ids);
  REQUIRE(persistent);
  for (vtkIdType c = 0; c < 4; ++c) {
    CAPTURE(c);
    CHECK(ids->GetTuple1(c) == double(c));
    CHECK(persistent->GetTuple1(c) == (c < 2 ? 1 : 0));
    vtkCell* cell = grid->GetCell(c);
    REQUIRE(cell->GetCellType() == VTK_LINE);
    REQUIRE(cell->GetNumberOfPoints() == 2);
    Vec3 a, b;
    cell->GetPoints()->GetPoint(0, a.data());
    cell->GetPoints()->GetPoint(1, b.data());
    CHECK(a.y() == 0);
    CHECK(b.y() == 0);
    const auto& [p, q] = want[std::size_t(c)];
    // Either direction along the line.
    const double d = std::min((a - p).norm() + (b - q).norm(), (a - q).norm() + (b - p).norm());
    CHECK_THAT(d, WithinAbs(0, 1e-12));
  }
}

TEST_CASE("2-D: the YADE model of prisms runs in YADE and stays in the section",
          "[tools][export][yade][2d]") {
  auto sec = random_section(3, 8);
  auto& bs = sec.bs;
  const auto& g = *bs.geometry;
  // Blocks on the bottom are fixed; two others form a clump; one is removed.
  std::size_t fixed = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b)
    for (const Vec3& x : sec.polygons[b])
      if (x.z() < 1e-9) {
        bs.blocks[b].flags |= slice::kFixed;
        ++fixed;
        break;
      }
  REQUIRE(fixed > 0);
  std::vector<std::size_t> free;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b)
    if (!(bs.blocks[b].flags & slice::kFixed)) free.push_back(b);
  REQUIRE(free.size() >= 4);
  bs.blocks[free[0]].cluster = 0;
  bs.blocks[free[1]].cluster = 0;
  bs.blocks[free[2]].flags |= slice::kRemoved;

  test::TempDir tmp;
  const std::string model = (tmp / "model.py").string(), report = (tmp / "report.json").string();
  slice::YadeOptions opt;
  opt.steps = 20;
  const auto st = slice::write_yade_script(model, bs, opt);
  CHECK(st.bodies == bs.blocks.size() - 1);
  CHECK(st.clumps == 1);
  const int code = test::run_yade_report(model, report, tmp / "yade.log");
  INFO("yade log (tail): " << test::tail_of(tmp / "yade.log"));
  REQUIRE(code == 0);
  const auto r = nlohmann::json::parse(test::read_bytes(report));
  REQUIRE_FALSE(r.contains("error"));
  CHECK(r["iterations"] == 20);
  const auto& bodies = r["bodies"];
  CHECK(bodies.size() == st.bodies + 1);  // and the clump
  REQUIRE(r["body_of_block"].size() == st.bodies);
  std::size_t moved = 0;
  for (const auto& [key, id] : r["body_of_block"].items()) {
    const auto b = std::size_t(std::stoll(key));
    CAPTURE(b);
    const auto& body = bodies.at(id.get<std::size_t>());
    // YADE's volume and mass of the prism built from the vertices: area x unit thickness, the
    // prism scaled by 1 - initial_gap about its centroid (export_yade_test.cpp), its mass kept.
    const double shrunk = std::pow(1 - r["initial_gap"].get<double>(), 3);
    CHECK_THAT(body["volume"].get<double>(), WithinRel(shrunk * g.volume[b], 1e-9));
    const auto c = body["clump"].get<std::int64_t>();
    if (c < 0) CHECK_THAT(body["mass"].get<double>(), WithinRel(2650 * g.volume[b], 1e-9));
    const auto& holder = c >= 0 ? bodies.at(std::size_t(c)) : body;
    const bool is_fixed = bs.blocks[b].flags & slice::kFixed;
    CHECK(holder["blocked"] == (is_fixed ? "xyzXYZ" : "yXZ"));
    Vec3 p;
    for (std::size_t k = 0; k < 3; ++k) p[Eigen::Index(k)] = body["pos"][k].get<double>();
    CHECK(std::abs(p.y()) <= 1e-12);  // in the section
    // The prism's centroid is the polygon's; gravity moves the free ones down, in (x, z).
    if (is_fixed) CHECK((p - g.centroid[b]).norm() <= 1e-12 * 20);
    moved += !is_fixed && p.z() < g.centroid[b].z() ? 1 : 0;
  }
  CHECK(moved > 0);
}

TEST_CASE("2-D: PotentialBlock and 3DEC exports refuse a section, saying so",
          "[tools][export][2d]") {
  auto sec = random_section(1, 4);
  test::TempDir tmp;
  slice::YadeOptions pb;
  pb.shape = slice::YadeShape::potential_blocks;
  const auto e1 = test::error_of([&] { slice::write_yade_script(tmp / "pb.py", sec.bs, pb); });
  CHECK_THAT(e1, Contains("2-D section") && Contains("--format yade"));
  const auto e2 =
      test::error_of([&] { slice::write_3dec(tmp / "grid.3ddat", tmp / "run.dat", sec.bs); });
  CHECK_THAT(e2, Contains("2-D section") && Contains("3-D only"));
  CHECK(test::fs::is_empty(tmp.path()));  // nothing written, no .partial
}

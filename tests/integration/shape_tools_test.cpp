// Block shape (issue 26 item 5, docs/block-shape.md) with the real tools: slice-info's summary by
// shape class on data/ scenes, pipelines/plot's block shape diagram, and the numpy factors of
// pipelines/plot against the library's, block by block.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "slice/h5io.hpp"
#include "slice/shape.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using test::run_tool;

namespace {

nlohmann::json info_json(const std::string& file) {
  const auto r = run_tool("slice-info", {file, "--json"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return nlohmann::json::parse(r.out);
}

// The kept blocks' classes add up to the kept volume and block count of the file, for MBSCT's
// classes ("by_class") and UnBlocks-gen's on beta_k ("by_class_kalenchuk").
void check_adds_up(const nlohmann::json& j, const char* key = "by_class") {
  const auto& s = j["shape"];
  REQUIRE(s.is_object());
  REQUIRE(s[key].size() == slice::kShapeClasses.size());
  double volume = 0;
  std::size_t blocks = 0;
  for (const auto& c : s[key]) {
    volume += c["volume"].get<double>();
    blocks += c["blocks"].get<std::size_t>();
  }
  const double kept =
      j["geometry"]["volume"].get<double>() - j["geometry"]["removed_volume"].get<double>();
  CHECK_THAT(s["volume"].get<double>(), WithinRel(kept, 1e-12));
  CHECK_THAT(volume, WithinRel(kept, 1e-12));
  CHECK(blocks == s["blocks"].get<std::size_t>());
  CHECK(blocks ==
        j["blocks"]["total"].get<std::size_t>() - j["blocks"]["removed"].get<std::size_t>());
}

}  // namespace

TEST_CASE("slice-info: 1000 unit cubes are all of class C", "[tools][block-shape]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::geometry);
  const auto j = info_json(geom);
  check_adds_up(j);
  const auto& c = j["shape"]["by_class"][0];
  CHECK(c["class"] == "C");
  CHECK(c["blocks"] == 1000);
  CHECK_THAT(c["volume"].get<double>(), WithinRel(1000, 1e-12));
  CHECK_THAT(c["volume_fraction"].get<double>(), WithinAbs(1, 1e-12));
  // UnBlocks-gen's classes on beta_k: C too (alpha 0.999 < 2, beta_k 10/9 < 4).
  check_adds_up(j, "by_class_kalenchuk");
  CHECK(j["shape"]["by_class_kalenchuk"][0]["class"] == "C");
  CHECK(j["shape"]["by_class_kalenchuk"][0]["blocks"] == 1000);
  // Kalenchuk's beta of a cube, 10/9 (docs/block-shape.md), for every block.
  const auto& bk = j["shape"]["beta_kalenchuk"];
  CHECK(bk["blocks"] == 1000);
  CHECK_THAT(bk["min"].get<double>(), WithinRel(10.0 / 9, 1e-9));
  CHECK_THAT(bk["max"].get<double>(), WithinRel(10.0 / 9, 1e-9));
  // The text form says the same.
  const auto t = run_tool("slice-info", {geom});
  REQUIRE(t.exit_code == 0);
  CHECK_THAT(t.out, Contains("class=\"C\" blocks=1000"));
}

TEST_CASE("slice-info: a tunnel scene's classes add up to the kept volume",
          "[tools][block-shape]") {
  // tunnel.toml removes the blocks in the tunnel: they are left out of the classes.
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "tunnel.toml", test::Stage::geometry);
  const auto j = info_json(geom);
  REQUIRE(j["blocks"]["removed"].get<int>() > 0);
  check_adds_up(j);
  check_adds_up(j, "by_class_kalenchuk");
  // A stochastic rock mass has blocks of many shapes: at least four classes hold some.
  int classes = 0;
  for (const auto& c : j["shape"]["by_class"]) classes += c["blocks"].get<int>() > 0 ? 1 : 0;
  CHECK(classes >= 4);
  // The library's own summary of the same file agrees.
  const auto bs = slice::read_blocks(geom);
  const auto shapes = slice::block_shapes(bs.blocks, *bs.geometry);
  std::vector<bool> keep;
  for (const auto& b : bs.blocks) keep.push_back((b.flags & slice::kRemoved) == 0);
  const auto s = slice::summarise_shapes(shapes, bs.geometry->volume, keep);
  const auto k = slice::summarise_shapes(shapes, bs.geometry->volume, keep, true);
  int classes_k = 0;
  for (std::size_t c = 0; c < s.count.size(); ++c) {
    CHECK(j["shape"]["by_class"][c]["blocks"] == s.count[c]);
    CHECK(j["shape"]["by_class_kalenchuk"][c]["blocks"] == k.count[c]);
    CHECK_THAT(j["shape"]["by_class_kalenchuk"][c]["volume"].get<double>(),
               WithinAbs(k.volume[c], 1e-9 * j["shape"]["volume"].get<double>()));
    classes_k += k.count[c] > 0 ? 1 : 0;
  }
  CHECK(classes_k >= 4);
}

TEST_CASE("slice-info: a 2-D section has no shape summary", "[tools][block-shape]") {
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "vajont-section.toml", test::Stage::geometry);
  const auto j = info_json(geom);
  CHECK(j["dimension"] == 2);
  CHECK(j["shape"].is_null());
}

TEST_CASE("pipelines/plot draws the block shape diagram, and its factors are the library's",
          "[tools][block-shape][plot]") {
  // pipelines/setup installs h5py and matplotlib: without them this test fails, not skips.
  REQUIRE(test::run_shell("/usr/bin/python3 -c 'import h5py, matplotlib' >/dev/null 2>&1") == 0);
  test::TempDir tmp;
  const auto geom = test::run_pipeline(tmp, "tunnel.toml", test::Stage::geometry);
  const std::string plot = (test::data_path("..") / "pipelines" / "plot").string();
  const auto png = tmp / "png";
  REQUIRE(test::run_shell("/usr/bin/python3 " + test::shell_quote(plot) + " " +
                          test::shell_quote(geom) + " -o " + test::shell_quote(png) +
                          " 2>/dev/null") == 0);
  for (const char* name : {"geom-shape.png", "geom-shape-kalenchuk.png"}) {
    const std::string bytes = test::read_bytes(png / name);
    REQUIRE(bytes.size() > 10000);
    CHECK(bytes.substr(1, 3) == "PNG");
  }
  // Block by block, plot's numpy alpha, beta and beta_k and both classes are the library's.
  const auto out = tmp / "factors.txt";
  const std::string script =
      "import importlib.machinery as m, importlib.util as u, h5py, sys\n"
      "l = m.SourceFileLoader('plot', sys.argv[1])\n"
      "p = u.module_from_spec(u.spec_from_loader('plot', l)); l.exec_module(p)\n"
      "s, _ = p.block_shapes(h5py.File(sys.argv[2], 'r'))\n"
      "for r in zip(s['alpha'], s['beta'], s['class'], s['beta_k'], s['class_kalenchuk']):\n"
      "    print(*map(str, r))\n";
  test::write_text(tmp / "factors.py", script);
  REQUIRE(test::run_shell("/usr/bin/python3 " + test::shell_quote(tmp / "factors.py") + " " +
                          test::shell_quote(plot) + " " + test::shell_quote(geom) + " > " +
                          test::shell_quote(out)) == 0);
  const auto bs = slice::read_blocks(geom);
  const auto shapes = slice::block_shapes(bs.blocks, *bs.geometry);
  std::istringstream in(test::read_bytes(out));
  std::size_t n = 0;
  double a = 0, b = 0, bk = 0;
  std::string c, ck;
  while (in >> a >> b >> c >> bk >> ck) {
    REQUIRE(n < shapes.size());
    CAPTURE(n);
    CHECK_THAT(a, WithinRel(shapes[n].alpha, 1e-12));
    CHECK_THAT(b, WithinAbs(shapes[n].beta, 1e-12));
    CHECK(c == slice::to_string(shapes[n].shape));
    CHECK_THAT(bk, WithinRel(shapes[n].beta_k, 1e-12));
    CHECK(ck == slice::to_string(shapes[n].shape_k));
    ++n;
  }
  CHECK(n == shapes.size());
  // Blocks without /geometry: no diagram, said so, exit 0.
  const auto blocks = test::run_pipeline(tmp, "cube-3sets.toml", test::Stage::blocks);
  const auto r = test::run_shell("/usr/bin/python3 " + test::shell_quote(plot) + " " +
                                 test::shell_quote(blocks) + " -o " + test::shell_quote(png) +
                                 " 2> " + test::shell_quote(tmp / "err.txt"));
  CHECK(r == 0);
  CHECK_THAT(test::read_bytes(tmp / "err.txt"), Contains("no shape diagram: no /geometry"));
  CHECK_FALSE(test::fs::exists(png / "blocks-shape.png"));
  CHECK_FALSE(test::fs::exists(png / "blocks-shape-kalenchuk.png"));
  // A 2-D section: likewise.
  const auto section = test::run_pipeline(tmp, "vajont-section.toml", test::Stage::geometry);
  CHECK(test::run_shell("/usr/bin/python3 " + test::shell_quote(plot) + " " +
                        test::shell_quote(section) + " -o " + test::shell_quote(png) + " 2> " +
                        test::shell_quote(tmp / "err.txt")) == 0);
  CHECK_THAT(test::read_bytes(tmp / "err.txt"), Contains("no shape diagram: a 2-D section"));
}

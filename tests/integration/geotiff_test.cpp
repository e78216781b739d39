// [[zones]] surface = "dtm.tif": GeoTIFF ground surfaces through GDAL (docs/topography.md,
// "GeoTIFF"), through the real tools. The GeoTIFFs are written here with GDAL's C API, each next
// to the same grid as ESRI ASCII: the two keep the same rock to the bit (the same blocks, faces
// and zone mesh), and the kept volume is the volume under the surface, computed triangle by
// triangle from the test's own heights (or in closed form for a plane). GeoTIFFs that do not fit
// the scene are refused with exit 1 and one line.
#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/hash.hpp"
#include "slice/surface.hpp"
#include "slice/vertices.hpp"
#include "support/compare.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"
#include "support/surface_volume.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::column_volume;
using test::run_tool;

namespace {

using Tri = std::array<Vec3, 3>;

std::string g17(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// A grid of heights and how to write it: as ESRI ASCII (xllcorner, yllcorner) and as a GeoTIFF
// whose geotransform puts the north-west cell's outer corner at (x0, y0 + rows x cell).
struct Raster {
  std::vector<std::vector<double>> z;  // [row from the north][column]
  double x0 = -2.5, y0 = -2.5;         // the south-west outer corner
  double cell = 5;
  double nodata = -9999;  // in the .asc; the GeoTIFF's no-data value is Tif::nodata
  std::size_t rows() const { return z.size(); }
  std::size_t cols() const { return z[0].size(); }
  double height(std::size_t row, std::size_t col) const { return z[row][col]; }

  std::string asc() const {
    std::ostringstream s;
    s << "ncols " << cols() << "\nnrows " << rows() << "\nxllcorner " << g17(x0) << "\nyllcorner "
      << g17(y0) << "\ncellsize " << g17(cell) << "\nNODATA_value " << g17(nodata) << "\n";
    for (const auto& row : z) {
      for (const double v : row) s << " " << g17(v);
      s << "\n";
    }
    return s.str();
  }
  // The triangles (SW-NE diagonals) of the cells between centres inside the plan [lo, hi].
  std::vector<Tri> triangles(const slice::Vec2& lo, const slice::Vec2& hi) const {
    const auto at = [&](std::size_t row, std::size_t col) {
      return Vec3(x0 + cell / 2 + cell * double(col),
                  y0 + cell / 2 + cell * double(rows() - 1 - row), z[row][col]);
    };
    std::vector<Tri> out;
    for (std::size_t row = 0; row + 1 < rows(); ++row)
      for (std::size_t col = 0; col + 1 < cols(); ++col) {
        const Vec3 sw = at(row + 1, col), se = at(row + 1, col + 1), ne = at(row, col + 1),
                   nw = at(row, col);
        if (sw.x() < lo.x() || sw.y() < lo.y() || ne.x() > hi.x() || ne.y() > hi.y()) continue;
        out.push_back({sw, se, ne});
        out.push_back({sw, ne, nw});
      }
    return out;
  }
};

// How a GeoTIFF is written.
struct Tif {
  GDALDataType type = GDT_Float64;
  std::vector<std::string> options;  // GTiff creation options: COMPRESS=..., TILED=YES, ...
  std::string srs = "EPSG:32633";    // "" for none
  bool point = false;                // AREA_OR_POINT=Point: the tie point is a cell centre
  std::optional<double> nodata = -9999.0;
  int bands = 1;
  std::string unit;                         // the band's unit type
  std::optional<std::array<double, 6>> gt;  // else from the raster; {} = none written
  bool no_gt = false;
  double scale = 1;
  std::vector<std::array<int, 2>> masked;  // (row, column) of cells an internal mask hides
};

Tif tif_of(GDALDataType type, std::vector<std::string> options, std::string srs = "EPSG:32633") {
  Tif t;
  t.type = type;
  t.options = std::move(options);
  t.srs = std::move(srs);
  return t;
}

// Writes `r` as a GeoTIFF with GDAL's GTiff driver.
void write_tif(const test::fs::path& file, const Raster& r, const Tif& t) {
  GDALAllRegister();
  GDALDriverH drv = GDALGetDriverByName("GTiff");
  REQUIRE(drv);
  std::vector<char*> opts;
  for (const auto& o : t.options) opts.push_back(const_cast<char*>(o.c_str()));
  opts.push_back(nullptr);
  const int w = int(r.cols()), h = int(r.rows());
  GDALDatasetH ds = GDALCreate(drv, file.c_str(), w, h, t.bands, t.type, opts.data());
  REQUIRE(ds);
  if (t.point) REQUIRE(GDALSetMetadataItem(ds, "AREA_OR_POINT", "Point", nullptr) == CE_None);
  std::array<double, 6> gt = {r.x0, r.cell, 0, r.y0 + r.cell * double(h), 0, -r.cell};
  if (t.gt) gt = *t.gt;
  if (!t.no_gt) REQUIRE(GDALSetGeoTransform(ds, gt.data()) == CE_None);
  if (!t.srs.empty()) {
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    REQUIRE(OSRSetFromUserInput(srs, t.srs.c_str()) == OGRERR_NONE);
    REQUIRE(GDALSetSpatialRef(ds, srs) == CE_None);
    OSRDestroySpatialReference(srs);
  }
  std::vector<double> v;
  for (const auto& row : r.z) v.insert(v.end(), row.begin(), row.end());
  for (int b = 1; b <= t.bands; ++b) {
    GDALRasterBandH band = GDALGetRasterBand(ds, b);
    if (t.nodata) REQUIRE(GDALSetRasterNoDataValue(band, *t.nodata) == CE_None);
    if (!t.unit.empty()) REQUIRE(GDALSetRasterUnitType(band, t.unit.c_str()) == CE_None);
    if (t.scale != 1) REQUIRE(GDALSetRasterScale(band, t.scale) == CE_None);
    REQUIRE(GDALRasterIO(band, GF_Write, 0, 0, w, h, v.data(), w, h, GDT_Float64, 0, 0) == CE_None);
  }
  if (!t.masked.empty()) {  // a mask inside the .tif (GDAL's default may write a .msk beside)
    CPLSetConfigOption("GDAL_TIFF_INTERNAL_MASK", "YES");
    REQUIRE(GDALCreateDatasetMaskBand(ds, GMF_PER_DATASET) == CE_None);
    CPLSetConfigOption("GDAL_TIFF_INTERNAL_MASK", nullptr);
    std::vector<unsigned char> valid(v.size(), 255);
    for (const auto& [row, col] : t.masked) valid[std::size_t(row * w + col)] = 0;
    REQUIRE(GDALRasterIO(GDALGetMaskBand(GDALGetRasterBand(ds, 1)), GF_Write, 0, 0, w, h,
                         valid.data(), w, h, GDT_Byte, 0, 0) == CE_None);
  }
  GDALClose(ds);
}

// The scene of surface_zone_test.cpp, named "dtm".
std::string scene(const std::string& box, const std::string& zone) {
  return test::surface_scene("dtm", box, zone);
}

struct Run {
  slice::BlockSystem blocks;
  std::string input_sha256;  // of the joints file (slice-joints' provenance)
  double kept = 0, removed = 0;
};

// Scene -> joints -> cut -> vertices, in a folder of its own.
Run run(const test::fs::path& dir, const std::string& text) {
  test::write_text(dir / "s.toml", text);
  const auto j = (dir / "j.h5").string(), b = (dir / "b.h5").string(), g = (dir / "g.h5").string();
  const auto r = run_tool("slice-joints", {(dir / "s.toml").string(), "-o", j});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  REQUIRE(run_tool("slice-cut", {j, "-o", b, "--prune"}).exit_code == 0);
  REQUIRE(run_tool("slice-vertices", {b, "-o", g}).exit_code == 0);
  Run out;
  out.blocks = slice::read_blocks(g);
  out.input_sha256 = slice::read_header(j).provenance.input_sha256;
  for (std::size_t i = 0; i < out.blocks.blocks.size(); ++i)
    ((out.blocks.blocks[i].flags & slice::kRemoved) ? out.removed : out.kept) +=
        out.blocks.geometry->volume[i];
  return out;
}

// 9 x 7 cells of 5 m, centres x = 0..40, y = 0..30, heights in [6, 24] from the seed, a no-data
// value in each corner (outside the domain's cells); `round`: each height a float's.
Raster random_raster(std::uint64_t seed, bool round_to_float, bool whole) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> height(6, 24);
  Raster r;
  r.z.assign(7, std::vector<double>(9));
  for (auto& row : r.z)
    for (double& v : row) {
      v = height(rng);
      if (round_to_float) v = double(float(v));
      if (whole) v = std::round(v);
    }
  r.z[0][0] = r.z[0][8] = r.z[6][0] = r.z[6][8] = r.nodata;
  return r;
}

const char* kBox = "{ min = [5, 5, 0], max = [35, 25, 20] }";
constexpr double kBoxVolume = 30.0 * 20 * 20;

}  // namespace

TEST_CASE("a GeoTIFF surface keeps the same rock as the same grid in ESRI ASCII",
          "[tools][zones][surface][geotiff]") {
  REQUIRE(slice::geotiff_supported());
  struct Variant {
    std::string name;
    Tif tif;
    bool round_to_float = false, whole = false;
  };
  std::vector<Variant> variants = {
      {"Float64, stripped, EPSG:32633, pixel-is-area", {}},
      {"Float64, deflate, tiled 16 x 16, pixel-is-point",
       tif_of(GDT_Float64, {"COMPRESS=DEFLATE", "TILED=YES", "BLOCKXSIZE=16", "BLOCKYSIZE=16"})},
      {"Float32, LZW with predictor, no CRS, NaN as no data",
       tif_of(GDT_Float32, {"COMPRESS=LZW", "PREDICTOR=3"}, ""), true},
      {"Int16 whole metres, packbits, no-data -32768, unit m",
       tif_of(GDT_Int16, {"COMPRESS=PACKBITS"}), false, true},
  };
  variants[1].tif.point = true;
  variants[2].tif.nodata = std::numeric_limits<double>::quiet_NaN();
  variants[3].tif.nodata = -32768;
  variants[3].tif.unit = "metre";
  for (std::size_t k = 0; k < variants.size(); ++k) {
    const Variant& var = variants[k];
    CAPTURE(var.name);
    Raster r = random_raster(100 + k, var.round_to_float, var.whole);
    test::TempDir tmp;
    test::fs::create_directory(tmp / "asc");
    test::fs::create_directory(tmp / "tif");
    test::write_text(tmp / "asc" / "dtm.asc", r.asc());
    // The GeoTIFF's no-data value in its corners (NaN, -32768), the .asc keeps -9999.
    Raster in_tif = r;
    for (auto* v : {&in_tif.z[0][0], &in_tif.z[0][8], &in_tif.z[6][0], &in_tif.z[6][8]})
      *v = *var.tif.nodata;
    write_tif(tmp / "tif" / "dtm.tif", in_tif, var.tif);
    if (var.tif.point) {
      // The file holds a centre as its tie point: read without GDAL's pixel-is-point shift, the
      // origin is half a cell in. rockslice reads it with the shift, as the same cells.
      CPLSetConfigOption("GTIFF_POINT_GEO_IGNORE", "TRUE");
      GDALDatasetH ds = GDALOpen((tmp / "tif" / "dtm.tif").c_str(), GA_ReadOnly);
      CPLSetConfigOption("GTIFF_POINT_GEO_IGNORE", nullptr);
      REQUIRE(ds);
      double gt[6];
      REQUIRE(GDALGetGeoTransform(ds, gt) == CE_None);
      CHECK(std::string(GDALGetMetadataItem(ds, "AREA_OR_POINT", nullptr)) == "Point");
      CHECK(gt[0] == r.x0 + r.cell / 2);
      GDALClose(ds);
    }
    const Run a = run(tmp / "asc", scene(kBox, "surface = \"dtm.asc\"\ncut = true"));
    const Run t = run(tmp / "tif", scene(kBox, "surface = \"dtm.tif\"\ncut = true"));
    // The same rock to the bit: joints (the surface's cut joints and zone mesh), blocks, flags.
    test::check_same(a.blocks, t.blocks);
    const double exact = [&] {
      double v = 0;
      for (const Tri& tri : r.triangles({5, 5}, {35, 25})) v += column_volume(tri, 0, 20);
      return v;
    }();
    CHECK(a.blocks.blocks.size() > 50);
    CHECK(t.kept == a.kept);
    CHECK_THAT(t.kept, WithinRel(exact, 1e-9));
    CHECK_THAT(t.kept + t.removed, WithinRel(kBoxVolume, 1e-9));
    // The GeoTIFF is an input of the joints file, by its SHA-256.
    CHECK_THAT(t.input_sha256, Contains(slice::sha256_file(tmp / "tif" / "dtm.tif")));
  }
}

TEST_CASE("a planar GeoTIFF at UTM coordinates removes the closed-form volume",
          "[tools][zones][surface][geotiff]") {
  // z = 12 + 0.1 (x - X) - 0.15 (y - Y) on a 2 m grid of 21 x 16 cells (centres from (X, Y))
  // around the domain [X + 4, X + 36] x [Y + 4, Y + 26] x [0, 20], with (X, Y) = (512000,
  // 4231000), a UTM position: the kept rock is the plan's area times the height at its centre,
  // 32 x 22 x 11.75 = 8272 m3.
  const double X = 512000, Y = 4231000;
  Raster r;
  r.x0 = X - 1, r.y0 = Y - 1, r.cell = 2;
  r.z.assign(16, std::vector<double>(21));
  for (std::size_t row = 0; row < 16; ++row)
    for (std::size_t col = 0; col < 21; ++col) {
      const double x = 2.0 * double(col), y = 2.0 * double(15 - row);
      r.z[row][col] = 12 + 0.1 * x - 0.15 * y;
    }
  test::TempDir tmp;
  test::fs::create_directory(tmp / "asc");
  test::fs::create_directory(tmp / "tif");
  test::write_text(tmp / "asc" / "dtm.asc", r.asc());
  write_tif(tmp / "tif" / "dtm.tiff", r, tif_of(GDT_Float64, {"COMPRESS=DEFLATE", "TILED=YES"}));
  const std::string box = "{ min = [" + g17(X + 4) + ", " + g17(Y + 4) + ", 0], max = [" +
                          g17(X + 36) + ", " + g17(Y + 26) + ", 20] }";
  const Run t = run(tmp / "tif", scene(box, "surface = \"dtm.tiff\"\ncut = true"));
  const Run a = run(tmp / "asc", scene(box, "surface = \"dtm.asc\"\ncut = true"));
  test::check_same(a.blocks, t.blocks);
  const double exact = 32.0 * 22.0 * (12 + 0.1 * 20 - 0.15 * 15);
  CHECK_THAT(exact, WithinRel(8272.0, 1e-12));
  CHECK_THAT(t.kept, WithinRel(exact, 1e-9));
  CHECK_THAT(t.kept + t.removed, WithinRel(32.0 * 22 * 20, 1e-9));
  // Without the cut, blocks go by their centres: a different kept volume, the same for both.
  const Run tp = run(tmp / "tif", scene(box, "surface = \"dtm.tiff\""));
  const Run ap = run(tmp / "asc", scene(box, "surface = \"dtm.asc\""));
  test::check_same(ap.blocks, tp.blocks);
  CHECK(std::abs(tp.kept - exact) > 1.0);
}

TEST_CASE("GeoTIFF surfaces that do not fit the scene are refused with one line",
          "[tools][zones][surface][geotiff]") {
  test::TempDir tmp;
  const Raster r = random_raster(7, false, false);
  Raster gap = r;
  gap.z[3][4] = -9999;  // row 4, column 5: inside the domain
  Raster nan = r;
  nan.z[3][4] = std::numeric_limits<double>::quiet_NaN();
  Raster thin = r;
  thin.z.resize(1);
  const std::array<double, 6> north_up = {-2.5, 5, 0, 32.5, 0, -5};
  struct Case {
    std::string file;
    Raster raster;
    Tif tif;
    std::vector<std::string> words;
    std::string box = kBox;
  };
  std::vector<Case> cases;
  const auto add = [&](std::string file, const Raster& ras, Tif tif,
                       std::vector<std::string> words) {
    cases.push_back({std::move(file), ras, std::move(tif), std::move(words)});
  };
  Tif t;
  t.srs = "EPSG:4326";
  add("wgs84.tif", r, t, {"is in degrees", "WGS 84, EPSG:4326", "gdalwarp -t_srs"});
  t = {};
  t.srs = "EPSG:2263";  // NAD83 / New York Long Island (ftUS)
  add("feet.tif", r, t, {"US survey foot", "EPSG:2263", "read in metres", "-a_srs \"\""});
  t = {};
  t.srs = "EPSG:32618+6360";  // UTM 18N with NAVD88 heights in US survey feet
  add("vertical-feet.tif", r, t, {"heights in US survey foot", "vertical CRS", "gdalwarp -t_srs"});
  t = {};
  t.unit = "ft";
  add("ft-heights.tif", r, t, {"heights in 'ft'", "-units m"});
  t = {};
  t.gt = north_up;
  (*t.gt)[2] = 0.5;
  add("rotated.tif", r, t, {"rotated or sheared", "gdalwarp"});
  t = {};
  t.gt = std::array<double, 6>{-2.5, 5, 0, -2.5, 0, 5};
  add("south-up.tif", r, t, {"not north-up", "gdalwarp"});
  t = {};
  t.no_gt = true;
  t.srs = "";
  add("nogt.tif", r, t, {"no georeferencing"});
  t = {};
  t.bands = 3;
  add("rgb.tif", r, t, {"has 3 bands", "gdal_translate -b"});
  t = {};
  t.scale = 0.01;
  add("scaled.tif", r, t, {"scaled", "-unscale"});
  add("gap.tif", gap, {}, {"row 4, column 5", "no-data value -9999", "gdal_fillnodata"});
  t = {};
  t.nodata.reset();
  add("nan.tif", nan, t, {"row 4, column 5", "nan, not finite", "-a_nodata"});
  add("thin.tif", thin, {}, {"9 x 1 cells", "at least 2 columns and 2 rows"});
  t = {};
  t.nodata.reset();
  t.masked = {{3, 4}};  // a finite height, hidden by the mask: no data
  add("masked.tif", r, t, {"row 4, column 5", "no-data value nan"});
  cases.push_back(
      {"narrow.tif", r, {}, {"cell centres span"}, "{ min = [-1, 5, 0], max = [35, 25, 20] }"});
  for (const auto& c : cases) {
    CAPTURE(c.file);
    write_tif(tmp / c.file, c.raster, c.tif);
    test::write_text(tmp / "s.toml", scene(c.box, "surface = \"" + c.file + "\""));
    const auto out = (tmp / "j.h5").string();
    std::vector<std::string> words = c.words;
    words.push_back("s.toml:");
    words.push_back(c.file);
    test::check_refused(run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", out}),
                        "slice-joints", words);
    CHECK_FALSE(test::fs::exists(out));
  }
  // Damaged files: text named .tif, a GeoTIFF cut in half, one with its strip offsets past the
  // end. GDAL's reason is in the line, on one line; nothing is written.
  write_tif(tmp / "whole.tif", r, {});
  const std::string whole = test::read_bytes(tmp / "whole.tif");
  struct Bad {
    std::string file, bytes;
    std::vector<std::string> words;
  };
  const std::vector<Bad> bad = {
      {"text.tif", "ncols 9\nnrows 7\n", {"is not a GeoTIFF that GDAL can read"}},
      {"half.tif", whole.substr(0, whole.size() / 2), {"half.tif"}},
      {"empty.tiff", "", {"is not a GeoTIFF that GDAL can read"}},
  };
  for (const auto& c : bad) {
    CAPTURE(c.file);
    test::write_text(tmp / c.file, c.bytes);
    test::write_text(tmp / "s.toml", scene(kBox, "surface = \"" + c.file + "\""));
    const auto out = (tmp / "j.h5").string();
    std::vector<std::string> words = c.words;
    words.push_back("s.toml:");
    test::check_refused(run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", out}),
                        "slice-joints", words);
    CHECK_FALSE(test::fs::exists(out));
  }
}

// GeoTIFF ground surfaces through GDAL (docs/topography.md, "GeoTIFF"): band 1 of a north-up
// GeoTIFF read into the HeightGrid an ESRI ASCII grid gives, so that both go through the same
// grid_surface. The one file of the library that includes GDAL's headers; a build without
// GDAL (CMake's SLICE_GDAL) compiles the refusal at the end instead.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "slice/error.hpp"
#include "slice/mesh.hpp"
#include "slice/surface.hpp"

#ifdef SLICE_HAS_GDAL
#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>
#endif

namespace slice {

#ifdef SLICE_HAS_GDAL

namespace {

std::string num(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

// GDAL prints its errors to stderr unless a handler takes them, and reads sidecar files (.aux.xml,
// .tfw world files) that would change the grid without changing the .tif's SHA-256 in the
// provenance. While a GeoTIFF is read: errors are kept quiet (their text goes into ours) and only
// the file's own tags count. Both are per thread in GDAL, and restored after.
class QuietGdal {
 public:
  QuietGdal() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
    for (std::size_t i = 0; i < kOptions.size(); ++i) {
      if (const char* v = CPLGetThreadLocalConfigOption(kOptions[i][0], nullptr)) saved_[i] = v;
      CPLSetThreadLocalConfigOption(kOptions[i][0], kOptions[i][1]);
    }
  }
  ~QuietGdal() {
    for (std::size_t i = 0; i < kOptions.size(); ++i)
      CPLSetThreadLocalConfigOption(kOptions[i][0], saved_[i] ? saved_[i]->c_str() : nullptr);
    CPLPopErrorHandler();
  }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;

 private:
  static constexpr std::array<std::array<const char*, 2>, 3> kOptions{{
      {"GDAL_PAM_ENABLED", "NO"},                    // no .aux.xml
      {"GDAL_GEOREF_SOURCES", "INTERNAL"},           // the GeoTIFF tags, no .tfw or .tab
      {"GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR"}  // no look for sidecars at all
  }};
  std::array<std::optional<std::string>, kOptions.size()> saved_;
};

// GDAL's last message, on one line and at most 200 characters.
std::string gdal_message() {
  std::string m = CPLGetLastErrorMsg();
  for (char& c : m)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  if (m.size() > 200) m = m.substr(0, 200) + "...";
  return m.empty() ? "no reason given" : m;
}

struct CloseDataset {
  void operator()(void* ds) const { GDALClose(ds); }
};

// "WGS 84, EPSG:4326", or the name alone.
std::string crs_name(OGRSpatialReferenceH srs) {
  const char* name = OSRGetName(srs);
  std::string s = name ? name : "unnamed";
  const char* auth = OSRGetAuthorityName(srs, nullptr);
  const char* code = OSRGetAuthorityCode(srs, nullptr);
  if (auth && code) s += std::string(", ") + auth + ":" + code;
  return s;
}

bool is_metre(std::string unit) {
  for (char& c : unit) c = char(std::tolower(static_cast<unsigned char>(c)));
  return unit == "m" || unit == "metre" || unit == "meter" || unit == "metres" || unit == "meters";
}

// The largest raster read: 2^25 cells, 256 MiB of heights, as many as an ESRI ASCII grid of the
// largest file a surface may have (kMaxMeshFileBytes) could hold.
constexpr std::int64_t kMaxCells = std::int64_t(kMaxMeshFileBytes / sizeof(double));

}  // namespace

bool geotiff_supported() { return true; }

HeightGrid read_geotiff(const std::filesystem::path& file) {
  const std::string where = file.string();
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw Error(where, "cannot be read", "check the path");
  if (size > kMaxMeshFileBytes)
    throw Error(where,
                "is " + std::to_string(size >> 20) + " MiB, more than the " +
                    std::to_string(kMaxMeshFileBytes >> 20) + " MiB a surface may have",
                "crop the raster to the domain, or resample it coarser (gdal_translate -projwin, "
                "-tr)");
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  const QuietGdal quiet;
  // GTiff only: a .tif that is some other format GDAL knows is no GeoTIFF.
  const char* const drivers[] = {"GTiff", nullptr};
  const std::unique_ptr<void, CloseDataset> ds(
      GDALOpenEx(file.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, drivers,
                 nullptr, nullptr));
  if (!ds)
    throw Error(where, "is not a GeoTIFF that GDAL can read (" + gdal_message() + ")",
                "check the file, or write it again (gdal_translate -of GTiff)");
  const int bands = GDALGetRasterCount(ds.get());
  if (bands != 1)
    throw Error(where,
                "has " + std::to_string(bands) +
                    " bands; a ground surface is one band of heights (an image is not)",
                "give the band of heights alone (gdal_translate -b N " + where + " heights.tif)");
  GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
  if (GDALDataTypeIsComplex(GDALGetRasterDataType(band)))
    throw Error(where, "holds complex numbers, not heights",
                "give a raster of real heights (Float32, Float64 or integers)");
  HeightGrid g;
  g.ncols = GDALGetRasterXSize(ds.get());
  g.nrows = GDALGetRasterYSize(ds.get());
  if (g.ncols < 2 || g.nrows < 2)
    throw Error(where,
                "is " + std::to_string(g.ncols) + " x " + std::to_string(g.nrows) +
                    " cells: heights are at cell centres, and the surface spans between them, "
                    "so a grid needs at least 2 columns and 2 rows",
                "give a raster of at least 2 x 2 cells over the domain");
  if (g.ncols * g.nrows > kMaxCells)
    throw Error(where,
                "is " + std::to_string(g.ncols) + " x " + std::to_string(g.nrows) +
                    " cells, more than the " + std::to_string(kMaxCells) + " a surface may have",
                "crop the raster to the domain, or resample it coarser (gdal_translate -projwin, "
                "-tr)");

  // Georeferencing. GDAL gives the geotransform for pixel-is-area whatever the file's
  // AREA_OR_POINT: (gt[0], gt[3]) is the outer corner of the north-west cell (a pixel-is-point
  // file's tie point, a cell centre, moved half a cell out), so the centres below are those of
  // the same grid as ESRI ASCII with xllcorner = gt[0], yllcorner = gt[3] + nrows gt[5].
  double gt[6];
  if (GDALGetGeoTransform(ds.get(), gt) != CE_None)
    throw Error(where, "has no georeferencing (no geotransform in its GeoTIFF tags)",
                "georeference it (gdal_translate -a_ullr ulx uly lrx lry, or -a_srs too)");
  if (!std::all_of(gt, gt + 6, [](double v) { return std::isfinite(v); }))
    throw Error(where, "has a geotransform that is not finite", "georeference it again");
  if (gt[2] != 0 || gt[4] != 0)
    throw Error(where,
                "is rotated or sheared (geotransform row and column terms " + num(gt[2]) + " and " +
                    num(gt[4]) + ", not 0): heights must lie on a north-up grid",
                "resample it north-up: gdalwarp " + where + " north-up.tif");
  if (!(gt[1] > 0) || !(gt[5] < 0))
    throw Error(where,
                "is not north-up (cell size " + num(gt[1]) + " x " + num(gt[5]) +
                    "; a north-up raster has x > 0 and y < 0)",
                "resample it north-up: gdalwarp " + where + " north-up.tif");
  g.dx = gt[1];
  g.dy = -gt[5];
  g.x0 = gt[0] + g.dx / 2;
  g.y0 = (gt[3] + double(g.nrows) * gt[5]) + g.dy / 2;
  if (!std::isfinite(g.x0) || !std::isfinite(g.y0) || !std::isfinite(g.x(g.ncols - 1)) ||
      !std::isfinite(g.y(0)))
    throw Error(where,
                "reaches past the largest number (its corner plus " + std::to_string(g.ncols) +
                    " x " + std::to_string(g.nrows) + " cells of " + num(g.dx) + " x " + num(g.dy) +
                    ")",
                "check its geotransform and unit");

  // Units. The scene's lengths have no unit of their own (docs/scenes.md); a raster with a CRS
  // is read as metres, which most projections are. One without a CRS is in the scene's unit,
  // as an ESRI ASCII grid.
  if (OGRSpatialReferenceH srs = GDALGetSpatialRef(ds.get()); srs) {
    const std::string crs = crs_name(srs);
    if (OSRIsGeographic(srs))
      throw Error(
          where,
          "is in degrees: its CRS is geographic (" + crs + "), and the scene's x and y are lengths",
          "reproject it to a metric projection with gdalwarp, e.g. gdalwarp -t_srs "
          "EPSG:32633 " +
              where + " utm.tif (the UTM zone of the site)");
    char* unit = nullptr;
    const double to_m = OSRGetLinearUnits(srs, &unit);
    const std::string unit_name = unit ? unit : "unknown";
    const std::string dropped =
        "or, if the scene is in that unit, drop the raster's CRS (gdal_edit.py -a_srs \"\" " +
        where + "): a raster without one is read in the scene's unit";
    if (std::abs(to_m - 1) > 1e-12)
      throw Error(where,
                  "has x and y in " + unit_name + " (" + num(to_m) + " m) by its CRS (" + crs +
                      "), and a georeferenced surface is read in metres",
                  "reproject it to a projection in metres (gdalwarp -t_srs EPSG:...), " + dropped);
    if (OSRIsCompound(srs) || OSRIsVertical(srs)) {
      char* vunit = nullptr;
      const double v_to_m = OSRGetTargetLinearUnits(srs, "VERT_CS", &vunit);
      if (std::abs(v_to_m - 1) > 1e-12)
        throw Error(where,
                    "has heights in " + std::string(vunit ? vunit : "unknown") + " (" +
                        num(v_to_m) + " m) by its vertical CRS (" + crs +
                        "), and a georeferenced surface is read in metres",
                    "convert the heights to metres: gdalwarp -t_srs with a vertical CRS in "
                    "metres converts them (e.g. EPSG:32633+5773, UTM 33N with EGM96 heights)");
    }
    // The band's unit: "" (most files) is taken as the CRS's, metres.
    if (const char* u = GDALGetRasterUnitType(band); u && *u && !is_metre(u))
      throw Error(where,
                  "has heights in '" + std::string(u).substr(0, 40) +
                      "' (its band's unit), and a georeferenced surface is read in metres",
                  "convert the heights to metres, or, if they are metres, say so (gdal_edit.py "
                  "-units m " +
                      where + ")");
  }

  int has_scale = 0, has_offset = 0;
  const double scale = GDALGetRasterScale(band, &has_scale);
  const double offset = GDALGetRasterOffset(band, &has_offset);
  if ((has_scale && scale != 1) || (has_offset && offset != 0))
    throw Error(where,
                "stores heights scaled (height = value x " + num(scale) + " + " + num(offset) + ")",
                "write the heights themselves: gdal_translate -unscale -ot Float64 " + where +
                    " heights.tif");

  // No data: the band's no-data value (NaN too), and the cells of a mask band if it has one.
  int has_nodata = 0;
  double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  if (has_nodata && GDALGetRasterDataType(band) == GDT_Float32 && std::isfinite(nodata) &&
      std::abs(nodata) <= std::numeric_limits<float>::max())
    nodata = double(float(nodata));  // as the band's values hold it
  const int mask_flags = GDALGetMaskFlags(band);
  const bool masked = !(mask_flags & (GMF_ALL_VALID | GMF_NODATA));
  if (has_nodata || masked) g.nodata = has_nodata ? nodata : std::nan("");

  const std::size_t n = std::size_t(g.ncols * g.nrows);
  g.z.resize(n);
  const int w = int(g.ncols), h = int(g.nrows);
  if (GDALRasterIO(band, GF_Read, 0, 0, w, h, g.z.data(), w, h, GDT_Float64, 0, 0) != CE_None)
    throw Error(where, "cannot be read (" + gdal_message() + ")",
                "the file is damaged or cut off: write it again");
  if (masked) {
    std::vector<unsigned char> valid(n);
    if (GDALRasterIO(GDALGetMaskBand(band), GF_Read, 0, 0, w, h, valid.data(), w, h, GDT_Byte, 0,
                     0) != CE_None)
      throw Error(where, "cannot be read (its mask: " + gdal_message() + ")",
                  "the file is damaged or cut off: write it again");
    for (std::size_t i = 0; i < n; ++i)
      if (!valid[i]) g.z[i] = *g.nodata;
  }
  const bool nan_nodata = g.nodata && std::isnan(*g.nodata);
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(g.z[i]) && !(nan_nodata && std::isnan(g.z[i])) &&
        !(g.nodata && g.z[i] == *g.nodata))
      throw Error(where,
                  "the height of row " + std::to_string(i / std::size_t(w) + 1) + ", column " +
                      std::to_string(i % std::size_t(w) + 1) + " is " + num(g.z[i]) +
                      ", not finite",
                  "give missing heights the band's no-data value (gdal_edit.py -a_nodata)");
  return g;
}

#else  // no GDAL in this build

bool geotiff_supported() { return false; }

HeightGrid read_geotiff(const std::filesystem::path& file) {
  throw Error(file.string(),
              "is a GeoTIFF, and this build of rockslice has no GeoTIFF support (GDAL was not "
              "found when it was built)",
              "run `bash pipelines/setup --gdal`, which installs libgdal-dev and rebuilds, or "
              "give an ESRI ASCII grid (gdal_translate -of AAIGrid " +
                  file.filename().string() + " " + file.stem().string() + ".asc)");
}

#endif

}  // namespace slice

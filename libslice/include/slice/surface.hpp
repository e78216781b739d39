#pragma once
// Topography surfaces ([[zones]] surface, docs/topography.md): an open triangulated height
// field z = h(x, y), piecewise linear on its triangles, from STL or OBJ, an ESRI ASCII grid or
// a GeoTIFF;
// checked to be a height field that covers the domain in plan, and closed into the solid of
// the rock above it, which then removes blocks as a mesh zone does (mesh.hpp).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/mesh.hpp"

namespace slice {

/// An ESRI ASCII grid (.asc) or a GeoTIFF's band (.tif): one height per cell, at the cell's
/// centre.
struct HeightGrid {
  std::int64_t ncols = 0, nrows = 0;
  double x0 = 0, y0 = 0;               // the centre of the lower-left (south-west) cell
  double dx = 0, dy = 0;               // the cell size in x and y (cellsize, or dx and dy)
  std::optional<double> nodata;        // NaN: NaN heights are no data (a GeoTIFF's)
  std::vector<double> z;               // nrows x ncols, from the north row, as in the file
  std::vector<std::int64_t> row_line;  // the file line each row starts on (none: a GeoTIFF)
  double x(std::int64_t col) const { return x0 + double(col) * dx; }
  double y(std::int64_t row) const { return y0 + double(nrows - 1 - row) * dy; }
  double at(std::int64_t row, std::int64_t col) const { return z[std::size_t(row * ncols + col)]; }
};

/// Reads an ESRI ASCII grid: a header of `ncols`, `nrows`, `xllcorner` or `xllcenter`,
/// `yllcorner` or `yllcenter`, `cellsize` (or `dx` and `dy`) and optionally `NODATA_value`
/// (keys in any case and order), then nrows x ncols numbers, the north row first. A corner
/// gives the outer corner of the south-west cell, whose centre is half a cell in; a centre
/// gives that centre. Throws Error("<file>:<line>", ...) on a malformed file. Files over
/// kMaxMeshFileBytes are refused by their size.
HeightGrid read_ascii_grid(const std::filesystem::path& file);

/// Reads band 1 of a north-up GeoTIFF through GDAL (docs/topography.md, "GeoTIFF"): cell
/// centres from its geotransform (pixel-is-area or pixel-is-point alike, as GDAL gives it), its
/// no-data value and mask as no data. Throws Error(<file>, ...) for a file GDAL's GTiff driver
/// cannot read, more than one band, a rotated, sheared or not north-up raster, a geographic CRS
/// (degrees), a CRS or band unit other than metres, scaled heights, a height that is neither
/// finite nor no data, fewer than 2 x 2 or more than 2^25 cells; and, in a build without GDAL
/// (geotiff_supported() false), for any file, saying how to get a build with it.
HeightGrid read_geotiff(const std::filesystem::path& file);
bool geotiff_supported();

/// The grid's surface over the plan rectangle [lo, hi]: the cells between four neighbouring
/// centres that meet its interior, each split into two triangles by the diagonal from its
/// south-west to its north-east centre. Throws Error if the centres do not span [lo, hi]
/// (within tol) or a no-data value is among them, naming its row, column and line (if any).
TriangleMesh grid_surface(const HeightGrid& grid, const Vec2& lo, const Vec2& hi, double tol,
                          const std::string& where);

/// Reads a surface file by its extension: .stl or .obj (read_mesh, the whole surface), or
/// .asc or .tif / .tiff (read_ascii_grid or read_geotiff, then grid_surface over the plan
/// rectangle [lo, hi]).
TriangleMesh read_surface(const std::filesystem::path& file, const Vec2& lo, const Vec2& hi,
                          double tol);

/// The part of a surface that matters over the plan rectangle [lo, hi]: its triangles whose
/// plan bounding box meets the rectangle, and (so that the part stays one sheet edge to edge)
/// every triangle around a vertex where the kept triangles would otherwise meet at that vertex
/// only. `numbers`: each kept triangle's number in `surface` (1-based), for messages. Vertices
/// no kept triangle uses are dropped. Outside the rectangle nothing is checked: a fold or an
/// overhang there is cropped away with its triangles.
struct CroppedSurface {
  TriangleMesh mesh;
  std::vector<std::int64_t> numbers;
};
CroppedSurface crop_surface(const TriangleMesh& surface, const Vec2& lo, const Vec2& hi);

/// The convex hull of the points in plan (x, y), counter-clockwise.
std::vector<Vec2> plan_hull(std::span<const Vec3> points);

/// Checks that `surface` is a height field that covers the convex polygon `plan`
/// (counter-clockwise) and returns it with every triangle counter-clockwise seen from above.
/// Throws Error(where, ...) for a triangle without area, a vertical triangle, two triangles
/// that overlap in plan by more than `tol` (an overhang or a fold: z is not a function of x and
/// y), and an edge of the surface's border (a side of one triangle only) that runs inside
/// `plan` by more than tol, or a surface that misses `plan` (a hole, a gap, or too small).
/// `numbers`: the triangles' numbers in messages (crop_surface's), else their index + 1.
TriangleMesh check_height_field(const TriangleMesh& surface, std::span<const Vec2> plan, double tol,
                                const std::string& where,
                                std::span<const std::int64_t> numbers = {});

/// The closed mesh (outward, as check_solid_mesh wants) of the rock above a checked surface
/// (check_height_field) up to z = top, which must lie above it: the surface's triangles
/// turned down, a vertical wall on each border edge and a lid at z = top: a fan from the
/// border's centre if the border is one loop star-shaped about it, else the surface's triangles.
TriangleMesh solid_above(const TriangleMesh& up, double top);

}  // namespace slice

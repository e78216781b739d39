// libFuzzer target: the ESRI ASCII grid reader of [[zones]] surface (surface.hpp,
// docs/topography.md). The input is written to "grid.asc"; slice::read_ascii_grid reads it, and
// a grid it accepts becomes its surface (slice::grid_surface) over the plan rectangle of its
// cell centres shrunk by a quarter cell, then over a rectangle reaching past them (refused).
// slice::Error (bad input, exit 1 in the tools) is the expected answer; any other exception, a
// crash, a sanitizer report, a timeout or running out of memory is a finding, and so is a grid
// that is accepted but breaks what surface.hpp promises: nrows x ncols heights of >= 2 x 2,
// finite heights, a cell size > 0, a line for each row; a surface with a vertex not finite, a
// triangle index out of its vertices, or no triangle.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input.hpp"
#include "slice/error.hpp"
#include "slice/surface.hpp"

namespace {

const char* const kTarget = "fuzz_asc";

void check_grid(const slice::HeightGrid& g) {
  if (g.ncols < 2 || g.nrows < 2 || g.z.size() != std::size_t(g.ncols * g.nrows) ||
      g.row_line.size() != std::size_t(g.nrows))
    fuzz::finding(kTarget, "read_ascii_grid accepted a grid whose counts disagree");
  if (!(g.dx > 0) || !(g.dy > 0) || !std::isfinite(g.x0) || !std::isfinite(g.y0))
    fuzz::finding(kTarget, "read_ascii_grid accepted a cell size <= 0 or an origin not finite");
  for (const double z : g.z)
    if (!std::isfinite(z)) fuzz::finding(kTarget, "read_ascii_grid accepted a height not finite");
}

void check_surface(const slice::TriangleMesh& m) {
  if (m.triangles.empty()) fuzz::finding(kTarget, "grid_surface made no triangle");
  for (const slice::Vec3& x : m.vertices)
    if (!x.allFinite()) fuzz::finding(kTarget, "grid_surface made a vertex not finite");
  const auto n = std::int64_t(m.vertices.size());
  for (const auto& t : m.triangles)
    for (const std::int64_t v : t)
      if (v < 0 || v >= n) fuzz::finding(kTarget, "grid_surface made a vertex index out of range");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  fuzz::set_input_name("grid.asc");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = fuzz::write_input(data, size);
  slice::HeightGrid g;
  try {
    g = slice::read_ascii_grid(path);
  } catch (const slice::Error&) {
    return 0;  // refused with a message: the promised answer to bad input
  }
  check_grid(g);
  const slice::Vec2 lo(g.x(0), g.y(g.nrows - 1)), hi(g.x(g.ncols - 1), g.y(0));
  const slice::Vec2 quarter(g.dx / 4, g.dy / 4);
  const double tol = 1e-9 * (hi - lo).norm();
  for (const slice::Vec2& grow : {slice::Vec2(-quarter), slice::Vec2(quarter)}) {
    if (!(lo - grow).allFinite() || !(hi + grow).allFinite() ||
        !((hi + grow - lo + grow).minCoeff() > 0))
      continue;
    try {
      check_surface(slice::grid_surface(g, lo - grow, hi + grow, tol, "fuzz grid"));
    } catch (const slice::Error&) {
      // a no-data height among the centres, or a rectangle beyond them: refused with a message
    }
  }
  return 0;
}

#pragma once
// libslice/src/scene/dfn_fab.cpp, dfn_csv.cpp: discrete fracture networks made by other programs
// (docs/dfn.md), read for the scene table [[dfn]] (docs/scenes.md), and the joints of a joint
// system written as a FracMan FAB file.
//   FAB (FracMan's ASCII format, as FracMan and PorePy's fracture_importer read and write it):
//   sections BEGIN NAME ... END NAME: FORMAT (key = value: Format = Ascii, No_Fractures,
//   No_TessFractures, No_Nodes, No_Properties, ...), PROPERTIES (PropK = (type) "name"), SETS
//   (SetK = "name"), FRACTURE (per fracture a line "id nodes set prop1 ... propP", one line
//   "k x y z" per node, a line "0 nx ny nz", the normal), TESSFRACTURE (per fracture a line
//   "id nodes faces set", one line "k x y z" per node, one line per triangle: five whole numbers,
//   the face's number and its node indices, then any property values) and ROCKBLOCK (read only
//   when empty).
//   CSV: a header row, then one disc per row (docs/dfn.md names the columns).
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/scene.hpp"

namespace slice {

/// One fracture of a DFN file. FAB gives its corners (`nodes`, as listed); CSV gives a disc,
/// made a polygon here: its centre, orientation and corners in its plane frame (orientation.hpp).
struct DfnFracture {
  std::string id;           // as the file names it (FAB: the fracture's id; CSV: `id` or the row)
  std::int64_t line = 0;    // where it starts in the file (1-based)
  std::size_t set = 0;      // index into DfnFile::sets
  std::vector<Vec3> nodes;  // FAB: the polygon's corners in global coordinates, in file order
  // FAB TESSFRACTURE: `nodes` are the mesh's nodes, `faces` the first five whole numbers of each
  // face line (docs/dfn.md: where the three node indices, 1-based, stand is read from them).
  bool tessellated = false;
  std::vector<std::array<std::int64_t, 5>> faces;
  bool disc = false;  // CSV: the fields below hold the joint, `nodes` is empty
  Vec3 centre = Vec3::Zero();
  double dip_deg = 0, dip_direction_deg = 0;
  std::vector<Vec2> polygon_uv;  // counter-clockwise about centre
};

struct DfnFile {
  std::vector<std::string> sets;       // the file's sets, by name, in the file's order
  std::vector<DfnFracture> fractures;  // in file order
};

/// Reads a FAB file. Throws Error("<file>:<line>", what, fix) on anything it cannot read as
/// written: a section without its END, counts that disagree with FORMAT, a number that is not
/// finite, a node count the rest of the file cannot hold, a set id SETS does not declare (when
/// SETS declares any), a face line that is not five whole numbers and numbers, rock blocks
/// (ROCKBLOCK not empty), a binary FAB.
DfnFile read_fab(const std::filesystem::path& file);

/// How a CSV disc becomes a polygon: `sides` corners (the row's `sides` column wins) about the
/// ellipse of the row's radius (the long semi-axis) and aspect (long / short, >= 1), turned by
/// its rotation (degrees, counter-clockwise from strike): fit equal-area keeps the disc's area,
/// circumscribed puts every edge on a tangent (joint_polygon, stochastic.hpp).
struct DfnCsvOptions {
  std::int64_t sides = 16;
  EllipseFit fit = EllipseFit::equal_area;
};
/// Reads a CSV file of discs. `default_set`: the name of the one set of a file without a `set`
/// column. Throws Error("<file>:<line>", what, fix).
DfnFile read_dfn_csv(const std::filesystem::path& file, const DfnCsvOptions& opt,
                     const std::string& default_set);

struct FabStats {
  std::size_t fractures = 0;
  std::size_t nodes = 0;
  std::size_t persistent = 0;  // persistent joints written as their plane clipped to the domain
  std::size_t left_out = 0;    // persistent joints whose plane misses the domain's interior
  std::size_t sets = 0;
};
/// Writes the joints of a 3-D joint system as a FAB file, atomically: one FRACTURE per joint,
/// its polygon's corners (a persistent joint: its plane clipped to the domain), its set (SETS
/// names each of js.sets, and one more, "[[joints]]", for joints without a set), no properties.
/// Coordinates with 17 significant digits, so that reading the file back gives the same
/// corners. Throws Error for a 2-D joint system or when the file cannot be written.
FabStats write_fab(const std::filesystem::path& out, const JointSystem& js);

}  // namespace slice

#pragma once
// What slice-stability stores (HDF5 /contacts and /stability; docs/formats.md) and the loads it
// was run with: the data a BlockSystem carries. The analysis itself: slice/stability.hpp.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "slice/geometry.hpp"

namespace slice {

/// The largest --max-group slice-stability takes.
inline constexpr std::size_t kMaxGroup = 64;

/// /stability/mode (a public contract: the values are the file's).
enum class FailureMode : std::uint8_t {
  not_exposed = 0,    // no free face, or removed, or a boundary or fixed block
  not_removable = 1,  // exposed, but every direction pushes into a face it touches
  stable = 2,         // removable, but no motion the resultant can drive
  falls = 3,          // falls or lifts: leaves every face it touches
  slides_one = 4,     // slides on one plane
  slides_two = 5,     // slides on two planes, along their line of intersection
};

/// The loads of a stability analysis (slice-stability's options).
struct StabilityOptions {
  double density = 2650;              // kg/m3, of the rock
  double gravity = 9.81;              // m/s2, along -z (as the DEM exports)
  double seismic = 0;                 // pseudo-static coefficient k: k W, horizontal
  double seismic_azimuth_deg = 0;     // towards this azimuth, clockwise from North (+y)
  std::optional<double> water_table;  // z of a horizontal water table: hydrostatic pressure on
                                      // the contact faces below it
  double water_density = 1000;        // kg/m3
  double support_pressure = 0;        // Pa, on the free faces a block has at the start, inwards
  std::uint8_t free_faces = 0;        // bits of kBoxFaceNames: domain faces that are free surfaces
  double fos_target = 1;              // a block with a mode of motion and FoS below this fails
  std::size_t max_group = 8;          // most bodies in a group that fails together (1: none)
};

/// Rows of HDF5 /contacts: where each kept block touches another block (kept or removed) or the
/// domain's boundary. Block-block rows have a < b, except a row with a removed block, whose kept
/// block is a; b = -1: a face on the domain's boundary.
struct ContactRows {
  std::vector<std::array<std::int64_t, 2>> pairs;  // blocks a, b (-1: the domain's boundary)
  std::vector<std::array<std::int64_t, 2>> faces;  // face rows of /blocks/face_* (-1: none)
  std::vector<double> area;
  std::vector<Vec3> centroid;
  std::vector<Vec3> normal;         // a's outward unit normal
  std::vector<std::int64_t> joint;  // -1: a face of the domain
  std::vector<double> fraction;     // part of the contact on its joint's polygon (1: persistent)
  std::vector<std::uint8_t> free;   // 1: b is removed, or the domain face is a free surface
  std::size_t size() const { return pairs.size(); }
};

/// HDF5 /stability, per block (B rows): a cluster's members carry the cluster's values.
struct StabilityResult {
  StabilityOptions options;  // stored as attributes of /stability
  std::vector<std::uint8_t> removable;
  std::vector<std::uint8_t> mode;                   // FailureMode
  std::vector<double> fos;                          // +inf where nothing can move
  std::vector<Vec3> direction;                      // unit direction of motion, 0 where none
  std::vector<std::int32_t> generation;             // round it fails in; -1 never
  std::vector<std::array<std::int64_t, 2>> planes;  // joints of the sliding plane(s), -1 none
  std::vector<std::int64_t> group;  // a group that fails together: its smallest block; -1 none
};

/// What a BlockSystem holds once slice-stability has run: /contacts and /stability. Anything
/// that changes the blocks resets it (as it resets /geometry).
struct StabilityData {
  ContactRows contacts;
  StabilityResult result;
};

}  // namespace slice

#pragma once
// Which blocks fall: removability, failure mode and factor of safety of every exposed block by
// limit equilibrium, with successive failure (docs/stability.md; docs/design.md, "Stability").
// The stage slice-stability; HDF5 /contacts and /stability (docs/formats.md).
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "slice/geometry.hpp"

namespace slice {

struct BlockSystem;

/// /stability/mode (a public contract: the values are the file's).
enum class FailureMode : std::uint8_t {
  not_exposed = 0,    // no free face, or removed, or a boundary or fixed block
  not_removable = 1,  // exposed, but every direction pushes into a face it touches
  stable = 2,         // removable, but no motion the resultant can drive
  falls = 3,          // falls or lifts: leaves every face it touches
  slides_one = 4,     // slides on one plane
  slides_two = 5,     // slides on two planes, along their line of intersection
};
const char* to_string(FailureMode m);

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
};

/// What a BlockSystem holds once slice-stability has run: /contacts and /stability. Anything
/// that changes the blocks resets it (as it resets /geometry).
struct StabilityData {
  ContactRows contacts;
  StabilityResult result;
};

// --- one body -----------------------------------------------------------------------------------

/// The faces of one body (a block or a cluster) that touch something, grouped by direction: all
/// contacts with one outward normal act as one plane in a rigid translation.
struct ContactPlane {
  Vec3 normal = Vec3::UnitZ();  // outward unit normal of the body
  double area = 0;              // sum over its contacts
  double friction = 0;          // sum of A tan(phi): N is spread over the plane by area
  double cohesion = 0;          // sum of c A (N)
  double tension = 0;           // sum of t A (N)
  bool locked = false;          // a domain face without [rock]: never slips
  std::int64_t joint = -1;      // the joint of its largest contact (-1: the domain)
};

/// The answer for one body under the resultant of its loads.
struct BodyStability {
  bool removable = false;
  FailureMode mode = FailureMode::stable;
  double fos = std::numeric_limits<double>::infinity();
  Vec3 direction = Vec3::Zero();
  std::array<int, 2> planes{-1, -1};  // indices into the planes given (sliding planes)
};

/// Goodman & Shi's removability and the mode of motion of a body touching `planes` (none free)
/// under `resultant` (N), with its factor of safety by limit equilibrium. `angle_tol`: a
/// direction within this (radians) of a plane moves along it (a release face). Exposure is the
/// caller's: a body with no planes falls.
BodyStability analyse_body(std::span<const ContactPlane> planes, const Vec3& resultant,
                           double angle_tol = 1e-9);

// --- the whole model -----------------------------------------------------------------------------

struct StabilityStats {
  std::size_t bodies = 0, exposed = 0, removable = 0, failing = 0, rounds = 0;
  std::size_t contacts = 0;
  double seconds = 0;
};

/// Contacts, then every exposed body's stability, rounds of successive failure until nothing
/// more fails. Needs /geometry (throws Error without it). Byte-identical results on any number
/// of threads.
StabilityData analyse_stability(const BlockSystem& bs, const StabilityOptions& opt,
                                StabilityStats* stats = nullptr);

/// Refuses options no analysis can use (Error naming the option): a density or gravity that is
/// not positive, a coefficient, pressure or target that is negative or not finite, a water
/// table of NaN.
void check_stability_options(const StabilityOptions& opt);

/// The free-face names of a --free-faces string ("+z,-x"), or throws Error naming the bad one.
std::uint8_t parse_free_faces(const std::string& text);

}  // namespace slice

#pragma once
// Which blocks fall: removability, failure mode and factor of safety of every exposed block by
// limit equilibrium, with successive failure (docs/stability.md; docs/design.md, "Stability").
// The stage slice-stability; HDF5 /contacts and /stability (docs/formats.md).
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "slice/geometry.hpp"
#include "slice/stability_data.hpp"

namespace slice {

struct BlockSystem;

const char* to_string(FailureMode m);

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
  std::size_t groups = 0;  // groups of bodies that fail together
  std::size_t contacts = 0;
  double seconds = 0;           // all of analyse_stability:
  double contacts_seconds = 0;  //   the contact search and its rows
  double bodies_seconds = 0;    //   bodies and their contact lists
  double analysis_seconds = 0;  //   the rounds of analysis (the exposed bodies)
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

#pragma once
// slice-stability through the real tools, shared by its integration tests
// (tests/integration/stability_test.cpp, stability_invariants_test.cpp): a run read back, its
// /stability and /contacts read with h5py (Debian's python3) and checked against the contract's
// rules; an independent limit-equilibrium analysis of a block's faces; the scenes with closed
// forms (a block on a plane, Hoek & Bray's wedge, a hanging block, Goodman's roof in any frame).
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "support/support.hpp"

namespace test::stability {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kRho = 2650, kG = 9.81;  // the tool's default density; g along -z
inline constexpr double kRhoWater = 1000;
double rad(double deg);
double tand(double deg);

/// The upward unit normal of a plane (docs/scenes.md, "Angles").
slice::Vec3 upward_normal(double dip, double dd);

/// x with 17 significant digits, for a scene or an option.
std::string num(double x);

// --- running the tools ---------------------------------------------------------------------------

/// slice-joints -> slice-cut --prune -> slice-vertices on a scene text (test::geometry_of_text),
/// into tmp/<stem>-*: returns the path of <stem>-geom.h5 (<stem>-blocks.h5 stays beside it).
/// The stem keeps them apart from run_pipeline's geom.h5 in the same tmp.
std::string geometry_of(const TempDir& tmp, const std::string& scene,
                        const std::string& stem = "scene");

/// A row of /contacts.
struct Contact {
  std::int64_t a = -1, b = -1, face_a = -1, face_b = -1, joint = -1;
  double area = 0, fraction = 0;
  slice::Vec3 centroid = slice::Vec3::Zero(), normal = slice::Vec3::Zero();  // normal: a's outward
  bool free = false;
};

/// /stability, per block, and /contacts.
struct Stability {
  std::vector<int> removable, mode, generation;
  std::vector<double> fos;
  std::vector<slice::Vec3> direction;
  std::vector<std::array<std::int64_t, 2>> planes;
  std::vector<std::int64_t> group;  // a group failing together: its smallest block; -1 none
  std::vector<Contact> contacts;
};

/// What slice-stability wrote: the blocks (its copy of geom.h5, read and checked by the
/// library) and the new datasets.
struct Model {
  slice::BlockSystem bs;
  Stability st;
  std::vector<std::size_t> face_offset;  // B + 1: the blocks' rows in /blocks/face_*
  std::string path;

  std::size_t blocks() const { return bs.blocks.size(); }
  bool removed(std::int64_t b) const {
    return (bs.blocks[static_cast<std::size_t>(b)].flags & slice::kRemoved) != 0;
  }
  /// Neither removed, boundary nor fixed: a block that may move.
  bool movable(std::size_t b) const {
    return !removed(std::int64_t(b)) && !slice::is_fixed(bs.blocks[b]);
  }
  double volume(std::size_t b) const { return bs.geometry->volume[b]; }
  const slice::Vec3& centroid(std::size_t b) const { return bs.geometry->centroid[b]; }
  double face_area(std::size_t b, std::size_t k) const {
    return bs.geometry->face_area[face_offset[b] + k];
  }
};

/// What a block touches: a row of /contacts seen from the block.
struct Touch {
  std::size_t row = 0;
  std::size_t face = 0;  // the block's own face (index into its faces)
  slice::Vec3 normal;    // the block's outward normal
  std::int64_t other = -1;
  bool free = false;
  double area = 0;
  std::int64_t joint = -1;
};

std::vector<Touch> touches(const Model& m, std::size_t b);

/// The options of a run, and what the contract checks need of them.
struct Run {
  std::vector<std::string> args;  // e.g. {"--free-faces", "+z,+x"}
  std::string free_faces;         // the --free-faces value among them ("" for none)
  double fos_target = 1;
};

/// Runs slice-stability on geom.h5 into tmp/<out>, checks exit 0 and the contract's rules (for
/// every block and contact of any run); returns what it wrote.
Model stability_of(const TempDir& tmp, const std::string& geom, const Run& run,
                   const std::string& out_name = "stab.h5");

/// The blocks that may move.
std::vector<std::size_t> movable_blocks(const Model& m);

/// The area of block b's contacts on joint j.
double area_on(const Model& m, std::size_t b, std::int64_t j);

std::set<std::int64_t> plane_set(const std::array<std::int64_t, 2>& p);

// --- limit equilibrium, independently of the tool ------------------------------------------------

/// A face a body presses on: its outward unit normal, tan(phi), c A [N], the joint.
struct Bearing {
  slice::Vec3 m;
  double tan_phi = 0;
  double cohesion_force = 0;
  std::int64_t joint = -1;
};

struct Motion {
  bool removable = false;
  int mode = 1;
  slice::Vec3 direction = slice::Vec3::Zero();
  std::set<std::int64_t> planes{-1};
  double fos = kInf;
  int found = 0;  // modes that fit: more than one would make the scene ambiguous
};

/// Londe's and Goodman & Shi's modes under the resultant r: falls (leaves every face), slides on
/// one face (pressed on it, leaving the others) or on two (pressed on both, along their line);
/// FoS by limit equilibrium: one plane (c A + N tan phi) / S, two planes (c_A A_A + c_B A_B + N_A
/// tan phi_A + N_B tan phi_B) / (r along the line), N from equilibrium across the line.
Motion limit_equilibrium(const std::vector<Bearing>& faces, const slice::Vec3& r);

// --- scenes --------------------------------------------------------------------------------------

/// A block on a plane of dip 30 dipping east: the domain [0, 12] x [0, 4] x [0, 8], the plane
/// through (6, 2, 5), so z = 8 at x = 6 - 3 / tan 30 and z = 5 - 6 tan 30 = 1.536 at x = 12; the
/// rock below it touches the base and is fixed. With --free-faces +z,+x,-y,+y the block above
/// touches nothing but the plane. `cluster`: a vertical construction joint at x = 9 cuts it into
/// two blocks that move as one.
std::string plane_scene(double phi, double cohesion, bool cluster = false);
inline constexpr double kPlaneDip = 30;
inline const std::string kPlaneFree = "+z,+x,-y,+y";

/// The block on that plane in closed form: its length in plan l = 6 + 3 / tan a (from z = 8 down
/// to x = 12), width 4.
struct PlaneBlock {
  double a = rad(kPlaneDip);
  double l = 6 + 3 / std::tan(a);
  double volume = 4 * 0.5 * l * l * std::tan(a);  // a right prism on the triangle l by l tan a
  double area = 4 * l / std::cos(a);              // the contact on the plane
  double z_low = 5 - 6 * std::tan(a);             // its lowest edge (x = 12)
  double z_centroid = (8 + z_low) / 2;            // the contact's centroid
  double area_east = 4 * (8 - z_low);             // the free face x = 12
  double area_top = 4 * l;                        // the free face z = 8
  slice::Vec3 down_dip = slice::Vec3(std::cos(a), 0, -std::sin(a));
  slice::Vec3 outward = -upward_normal(kPlaneDip, 90);  // the block's, on the plane
};

/// Itasca's 3DEC "Sliding Wedge" verification (Hoek & Bray): planes A (40/130) and B (60/220)
/// through (10, 10, 12) in a 20 m cube, both boundary joints keeping what lies below them; the
/// wedge above both is the one block that moves. Run with every face but the base free.
std::string wedge_scene(double phi_a, double phi_b, double c_a, double c_b);

/// A block hanging from a fixed block above it by the tension t of the joint between them: the
/// domain [0, 4]^3, the joint z = 2; run with every face but the top free.
std::string hanging_scene(double tension);

/// A similarity of the plan: turn by `turn_deg` about the vertical through the origin (clockwise
/// seen from above, as azimuths turn: a dip direction gains turn_deg), scale, then shift.
struct Frame {
  double turn_deg = 0;
  double scale = 1;
  slice::Vec3 shift = slice::Vec3::Zero();

  slice::Vec3 vector(const slice::Vec3& v) const;
  slice::Vec3 back(const slice::Vec3& v) const;  // vector's inverse
  slice::Vec3 point(const slice::Vec3& p) const;
  double azimuth(double az) const;
};

/// Goodman's three sets (Brady & Brown's example: 30/90, 60/45, 20/330), regular at 2 m, over an
/// opening: the domain [0, 20] x [0, 20] x [0, 14], a horizontal rock joint z = 7 for the roof
/// and the zone [5, 15] x [5, 15] x [3, 7] below it removed (its walls and floor are as rough as
/// the blocks). `cohesion`: of J1, J2, J3 [Pa, before scaling]; friction 40, 35, 35 (the roof
/// joint 30, no cohesion). In the frame f: dip directions turned, lengths and cohesion scaled (so
/// c / (rho g L) and every FoS stay), points shifted.
std::string goodman_scene(const Frame& f, const std::array<double, 3>& cohesion = {0, 0, 0});

/// The text of tests/data/stability/<name>.
std::string data_scene(const std::string& name);

void check_direction(const slice::Vec3& got, const slice::Vec3& want, double tol = 1e-9);

}  // namespace test::stability

#pragma once
// 3DEC models: the rigid blocks in 3DEC's ASCII grid format (".3dgrid", read by 3DEC's
// `block import filename "model.3dgrid"`), and a command file that imports them and makes them a
// runnable model. docs/3dec.md gives the rules, the commands and the Itasca pages they rest on.
//
// The grid file, as 3DEC's `block import` documents it: `*` comment lines; a `TOL` line (3DEC's
// tolerance ATOL, as 3DEC's own grid export writes it); `G id x y z` gridpoints; `F id g1 g2 g3
// ...` faces; `B id zone-id F f1 f2 ...` rigid blocks; `JS id b1-b2 ...` joint-set IDs of block
// contacts. Here:
//   - one block per block of blocks.h5 that is not removed; its ID is its row in blocks.h5 + 1
//     (3DEC IDs are positive), so gaps mark the removed blocks; zone-id 1;
//   - every block has its own gridpoints and faces; IDs count up from 1 in block order;
//   - a face's gridpoints go clockwise seen from outside the block, as Itasca's `block create`
//     documents polyhedron faces; /geometry's loops go the other way and are written backwards;
//   - TOL = min(0.0012 x the mean extent of the kept blocks in x, y, z (3DEC's default ATOL),
//     0.2 x the shortest edge of a kept block (Itasca: ATOL at most 20 % of the smallest block
//     edge)), and never below the scene's tolerance x its length scale;
//   - JS lines: two kept blocks with faces on the same rock or boundary joint, facing each other
//     and overlapping with positive area, are a contact. Joint-set IDs (ThreeDecJointSets): set
//     s is s + 1; the k-th [[joints]] entry (set -1, in /joints order) is sets + 1 + k; with a
//     [rock] table, a rock-bridge contact (at most half of it on its joint's polygon, by
//     /geometry/face_joint_fraction) gets its joint's ID + (sets + [[joints]] entries).
//     Construction joints and domain faces give none;
//   - numbers in their shortest exact form: the same blocks give the same bytes.
// The command file (".dat"): imports the grid; sets the density; joins the blocks of each
// cluster (group "cluster-c" in slot "cluster", `block join`); puts boundary and fixed blocks in
// group "boundary" (fixed); gives every contact Mohr-Coulomb properties (stiffness, friction,
// cohesion, tension) by joint-set ID. Scene text (its name, set names) appears only in comment
// lines, with control characters escaped, and the grid file's name is quoted: no text of the
// scene or the command line adds a line to either file.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "slice/dem.hpp"
#include "slice/h5io.hpp"

namespace slice {

/// What the command file sets beyond the geometry. Units: SI (the scene in metres).
struct ThreeDecOptions {
  double density = 2650;     // kg/m3, every block (block property density)
  double jkn = 1e10;         // Pa/m, joint normal stiffness of every contact
  double jks = 1e9;          // Pa/m, joint shear stiffness of every contact
  double friction_deg = 30;  // contacts 3DEC finds beyond the JS lines (joint set 0)
  /// Throws Error naming the first bad option (--3dec-density, ...).
  void validate() const;
};

/// 3DEC's critical time step of rigid blocks: frac x 2 sqrt(m_min / k_max), frac = 0.1
/// (docs/3dec.md).
inline constexpr double kThreeDecTimestepFrac = 0.1;

struct ThreeDecStats {
  std::size_t blocks = 0, faces = 0, gridpoints = 0;
  std::size_t contacts = 0;         // block pairs on JS lines
  std::size_t bridge_contacts = 0;  // of which rock bridges (intact-rock properties)
  std::size_t joint_sets = 0;       // JS IDs with contacts (each gets its properties)
  std::size_t removed = 0;          // blocks left out
  std::size_t fixed = 0;            // in group "boundary"
  std::size_t clusters = 0;         // joined groups "cluster-c"
  double tol = 0;                   // the TOL line
  // What sets the time step: the bodies (dem.hpp: a joined cluster is one body), the mass of
  // the smallest moving one, the largest contact and 3DEC's critical time step.
  DemBodies dem;
  double min_mass = 0;               // kg, density x dem.moving_volume
  double max_contact_area = 0;       // m2, the largest JS contact (or face, if none)
  double max_contact_stiffness = 0;  // N/m, jkn x max_contact_area
  double critical_timestep = 0;      // s; 0 if there is no free body
};

/// Writes `grid` and `commands` atomically (each through "<file>.partial"). Needs bs.geometry;
/// throws Error if it is missing, for a 2-D section (dimension 2: no 3DEC polyhedra), if the
/// grid's name cannot be written as a 3DEC string (a control character, or both quote marks),
/// or if a file cannot be written. The command file names the grid by its file name if both are
/// in one directory, else by its absolute path.
ThreeDecStats write_3dec(const std::filesystem::path& grid, const std::filesystem::path& commands,
                         const BlockSystem& bs, const ThreeDecOptions& opt = {});

}  // namespace slice

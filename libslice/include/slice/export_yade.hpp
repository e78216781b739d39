#pragma once
// YADE models (docs/design.md, "Exports"; docs/dem-exports.md): a Python script that `yade -n -x
// model.py` runs as is, with the block data inside it (one line per block). Two shapes:
//   polyhedra         vertex-based Polyhedra bodies (YADE as Debian packages it);
//   potential_blocks  face-based PotentialBlock bodies (YADE built with ENABLE_POTENTIAL_BLOCKS;
//                     the script stops with a clear message on a YADE without them).
// Rules, the same for both:
//   - one body per block that is not removed;
//   - Polyhedra, law mohr_coulomb (the default; docs/dem-exports.md, "The contact law"): each
//     contact of two blocks across a joint (contacts.hpp) has its joint's friction, cohesion and
//     tension ([rock]'s for a rock bridge), in the script's CONTACTS (yade_contacts); a contact
//     made later as blocks move (and any contact of a 2-D section, which has no CONTACTS yet)
//     gets the smaller of its two blocks' friction angles (the rule below), no cohesion or
//     tension;
//   - law volumetric, and PotentialBlock: one material per block; its friction angle is the
//     smallest friction angle of the joints of the block's faces, over rock and boundary joints
//     (domain faces and construction joints are no contacts and carry none), rock bridges
//     weighted in with [rock]'s (see block_friction_deg); a block with no such face gets
//     default_friction_deg;
//   - boundary blocks are fixed (blockedDOFs 'xyzXYZ');
//   - the blocks of a cluster (joined across construction joints) are one clump; a clump with a
//     boundary block is fixed;
//   - engines for a settling run under gravity along -z; with steps > 0 the script runs them.
// A 2-D section (dimension 2, docs/2d.md) is written as Polyhedra prisms of unit thickness (each
// polygon at y = -0.5 and y = 0.5; YADE computes their mass and inertia from the vertices, as in
// 3-D) whose bodies and clumps, unless fixed, have blockedDOFs 'yXZ' (they move in (x, z) and
// turn about y only). potential_blocks refuses a section (Error).
// Numbers are written in their shortest exact form, so the same blocks give the same bytes.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "slice/dem.hpp"
#include "slice/h5io.hpp"

namespace slice {

enum class YadeShape { polyhedra, potential_blocks };
/// The Polyhedra contact law: mohr_coulomb, rockslice's per-contact law on YADE's polyhedra
/// geometry (each contact its own shear force and its joint's strength); volumetric, YADE's
/// Law2_PolyhedraGeom_PolyhedraPhys_Volumetric alone (in YADE 2023.02a its shear force is shared
/// by all contacts: wrong for a body with two or more).
enum class YadeLaw { mohr_coulomb, volumetric };
/// The law's name in scripts and options: "mohr-coulomb" or "volumetric".
const char* to_string(YadeLaw law);
/// The law `name` names (slice-export's --yade-law); throws Error naming --yade-law otherwise.
YadeLaw parse_yade_law(const std::string& name);

/// YADE Polyhedra bodies are their blocks scaled by 1 - kYadeInitialGap about the centroid, so
/// that faces that touch open a little (the script's comment before SHRINK says why).
inline constexpr double kYadeInitialGap = 1e-6;

/// The most steps --yade-steps may ask for (issue 42 item 9): 30 years at a million a second.
inline constexpr long kYadeMaxSteps = 1'000'000'000'000'000;

struct YadeOptions {
  YadeShape shape = YadeShape::polyhedra;
  YadeLaw law = YadeLaw::mohr_coulomb;
  long steps = 0;                    // 0: build the model only; N: run N steps at the end
  double density = 2650;             // kg/m3 (granite-like rock)
  double young = 1e9;                // Polyhedra: PolyhedraMat.young, the volumetric contact
                                     //   stiffness [N/m3]; PotentialBlock: kn [N/m] per m2
  double poisson = 0.25;             // Polyhedra: shear/normal stiffness ratio (PolyhedraMat)
  double default_friction_deg = 30;  // blocks with no rock or boundary joint face
  double damping = 0.3;              // NewtonIntegrator's numerical damping
  double gravity = 9.81;             // m/s2, along -z
  double timestep_factor = 0.2;      // O.dt = factor * sqrt(m / k) of the smallest block
  double pb_rounding = 0.05;         // PotentialBlock r = pb_rounding * inscribed radius
  std::string source;                // the input file, named in the script's header
  /// Throws Error naming the first bad option.
  void validate() const;
};

struct YadeStats {
  std::size_t bodies = 0, fixed = 0, clumps = 0, removed = 0;  // bodies: blocks written
  std::size_t contacts = 0, bridges = 0;  // rows of CONTACTS; of them, rock bridges
  DemBodies dem;        // the model's rigid bodies, the smallest free block and moving body
  double timestep = 0;  // O.dt the script sets (yade_timestep)
};

/// The friction angle [degrees] the rule above gives block `b` of `bs`. With a [rock] table in
/// the scene (bs.joints.rock.given) and /geometry, each face's angle is weighted by its
/// face_joint_fraction f: f x the joint's + (1 - f) x [rock]'s friction_angle, since a rock
/// bridge (f < 1) is intact rock. Per body, this is all YADE's volumetric law can take (no
/// cohesion or tension; a contact gets the smaller of its two bodies' angles); the per-contact
/// law (yade_contacts) falls back on it for contacts the model does not list.
/// `first_face`: block b's first row in /geometry's per-face arrays.
double block_friction_deg(const BlockSystem& bs, std::size_t b, std::size_t first_face,
                          double default_friction_deg);
/// The same, finding first_face by counting the faces of blocks 0 .. b - 1.
double block_friction_deg(const BlockSystem& bs, std::size_t b, double default_friction_deg);

/// A row of the script's CONTACTS: two kept blocks touching across a joint (contacts.hpp), with
/// the strength the law gives the contact: its joint's friction angle [deg], cohesion and
/// tension [Pa], or [rock]'s where the contact is a rock bridge (is_rock_bridge). One row per
/// pair of blocks (the contact of largest area if a pair touches on two joints).
struct YadeContact {
  std::size_t a = 0, b = 0;
  double friction_deg = 0, cohesion = 0, tension = 0, area = 0;
  Vec3 centroid = Vec3::Zero(), normal = Vec3::UnitZ();  // normal: from a towards b
  bool bridge = false;
};
std::vector<YadeContact> yade_contacts(const BlockSystem& bs);

/// Writes the script atomically (to "<out>.partial", renamed when complete). Needs bs.geometry
/// (slice-vertices); throws Error if missing or if the file cannot be written.
YadeStats write_yade_script(const std::filesystem::path& out, const BlockSystem& bs,
                            const YadeOptions& opt);

}  // namespace slice

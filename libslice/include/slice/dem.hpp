#pragma once
// What a DEM run of the blocks will see (docs/design.md, "Bodies and the time step"): its bodies
// (a kept block in no cluster, or a cluster of kept blocks moving as one), the smallest of them,
// and the critical time step the exported YADE model takes from it. Needs /geometry.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "slice/h5io.hpp"

namespace slice {

struct DemBodies {
  std::size_t bodies = 0;  // kept blocks in no cluster + clusters
  std::size_t clumps = 0;  // clusters of two or more kept blocks
  std::size_t fixed = 0;   // bodies that hold a boundary or fixed block: they never move
  /// The smallest free block: kept, in no cluster, not fixed. block < 0: there is none.
  std::int64_t free_block = -1;
  double free_volume = 0, free_inradius = 0;
  /// The smallest body that moves (a free block or a cluster that is not fixed), which sets the
  /// time step: its volume (a cluster's is the sum of its blocks'), its first block and its
  /// cluster (-1 for a block on its own). block < 0: nothing moves.
  std::int64_t moving_block = -1, moving_cluster = -1;
  double moving_volume = 0;
};

/// The bodies of the model slice-export writes (removed blocks left out). Throws Error without
/// /geometry.
DemBodies dem_bodies(const BlockSystem& bs);

/// The time step the exported YADE Polyhedra script sets (export_yade.hpp): the smallest moving
/// body of volume V has mass m = density V and, for the volumetric contact law, a contact as large
/// as a face (A ~ V^(2/3)) of stiffness k = young A; dt = factor sqrt(m / k). 0 if nothing moves.
double yade_timestep(const DemBodies& bodies, double density, double young, double factor);

/// The open joint area per unit volume (P32) each set has in the block model: half the sum over
/// the blocks' faces on the set's rock or boundary joints of face area x face_joint_fraction
/// (each point of a cut plane is on the faces of two blocks, one each side), over the volume of
/// all blocks. Entry s for set s; the last entry for the [[joints]] entries (set -1).
std::vector<double> realised_p32(const BlockSystem& bs);

}  // namespace slice

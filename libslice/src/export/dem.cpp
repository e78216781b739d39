#include "slice/dem.hpp"

#include <cmath>
#include <map>

#include "slice/error.hpp"

namespace slice {

DemBodies dem_bodies(const BlockSystem& bs) {
  const Geometry& g = geometry_of(bs, "/geometry");
  struct Cluster {
    std::size_t members = 0, first = 0;
    double volume = 0;
    bool fixed = false;
  };
  std::map<std::int64_t, Cluster> clusters;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    if ((blk.flags & kRemoved) || blk.cluster < 0) continue;
    Cluster& c = clusters[blk.cluster];
    if (c.members++ == 0) c.first = b;
    c.volume += g.volume[b];
    c.fixed = c.fixed || is_fixed(blk);
  }
  DemBodies d;
  const auto moving = [&](std::size_t block, std::int64_t cluster, double volume) {
    if (d.moving_block < 0 || volume < d.moving_volume) {
      d.moving_block = std::int64_t(block);
      d.moving_cluster = cluster;
      d.moving_volume = volume;
    }
  };
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    if (blk.flags & kRemoved) continue;
    // A cluster with one kept block (the others removed) is a block on its own, as in the script.
    if (blk.cluster >= 0 && clusters[blk.cluster].members >= 2) continue;
    ++d.bodies;
    if (is_fixed(blk)) {
      ++d.fixed;
      continue;
    }
    if (d.free_block < 0 || g.volume[b] < d.free_volume) {
      d.free_block = std::int64_t(b);
      d.free_volume = g.volume[b];
      d.free_inradius = blk.inradius;
    }
    moving(b, -1, g.volume[b]);
  }
  for (const auto& [id, c] : clusters) {
    if (c.members < 2) continue;
    ++d.bodies;
    ++d.clumps;
    if (c.fixed)
      ++d.fixed;
    else
      moving(c.first, id, c.volume);
  }
  return d;
}

double yade_timestep(const DemBodies& bodies, double density, double young, double factor) {
  if (bodies.moving_block < 0) return 0;
  return factor * std::sqrt(density * std::cbrt(bodies.moving_volume) / young);
}

std::vector<double> realised_p32(const BlockSystem& bs) {
  const Geometry& g = geometry_of(bs, "/geometry");
  const auto& joints = bs.joints.joints;
  std::vector<double> area(bs.joints.sets.size() + 1, 0.0);
  double volume = 0;
  std::size_t row = 0;  // the face's row in /geometry's per-face arrays
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    volume += g.volume[b];
    for (const Face& f : bs.blocks[b].faces) {
      const std::size_t r = row++;
      if (f.joint < 0) continue;
      const Joint& j = joints[std::size_t(f.joint)];
      if (j.kind == JointKind::construction) continue;
      const std::size_t s = j.set < 0 ? bs.joints.sets.size() : std::size_t(j.set);
      area[s] += 0.5 * g.face_area[r] * g.face_joint_fraction[r];
    }
  }
  for (double& a : area) a = volume > 0 ? a / volume : 0;
  return area;
}

}  // namespace slice

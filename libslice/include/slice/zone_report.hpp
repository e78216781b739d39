#pragma once
// libslice/src/geometry/zone_report.cpp. The removal zones measured: each zone's volume in the
// domain and the part of it above the ground (a [[zones]] surface), which slice-joints warns of
// (issue 43: a bench designed above the ground removed nothing, and nothing said so); and what
// each zone removed of a block system, which slice-info lists (docs/tools.md, docs/scenes.md).
#include <cstdint>
#include <vector>

#include "slice/scene.hpp"

namespace slice {

struct BlockSystem;  // h5io.hpp

/// js.zone_info with volume, ground and volume_above_ground measured (empty if js has none):
///  - a box, planes or tunnel region: its volume inside the domain, and the part of that above
///    the ground, exactly: the region clipped to the domain, then to each ground triangle's
///    vertical prism and the half-space above the triangle's plane, volumes summed;
///  - a mesh zone: ground only, from its vertices inside the domain (any above the ground:
///    partly; all: wholly), so a ridge of ground between vertices is missed; volumes -1;
///  - a surface zone: its volume (the air inside the domain); ground not_checked.
/// The ground is the first surface zone's (its solid's downward triangles). A part of less than
/// a tolerance-thick layer over the zone's plan (tolerance x length scale x plan area) does not
/// count: a zone whose top is the ground is below it. 2-D files and files without a surface
/// zone: volumes only.
std::vector<ZoneInfo> measure_zones(const JointSystem& js);

/// What each zone removed: the removed blocks (BlockFlag kRemoved) by the zone that holds the
/// block's centre (its origin, as slice-cut tested it). A centre above the ground (inside the
/// first surface zone) belongs to the surface: that was air, not rock a zone removed; any other
/// to the first zone that holds it, in zone order (regions, then meshes). Files without
/// zone_info (kinds unknown): the first zone.
struct ZoneRemovals {
  std::vector<std::int64_t> blocks;  // per zone (regions, then meshes)
  std::vector<double> volume;        // per zone; empty without /geometry
  std::int64_t other_blocks = 0;     // removed, centre in no zone: slivers removed with an
  double other_volume = 0;           //   excavation (slivers = "excavate"; docs/scenes.md)
};
ZoneRemovals zone_removals(const BlockSystem& bs);

}  // namespace slice

#pragma once
// The removal zones for people and scripts: slice-info's listing (index as slice-extract
// --near-zone takes it, kind, [[zones]] entry, volume in the domain, what it removed, whether it
// removed rock) and the warning slice-joints and slice-info give for a zone above the ground
// (docs/tools.md, docs/scenes.md "Zones and the ground").
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "slice/scene.hpp"

namespace info {

/// One line per [[zones]] entry that lies wholly or partly above the ground surface (its
/// regions together: a tunnel of several), as slice-joints measured it (/zones/above_ground).
/// None for a file without /zones/kind.
std::vector<std::string> ground_warnings(const slice::JointSystem& js);

/// slice-info --json's `removal_zones` and `removed_outside_zones`, as an object to merge.
/// `removal_zones`: one object per zone, in slice-extract's numbering (regions, then meshes):
/// index, kind ("unknown" in files from before /zones/kind), entry (0-based [[zones]] entry;
/// null if not known), line, cut, volume (in the domain), above_ground, volume_above_ground,
/// removed_blocks, removed_volume, removed_rock (null where the file cannot say: a joints.h5 has
/// no blocks, a blocks.h5 no volumes) and warning (null: none). `removed_outside_zones`: the
/// removed blocks whose centre is in no zone (slivers removed with an excavation), {blocks,
/// volume}; null for a joints.h5. `bs`: the blocks, nullptr for a joints.h5.
nlohmann::ordered_json describe_zones(const slice::JointSystem& js, const slice::BlockSystem* bs);

/// The text listing of describe_zones' object, with the warnings; removes its two keys from `j`
/// so that the plain listing does not repeat them.
std::string zones_text(nlohmann::ordered_json& j);

}  // namespace info

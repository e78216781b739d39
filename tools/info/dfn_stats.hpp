#pragma once
// slice-info's statistics of joint sets (docs/dfn-statistics.md): per set, measured from its
// joints, the mean orientation, Fisher kappa, the 95 % cone, the sizes fitted, the intensity and
// a [[sets]] entry that draws a matching stochastic set; and a DFN file (FAB, CSV) read on its own.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "slice/scene.hpp"

namespace info {

/// The fields each entry of `joints.by_set` gains: mean_dip, mean_dip_direction, fisher_kappa
/// (degrees; fisher_kappa 0 when every joint has one orientation, as a scene's key means it;
/// null without joints), alpha95, and `statistics` (sizes, intensity, the [[sets]] entry).
nlohmann::ordered_json set_statistics(const slice::JointSystem& js, std::size_t set);

/// Text for people: the `statistics` of every by_set entry (removed from `j` so that the plain
/// listing stays one line a set), then the [[sets]] entries.
std::string statistics_text(nlohmann::ordered_json& j);

/// Whether `file` is a DFN file slice-info reads directly: .fab or .csv (any case).
bool is_dfn_file(const std::filesystem::path& file);
/// The joint system of a DFN file on its own: a scene of the box of its fractures' corners (the
/// domain P32 and P10 refer to) and one [[dfn]] entry of the file, with the defaults of
/// docs/scenes.md. Throws slice::Error naming the file.
slice::JointSystem dfn_file_joints(const std::filesystem::path& file);

}  // namespace info

#include "info/zones.hpp"

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/tool.hpp"
#include "slice/zone_report.hpp"

namespace info {

using nlohmann::ordered_json;

namespace {

std::string vol(double v) { return tool::sig(v, 6); }

// "zone 2", "zones 2-5" or "zones 2, 4": a [[zones]] entry's zone numbers.
std::string zone_numbers(const std::vector<std::size_t>& z) {
  if (z.size() == 1) return "zone " + std::to_string(z[0]);
  bool run = true;
  for (std::size_t k = 1; k < z.size(); ++k) run = run && z[k] == z[k - 1] + 1;
  if (run) return "zones " + std::to_string(z.front()) + "-" + std::to_string(z.back());
  std::string s = "zones ";
  for (std::size_t k = 0; k < z.size(); ++k) s += (k ? ", " : "") + std::to_string(z[k]);
  return s;
}

std::string entry_name(const slice::ZoneInfo& i) {
  return "[[zones]] #" + std::to_string(i.entry + 1);
}

// The warning of each [[zones]] entry above the ground, by entry.
std::map<std::int64_t, std::string> entry_warnings(const slice::JointSystem& js) {
  std::map<std::int64_t, std::string> out;
  const auto& info = js.zone_info;
  std::optional<std::size_t> surface;
  for (std::size_t z = js.zones.size(); z < info.size() && !surface; ++z)
    if (info[z].kind == slice::ZoneKind::surface) surface = z;
  if (!surface) return out;
  std::map<std::int64_t, std::vector<std::size_t>> by_entry;
  for (std::size_t z = 0; z < info.size(); ++z) by_entry[info[z].entry].push_back(z);
  for (const auto& [entry, zones] : by_entry) {
    std::size_t above = 0, wholly = 0;
    bool measured = true;
    double volume = 0, air = 0;
    for (const std::size_t z : zones) {
      const slice::ZoneInfo& i = info[z];
      above +=
          i.ground == slice::ZoneGround::partly_above || i.ground == slice::ZoneGround::wholly_above
              ? 1
              : 0;
      wholly += i.ground == slice::ZoneGround::wholly_above ? 1 : 0;
      measured = measured && i.volume >= 0 && i.volume_above_ground >= 0;
      volume += i.volume;
      air += i.volume_above_ground;
    }
    if (above == 0) continue;
    const slice::ZoneInfo& first = info[zones.front()];
    std::string line = entry_name(first) + " (" + slice::to_string(first.kind) + ", line " +
                       std::to_string(first.line) + "; " + zone_numbers(zones) + ") lies " +
                       (wholly == zones.size() ? "wholly" : "partly") +
                       " above the ground surface (" + entry_name(info[*surface]) + ")";
    if (!measured)
      line += ", by its vertices in the domain";
    else if (wholly == zones.size())
      line += ": all " + vol(volume) + " of its volume in the domain is air, so it removes no rock";
    else
      line += ": " + vol(air) + " of its " + vol(volume) + " in the domain (" +
              tool::fixed(100 * air / volume, 1) + " %) is air, where it removes no rock";
    out[entry] = line;
  }
  return out;
}

ordered_json or_null(double v) { return v >= 0 ? ordered_json(v) : ordered_json(nullptr); }

}  // namespace

std::vector<std::string> ground_warnings(const slice::JointSystem& js) {
  std::vector<std::string> out;
  for (const auto& [entry, line] : entry_warnings(js)) out.push_back(line);
  return out;
}

ordered_json describe_zones(const slice::JointSystem& js, const slice::BlockSystem* bs) {
  const std::size_t n = js.zones.size() + js.zone_meshes.size();
  const bool known = js.zone_info.size() == n;
  const auto warnings = entry_warnings(js);
  std::optional<slice::ZoneRemovals> removed;
  if (bs) removed = slice::zone_removals(*bs);
  const bool volumes = removed && !removed->volume.empty();
  ordered_json zones = ordered_json::array();
  for (std::size_t z = 0; z < n; ++z) {
    ordered_json o;
    o["index"] = z;
    if (known) {
      const slice::ZoneInfo& i = js.zone_info[z];
      const auto w = warnings.find(i.entry);
      o["kind"] = slice::to_string(i.kind);
      o["entry"] = i.entry >= 0 ? ordered_json(i.entry) : ordered_json(nullptr);
      o["line"] = i.line > 0 ? ordered_json(i.line) : ordered_json(nullptr);
      o["cut"] = i.cut;
      o["volume"] = or_null(i.volume);
      o["above_ground"] = slice::to_string(i.ground);
      o["volume_above_ground"] = or_null(i.volume_above_ground);
      o["warning"] = w == warnings.end() ? ordered_json(nullptr) : ordered_json(w->second);
    } else {  // a file from before /zones/kind: only what the zone's shape says
      o["kind"] = "unknown";
      for (const char* k : {"entry", "line", "cut", "volume"}) o[k] = nullptr;
      o["above_ground"] = slice::to_string(slice::ZoneGround::not_checked);
      o["volume_above_ground"] = nullptr;
      o["warning"] = nullptr;
    }
    const bool air = known && js.zone_info[z].kind == slice::ZoneKind::surface;
    o["removed_blocks"] = removed ? ordered_json(removed->blocks[z]) : ordered_json(nullptr);
    o["removed_volume"] = volumes ? ordered_json(removed->volume[z]) : ordered_json(nullptr);
    // A surface removes the air above the ground; any other zone rock, if it removed anything.
    o["removed_rock"] = !removed  ? ordered_json(nullptr)
                        : air     ? ordered_json(false)
                        : volumes ? ordered_json(removed->volume[z] > 0)
                                  : ordered_json(removed->blocks[z] > 0);
    zones.push_back(o);
  }
  ordered_json outside = nullptr;
  if (removed)
    outside = {{"blocks", removed->other_blocks},
               {"volume", volumes ? ordered_json(removed->other_volume) : ordered_json(nullptr)}};
  return {{"removal_zones", zones}, {"removed_outside_zones", outside}};
}

std::string zones_text(ordered_json& j) {
  if (!j.contains("removal_zones")) return "";
  const ordered_json zones = j["removal_zones"], outside = j["removed_outside_zones"];
  j.erase("removal_zones");
  j.erase("removed_outside_zones");
  if (zones.empty()) return "";
  std::string s = "removal zones (index: as slice-extract --near-zone takes it):\n";
  if (zones.front()["removed_blocks"].is_null())
    s += "  (what each zone removed needs blocks (slice-cut), its volume geom.h5 "
         "(slice-vertices))\n";
  const auto number = [](const ordered_json& v) {
    return v.is_null() ? std::string("?") : vol(v.get<double>());
  };
  std::vector<std::string> warnings;
  for (const auto& z : zones) {
    std::string line =
        "  " + std::to_string(z["index"].get<std::size_t>()) + "  " + z["kind"].get<std::string>();
    if (!z["entry"].is_null())
      line += ", [[zones]] #" + std::to_string(z["entry"].get<std::int64_t>() + 1);
    if (!z["line"].is_null())
      line += " (line " + std::to_string(z["line"].get<std::int64_t>()) + ")";
    if (!z["cut"].is_null()) line += z["cut"].get<bool>() ? ", cut" : "";
    if (!z["volume"].is_null()) line += ": " + number(z["volume"]) + " in the domain";
    const std::string ground = z["above_ground"].get<std::string>();
    if (ground == "partly above")
      line += ", " + number(z["volume_above_ground"]) + " of it above the ground";
    else if (ground != "not checked")
      line += ", " + ground + " the ground";
    if (!z["removed_blocks"].is_null()) {
      line += "; removed " + std::to_string(z["removed_blocks"].get<std::int64_t>()) + " blocks";
      if (!z["removed_volume"].is_null()) line += ", " + number(z["removed_volume"]);
      line += z["kind"] == "surface"          ? ", the air above the ground"
              : z["removed_rock"].get<bool>() ? ", rock"
                                              : ", no rock";
    }
    s += line + "\n";
    if (!z["warning"].is_null()) {
      const std::string w = z["warning"].get<std::string>();
      if (warnings.empty() || warnings.back() != w) warnings.push_back(w);
    }
  }
  if (!outside.is_null() && outside["blocks"].get<std::int64_t>() > 0)
    s += "  removed in no zone (slivers removed with an excavation): " +
         std::to_string(outside["blocks"].get<std::int64_t>()) + " blocks" +
         (outside["volume"].is_null() ? "" : ", " + number(outside["volume"])) + "\n";
  for (const std::string& w : warnings) s += "warning: " + w + "\n";
  return s;
}

}  // namespace info

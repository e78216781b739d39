// slice-info: what a rockslice HDF5 file holds, as text or JSON (stdout).
#include <array>
#include <cmath>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "common/tool.hpp"
#include "info/dfn_stats.hpp"
#include "info/zones.hpp"
#include "slice/dem.hpp"
#include "slice/export_yade.hpp"
#include "slice/h5io.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"
#include "slice/shape.hpp"
#include "slice/stability.hpp"

namespace {

using nlohmann::ordered_json;

ordered_json describe_joints(const slice::JointSystem& js) {
  ordered_json j;
  j["name"] = js.name;
  j["seed"] = js.seed;
  const auto poly = slice::analyse_polytope(slice::solid_region(js.domain, js.dimension),
                                            js.options.tolerance * js.length_scale);
  const auto xyz = [](const slice::Vec3& v) {  // + 0.0 prints -0.0 as 0
    return ordered_json::array({v.x() + 0.0, v.y() + 0.0, v.z() + 0.0});
  };
  j["domain"] = {{"planes", js.domain.planes.size()},
                 {"min", xyz(poly.min)},
                 {"max", xyz(poly.max)},
                 {"volume", poly.volume},
                 {"length_scale", js.length_scale}};
  j["options"] = {{"order", slice::to_string(js.options.order)},
                  {"min_inscribed_diameter", js.options.min_inscribed_diameter},
                  {"max_aspect_ratio", js.options.max_aspect_ratio},
                  {"tolerance", js.options.tolerance},
                  {"max_blocks", js.options.max_blocks},
                  {"fixed_faces", slice::fixed_faces_string(js.options.fixed_faces)},
                  {"slivers", slice::kSliverRuleNames[std::size_t(js.options.slivers)]}};
  std::map<std::string, std::size_t> by_kind{{"rock", 0}, {"construction", 0}, {"boundary", 0}};
  std::size_t persistent = 0;
  std::vector<std::size_t> per_set(js.sets.size(), 0);
  std::size_t deterministic = 0;
  for (const auto& jt : js.joints) {
    ++by_kind[slice::to_string(jt.kind)];
    persistent += jt.persistent() ? 1 : 0;
    if (jt.set < 0)
      ++deterministic;
    else
      ++per_set[std::size_t(jt.set)];
  }
  ordered_json sets = ordered_json::array();
  for (std::size_t s = 0; s < js.sets.size(); ++s) {
    sets.push_back({{"name", js.sets[s].name},
                    {"joints", per_set[s]},
                    {"intensity", slice::to_string(js.sets[s].intensity)},
                    {"size", slice::to_string(js.sets[s].size.distribution)},
                    {"p32", js.sets[s].achieved_p32},
                    {"p10", js.sets[s].achieved_p10}});
    sets.back().update(info::set_statistics(js, s));  // measured: docs/dfn-statistics.md
    const slice::TraceMapping& m = js.sets[s].mapping;
    if (!m.given) continue;
    // The traces on the set's mapping window, beside the trace lengths mapped there.
    const slice::TraceStats& t = js.sets[s].traces;
    const auto or_null = [](double v) { return v > 0 ? ordered_json(v) : ordered_json(nullptr); };
    sets.back()["traces"] = {{"count", t.count},
                             {"censored", {t.censored[0], t.censored[1], t.censored[2]}},
                             {"mean", t.mean},
                             {"sd", t.sd},
                             {"complete_mean", t.complete_mean},
                             {"p21", t.p21},
                             {"mapped_mean", or_null(m.field_mean)},
                             {"mapped_sd", or_null(m.field_sd)},
                             {"window",
                              {{"point", xyz(m.centre)},
                               {"dip", m.dip_deg},
                               {"dip_direction", m.dip_direction_deg},
                               {"width", m.width},
                               {"height", m.height}}}};
  }
  j["joints"] = {{"total", js.joints.size()},
                 {"persistent", persistent},
                 {"polygons", js.joints.size() - persistent},
                 {"deterministic", deterministic},
                 {"by_kind", by_kind},
                 {"by_set", sets}};
  j["zones"] = js.zones.size();
  j["zone_meshes"] = js.zone_meshes.size();  // [[zones]] mesh excavations
  return j;
}

// What sets the time step of the DEM model slice-export writes (removed blocks left out).
ordered_json describe_bodies(const slice::BlockSystem& bs, const slice::YadeOptions& yade) {
  const slice::DemBodies d = slice::dem_bodies(bs);
  ordered_json j = {{"bodies", d.bodies}, {"clumps", d.clumps}, {"fixed", d.fixed}};
  j["smallest_free_block"] = d.free_block < 0 ? ordered_json(nullptr)
                                              : ordered_json{{"block", d.free_block},
                                                             {"volume", d.free_volume},
                                                             {"inradius", d.free_inradius}};
  j["smallest_moving_body"] = d.moving_block < 0 ? ordered_json(nullptr)
                                                 : ordered_json{{"block", d.moving_block},
                                                                {"cluster", d.moving_cluster},
                                                                {"volume", d.moving_volume}};
  j["yade_timestep"] = {
      {"dt", slice::yade_timestep(d, yade.density, yade.young, yade.timestep_factor)},
      {"density", yade.density},
      {"young", yade.young},
      {"timestep_factor", yade.timestep_factor}};
  return j;
}

// Kept blocks by shape class of the block shape diagram (docs/block-shape.md): removed blocks
// are left out, so the classes' volumes add up to the kept volume. A 2-D section has none.
ordered_json describe_shapes(const slice::BlockSystem& bs) {
  if (bs.joints.dimension != 3) return nullptr;
  const auto& g = *bs.geometry;
  std::vector<bool> keep(bs.blocks.size());
  std::size_t kept = 0;
  double volume = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    keep[b] = (bs.blocks[b].flags & slice::kRemoved) == 0;
    kept += keep[b] ? 1 : 0;
    volume += keep[b] ? g.volume[b] : 0;
  }
  const auto shapes = slice::block_shapes(bs.blocks, g, bs.joints.dimension);
  // The kept blocks by class: MBSCT's classes (kalenchuk false) or UnBlocks-gen's on beta_k.
  const auto by_class = [&](bool kalenchuk) {
    const slice::ShapeSummary s = slice::summarise_shapes(shapes, g.volume, keep, kalenchuk);
    ordered_json out = ordered_json::array();
    for (std::size_t c = 0; c < slice::kShapeClasses.size(); ++c)
      out.push_back({{"class", slice::to_string(slice::kShapeClasses[c])},
                     {"blocks", s.count[c]},
                     {"volume", s.volume[c]},
                     {"volume_fraction", volume > 0 ? s.volume[c] / volume : 0.0}});
    return out;
  };
  // Kalenchuk's beta (UnBlocks-gen's eq. 5) beside the classes: its range over the kept blocks
  // where it is defined.
  std::size_t defined = 0;
  double lo = INFINITY, hi = -INFINITY, sum = 0;
  for (std::size_t b = 0; b < shapes.size(); ++b)
    if (keep[b] && !std::isnan(shapes[b].beta_k)) {
      ++defined;
      lo = std::min(lo, shapes[b].beta_k);
      hi = std::max(hi, shapes[b].beta_k);
      sum += shapes[b].beta_k;
    }
  const ordered_json beta_k =
      defined == 0
          ? ordered_json{{"blocks", 0}}
          : ordered_json{
                {"blocks", defined}, {"min", lo}, {"mean", sum / double(defined)}, {"max", hi}};
  return {
      {"method", "alpha = A lbar / (7.7 V), beta = MBSCT elongation index: docs/block-shape.md"},
      {"blocks", kept},
      {"volume", volume},
      {"by_class", by_class(false)},
      {"beta_kalenchuk", beta_k},
      {"method_kalenchuk",
       "UnBlocks-gen's classes (plotTools.py: alpha 2, 3, 5; beta_k 4, 7) on alpha and "
       "Kalenchuk's beta_k: docs/block-shape.md"},
      {"by_class_kalenchuk", by_class(true)}};
}

// /stability and /contacts (slice-stability): blocks and their volume by mode and by the round
// they fail in; a cluster's members count one by one.
ordered_json describe_stability(const slice::BlockSystem& bs) {
  const auto& st = *bs.stability;
  const auto& r = st.result;
  const auto& g = *bs.geometry;
  const auto& o = r.options;
  ordered_json j;
  j["options"] = {{"density", o.density},
                  {"seismic", o.seismic},
                  {"seismic_azimuth", o.seismic_azimuth_deg},
                  {"water_table", o.water_table ? ordered_json(*o.water_table) : nullptr},
                  {"support_pressure", o.support_pressure},
                  {"free_faces", slice::fixed_faces_string(o.free_faces)},
                  {"fos_target", o.fos_target},
                  {"max_group", o.max_group}};
  std::size_t free = 0;
  for (const auto f : st.contacts.free) free += f;
  j["contacts"] = {{"total", st.contacts.size()}, {"free", free}};
  std::array<std::size_t, 6> mode_blocks{};
  std::array<double, 6> mode_volume{};
  std::map<std::int32_t, std::pair<std::size_t, double>> rounds;
  std::size_t exposed = 0, removable = 0, failing = 0;
  double failing_volume = 0, min_fos = INFINITY;
  std::int64_t min_block = -1, largest = -1;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    if (bs.blocks[b].flags & slice::kRemoved) continue;
    const auto m = r.mode[b];
    ++mode_blocks[m];
    mode_volume[m] += g.volume[b];
    exposed += m > 0 ? 1 : 0;
    removable += r.removable[b];
    if (r.fos[b] < min_fos) min_fos = r.fos[b], min_block = std::int64_t(b);
    if (r.generation[b] >= 0) {
      ++failing;
      failing_volume += g.volume[b];
      auto& [n, v] = rounds[r.generation[b]];
      ++n;
      v += g.volume[b];
      if (largest < 0 || g.volume[b] > g.volume[std::size_t(largest)]) largest = std::int64_t(b);
    }
  }
  j["exposed"] = exposed;
  j["removable"] = removable;
  j["failing"] = failing;
  j["failing_volume"] = failing_volume;
  std::set<std::int64_t> groups;
  std::size_t in_groups = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b)
    if (r.group[b] >= 0 && !(bs.blocks[b].flags & slice::kRemoved))
      groups.insert(r.group[b]), ++in_groups;
  j["failing_in_groups"] = {{"groups", groups.size()}, {"blocks", in_groups}};
  j["min_fos"] = min_block < 0 || std::isinf(min_fos)
                     ? ordered_json(nullptr)
                     : ordered_json{{"fos", min_fos}, {"block", min_block}};
  j["largest_failing_block"] =
      largest < 0 ? ordered_json(nullptr)
                  : ordered_json{{"block", largest}, {"volume", g.volume[std::size_t(largest)]}};
  ordered_json by_mode = ordered_json::array();
  for (std::size_t m = 0; m < 6; ++m)
    by_mode.push_back({{"mode", m},
                       {"name", slice::to_string(slice::FailureMode(m))},
                       {"blocks", mode_blocks[m]},
                       {"volume", mode_volume[m]}});
  j["by_mode"] = by_mode;
  ordered_json by_round = ordered_json::array();
  for (const auto& [k, nv] : rounds)
    by_round.push_back({{"round", k}, {"blocks", nv.first}, {"volume", nv.second}});
  j["by_round"] = by_round;
  return j;
}

/// JSON text; bytes that are no UTF-8 (a Latin-1 path in the provenance) become U+FFFD rather
/// than an exception.
std::string dump(const ordered_json& j, int indent = -1) {
  return j.dump(indent, ' ', false, ordered_json::error_handler_t::replace);
}

void print_text(const ordered_json& j, const std::string& indent = "") {
  for (const auto& [key, value] : j.items()) {
    if (value.is_object()) {
      std::cout << indent << key << ":\n";
      print_text(value, indent + "  ");
    } else if (value.is_array() && !value.empty() && value.front().is_object()) {
      std::cout << indent << key << ":\n";
      for (const auto& item : value) {
        std::cout << indent << "  -";
        for (const auto& [k, v] : item.items()) std::cout << ' ' << k << '=' << dump(v);
        std::cout << '\n';
      }
    } else {
      std::cout << indent << key << ": "
                << (value.is_string() ? value.get<std::string>() : dump(value)) << '\n';
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  tool::Tool t{"slice-info", "Summarise a rockslice HDF5 file (joints.h5 or blocks.h5)."};
  std::string file;
  bool json = false;
  t.cli
      .add_option("file", file,
                  "a .h5 file written by a rockslice tool, or a DFN file (.fab, .csv) to measure "
                  "its sets")
      ->required();
  t.cli.add_flag("--json", json, "print JSON on stdout instead of text");
  slice::YadeOptions yade;  // the time step of geom.h5's YADE model, as slice-export sets it
  tool::add_yade_timestep_options(t.cli, yade);
  return t.run(argc, argv, [&] {
    yade.validate();
    ordered_json j;
    if (info::is_dfn_file(file)) {  // a FAB or CSV on its own: in the box of its fractures
      j["file"] = file;
      j["kind"] = "dfn";
      j["dimension"] = 3;
      j["domain_is"] = "the bounding box of the fractures' corners";
      j.update(describe_joints(info::dfn_file_joints(file)));
      const std::string stats = json ? "" : info::statistics_text(j);
      if (json)
        std::cout << dump(j, 2) << '\n';
      else
        print_text(j), std::cout << stats;
      return;
    }
    const slice::FileHeader h = slice::read_header(file);
    j["file"] = file;
    j["kind"] = slice::to_string(h.kind);
    j["schema"] = h.schema;
    j["schema_version"] = h.schema_version;
    j["dimension"] = h.dimension;
    j["provenance"] = {{"tool", h.provenance.tool},
                       {"version", h.provenance.version},
                       {"command_line", h.provenance.command_line},
                       {"input", h.provenance.input},
                       {"input_sha256", h.provenance.input_sha256}};
    if (h.kind == slice::FileKind::joints) {
      const slice::JointSystem js = slice::read_joints(file);
      j.update(describe_joints(js));
      j.update(info::describe_zones(js, nullptr));  // volumes removed need blocks
    } else {
      const slice::BlockSystem bs = slice::read_blocks(file);
      j.update(describe_joints(bs.joints));
      std::size_t boundary = 0, fixed = 0, removed = 0, faces = 0;
      for (const auto& b : bs.blocks) {
        boundary += (b.flags & slice::kBoundary) ? 1 : 0;
        fixed += (b.flags & slice::kFixed) ? 1 : 0;
        removed += (b.flags & slice::kRemoved) ? 1 : 0;
        faces += b.faces.size();
      }
      j["blocks"] = {{"total", bs.blocks.size()}, {"boundary", boundary}, {"fixed", fixed},
                     {"removed", removed},        {"faces", faces},       {"pruned", bs.pruned}};
      if (bs.geometry) {  // /geometry, from slice-vertices
        const auto& g = *bs.geometry;
        double volume = 0, removed_volume = 0;
        std::size_t bridge_faces = 0;
        for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
          volume += g.volume[b];
          removed_volume += (bs.blocks[b].flags & slice::kRemoved) ? g.volume[b] : 0;
        }
        for (const double f : g.face_joint_fraction) bridge_faces += f < 1 ? 1 : 0;
        j["geometry"] = {{"vertices", g.vertices.size()},
                         {"volume", volume},
                         {"removed_volume", removed_volume},
                         {"rock_bridge_faces", bridge_faces}};
        j["dem"] = describe_bodies(bs, yade);
        j["shape"] = describe_shapes(bs);
        // Beside each set's P32 in the DFN, the open joint area it keeps in the block model.
        const std::vector<double> p32 = slice::realised_p32(bs);
        auto& sets = j["joints"]["by_set"];
        for (std::size_t k = 0; k < sets.size(); ++k) sets[k]["p32_blocks"] = p32[k];
        j["joints"]["p32_blocks_deterministic"] = p32.back();
        if (bs.stability) j["stability"] = describe_stability(bs);
      }
      j.update(info::describe_zones(bs.joints, &bs));
    }
    const std::string stats = json ? "" : info::statistics_text(j);
    const std::string zones = json ? "" : info::zones_text(j);
    if (json)
      std::cout << dump(j, 2) << '\n';
    else
      print_text(j), std::cout << zones << stats;
  });
}

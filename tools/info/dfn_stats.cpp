#include "info/dfn_stats.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "slice/dfn.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/set_statistics.hpp"

namespace info {

using nlohmann::ordered_json;

namespace {

ordered_json number_or_null(double v) { return std::isfinite(v) ? ordered_json(v) : nullptr; }

ordered_json xyz(const slice::Vec3& v) {  // + 0.0 prints -0.0 as 0
  return ordered_json::array({v.x() + 0.0, v.y() + 0.0, v.z() + 0.0});
}

ordered_json fit_json(const slice::SizeFit& f) {
  const slice::SizeSpec& z = f.size;
  ordered_json j = {{"distribution", slice::to_string(z.distribution)}};
  switch (z.distribution) {
    case slice::SizeDistribution::fixed:
      j["value"] = z.value;
      break;
    case slice::SizeDistribution::lognormal:
      j["mean"] = z.mean;
      j["sd"] = z.sd;
      break;
    case slice::SizeDistribution::exponential:
      j["mean"] = z.mean;
      break;
    case slice::SizeDistribution::power_law:
      j["exponent"] = z.exponent;
      j["min"] = z.min;
      j["max"] = z.max;
      break;
    case slice::SizeDistribution::persistent:
      break;
  }
  j["ks"] = f.ks;
  return j;
}

std::string g(double v, int digits = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v + 0.0);
  return buf;
}

std::string fit_text(const ordered_json& f) {
  const std::string d = f["distribution"].get<std::string>();
  std::ostringstream o;
  o << d;
  if (d == "fixed") o << ' ' << g(f["value"].get<double>());
  if (d == "lognormal")
    o << " mean " << g(f["mean"].get<double>()) << " sd " << g(f["sd"].get<double>());
  if (d == "exponential") o << " mean " << g(f["mean"].get<double>());
  if (d == "power-law")
    o << " exponent " << g(f["exponent"].get<double>()) << " on [" << g(f["min"].get<double>())
      << ", " << g(f["max"].get<double>()) << ']';
  o << " (KS " << g(f["ks"].get<double>(), 3) << ')';
  return o.str();
}

}  // namespace

ordered_json set_statistics(const slice::JointSystem& js, std::size_t set) {
  const slice::SetStatistics s = slice::set_statistics(js, set);
  const slice::OrientationStats& o = s.orientation;
  ordered_json out;
  const bool any = s.joints > 0;
  out["mean_dip"] = any ? ordered_json(o.mean_dip_deg) : nullptr;
  out["mean_dip_direction"] = any ? ordered_json(o.mean_dip_direction_deg) : nullptr;
  // The scene's convention: 0 is no scatter (one joint, or every joint at one orientation).
  out["fisher_kappa"] = !any                            ? ordered_json(nullptr)
                        : std::isfinite(o.fisher_kappa) ? ordered_json(o.fisher_kappa)
                                                        : ordered_json(0.0);
  out["alpha95"] = number_or_null(o.alpha95_deg);
  ordered_json st;
  st["joints"] = s.joints;
  st["resultant"] = o.resultant;
  st["eigenvalues"] = {o.eigenvalues[0], o.eigenvalues[1], o.eigenvalues[2]};
  ordered_json sizes = nullptr;
  if (s.finite > 0) {
    sizes = {{"finite", s.finite},
             {"fitted", s.sizes.count},
             {"centred_inside", s.sizes_centred_inside},
             {"shape", slice::to_string(s.shape)}};
    const bool ellipse = s.shape == slice::JointShape::ellipse;
    if (s.shape == slice::JointShape::rectangle || ellipse) sizes["aspect"] = s.aspect;
    if (s.shape == slice::JointShape::polygon || ellipse) sizes["sides"] = s.sides;
    ordered_json fits = ordered_json::array();
    for (const auto& f : s.sizes.fits) fits.push_back(fit_json(f));
    sizes["fits"] = fits;
    sizes["best"] = slice::to_string(s.sizes.fits[s.sizes.best].size.distribution);
    sizes["ks_critical_95"] = s.sizes.ks_critical_95;
  }
  st["sizes"] = sizes;
  st["p32"] = s.p32;
  st["p10"] = s.p10;
  st["scanline"] = {{"from", xyz(s.scanline_from)},
                    {"to", xyz(s.scanline_to)},
                    {"length", (s.scanline_to - s.scanline_from).norm()}};
  const std::string entry = slice::sets_entry(js, s);
  st["sets_entry"] = entry.empty() ? ordered_json(nullptr) : ordered_json(entry);
  out["statistics"] = st;
  return out;
}

std::string statistics_text(ordered_json& j) {
  if (!j.contains("joints") || !j["joints"].contains("by_set")) return {};
  std::ostringstream o, entries;
  for (auto& set : j["joints"]["by_set"]) {
    if (!set.contains("statistics")) continue;
    const ordered_json st = set["statistics"];
    set.erase("statistics");
    o << "  " << set["name"].get<std::string>() << ": " << st["joints"].get<std::size_t>()
      << " joints";
    if (!set["mean_dip"].is_null()) {
      char buf[160];
      std::snprintf(buf, sizeof buf, ", mean %.1f/%05.1f (dip/dip direction)",
                    set["mean_dip"].get<double>(), set["mean_dip_direction"].get<double>());
      o << buf;
      const double k = set["fisher_kappa"].get<double>();
      o << (k > 0 ? ", Fisher kappa " + g(k) : std::string(", one orientation"));
      if (!set["alpha95"].is_null() && k > 0)
        o << ", alpha95 " << g(set["alpha95"].get<double>(), 3) << " deg";
    }
    o << '\n';
    if (!st["sizes"].is_null()) {
      const auto& z = st["sizes"];
      o << "      sizes of " << z["fitted"].get<std::size_t>() << " joints"
        << (z["centred_inside"].get<bool>() ? " centred in the domain" : "") << " (as "
        << z["shape"].get<std::string>() << "s"
        << (z.contains("sides") ? " of " + std::to_string(z["sides"].get<std::int64_t>()) + " sides"
                                : "")
        << (z.contains("aspect") ? ", aspect " + g(z["aspect"].get<double>(), 4) : "")
        << "): ";
      for (std::size_t k = 0; k < z["fits"].size(); ++k)
        o << (k ? ", " : "") << fit_text(z["fits"][k]);
      o << "; best " << z["best"].get<std::string>()
        << " (KS at 5 %: " << g(z["ks_critical_95"].get<double>(), 3) << ")\n";
    }
    const auto& sl = st["scanline"];
    const auto point = [&o](const ordered_json& p) {
      o << '(' << g(p[0].get<double>()) << ", " << g(p[1].get<double>()) << ", "
        << g(p[2].get<double>()) << ')';
    };
    o << "      intensity: P32 " << g(st["p32"].get<double>()) << ", P10 "
      << g(st["p10"].get<double>()) << " on the scanline ";
    point(sl["from"]);
    o << " to ";
    point(sl["to"]);
    o << " (" << g(sl["length"].get<double>()) << " long)\n";
    if (!st["sets_entry"].is_null()) entries << '\n' << st["sets_entry"].get<std::string>();
  }
  std::string text =
      "set statistics (measured from the joints; docs/dfn-statistics.md):\n" + o.str();
  if (!entries.str().empty()) {
    // The order joints are joined in changes the blocks of finite joints as much as their sizes
    // do (a user's DFN and its matched sets: the median block by 30 % from the order alone).
    const std::string order = j["options"]["order"].get<std::string>();
    text +=
        "\n# [[sets]] entries that draw stochastic sets like these (same domain). Blocks depend\n"
        "# on the order joints are joined in: these have [options] order = \"" +
        order +
        "\"; give the\n# sets the same to compare their blocks "
        "(docs/scenes.md#joint-orders-and-stages)\n" +
        entries.str();
  }
  return text;
}

bool is_dfn_file(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".fab" || ext == ".csv";
}

slice::JointSystem dfn_file_joints(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const std::filesystem::path abs = std::filesystem::absolute(file);
  const slice::DfnFile dfn =
      ext == ".fab" ? slice::read_fab(abs) : slice::read_dfn_csv(abs, {}, abs.stem().string());
  slice::Vec3 lo = slice::Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& f : dfn.fractures) {
    std::vector<slice::Vec3> corners = f.nodes;
    if (f.disc) {
      const slice::JointFrame fr = slice::plane_frame(f.dip_deg, f.dip_direction_deg);
      for (const auto& uv : f.polygon_uv) corners.push_back(fr.to_global(f.centre, uv));
    }
    for (const auto& c : corners) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  }
  if (dfn.fractures.empty() || !((hi - lo).minCoeff() > 0))
    throw slice::Error(
        file.string(),
        "its fractures' corners span no volume (" + std::to_string(dfn.fractures.size()) +
            " fractures)",
        "give a scene with a domain and a [[dfn]] entry of the file to slice-joints, "
        "and run slice-info on its joints.h5");
  const auto num = [](double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  std::string path = abs.string(), quoted = "\"";  // a TOML basic string
  for (const char c : path) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  quoted += '"';
  std::string stem;  // the scene's name: the file's stem, as a TOML basic string
  for (const char c : abs.stem().string())
    if (c != '"' && c != '\\' && static_cast<unsigned char>(c) >= 0x20) stem += c;
  const std::string text = "[scene]\nname = \"" + stem + "\"\n[domain]\nbox = { min = [" +
                           num(lo.x()) + ", " + num(lo.y()) + ", " + num(lo.z()) + "], max = [" +
                           num(hi.x()) + ", " + num(hi.y()) + ", " + num(hi.z()) +
                           "] }\n[[dfn]]\nfile = " + quoted + "\n";
  return slice::generate_joints(slice::parse_scene(text, abs));
}

}  // namespace info

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dfn_text.hpp"
#include "slice/dfn.hpp"
#include "slice/error.hpp"
#include "slice/stochastic.hpp"
#include "toml_read.hpp"

// CSV files of discs (dfn.hpp, docs/dfn.md) for [[dfn]].
namespace slice {

namespace {

constexpr std::array<std::string_view, 6> kRequired = {"x",     "y", "z", "dip", "dip_direction",
                                                       "radius"};
constexpr std::array<std::string_view, 5> kOptional = {"set", "sides", "aspect", "rotation", "id"};
constexpr std::int64_t kMaxDiscSides = 1000;

std::string lower(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return u;
}

std::string unquoted(std::string_view s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(dfn_text::trim(s));
}

}  // namespace

DfnFile read_dfn_csv(const std::filesystem::path& file, const DfnCsvOptions& opt,
                     const std::string& default_set) {
  dfn_text::Lines lines(file, dfn_text::read_file(file, "CSV"));
  const auto skip_comments = [&] {
    while (lines.next())
      if (lines.text().front() != '#') return true;
    return false;
  };
  if (!skip_comments())
    lines.fail_at_end("the CSV file is empty",
                      "write a header row (x, y, z, dip, dip_direction, radius, ...) and a row per "
                      "disc");
  const std::string_view head = lines.text();
  const char sep = head.find(',') != std::string_view::npos   ? ','
                   : head.find(';') != std::string_view::npos ? ';'
                                                              : '\t';
  std::map<std::string, std::size_t> column;
  const auto names = lines.fields(sep);
  std::vector<std::string_view> known(kRequired.begin(), kRequired.end());
  known.insert(known.end(), kOptional.begin(), kOptional.end());
  for (std::size_t c = 0; c < names.size(); ++c) {
    const std::string name = lower(unquoted(names[c]));
    if (!column.emplace(name, c).second)
      lines.fail("the header names column " + dfn_text::excerpt(name) + " twice",
                 "name each column once");
    // Other programs' columns (aperture, ...) are left alone; a near miss of ours is a typo.
    if (std::find(known.begin(), known.end(), name) == known.end())
      if (const std::string near = scene_read::closest(name, known); !near.empty())
        lines.fail("the header's column " + dfn_text::excerpt(name) + " is not one rockslice reads",
                   "did you mean \"" + near + "\"?");
  }
  for (const auto& k : kRequired)
    if (!column.count(std::string(k)))
      lines.fail("the header has no column \"" + std::string(k) + "\"",
                 "a disc needs the columns x, y, z, dip, dip_direction and radius (docs/dfn.md)");
  const auto col = [&](std::string_view k) -> std::optional<std::size_t> {
    const auto it = column.find(std::string(k));
    return it == column.end() ? std::nullopt : std::optional(it->second);
  };
  DfnFile out;
  std::map<std::string, std::size_t> set_index;
  if (!col("set")) {
    if (const std::string why = dfn_text::name_problem(default_set); !why.empty())
      lines.fail("the file has no column \"set\", so its discs' set takes the file's name, " +
                     dfn_text::excerpt(default_set) + ", which " + why,
                 "add a column \"set\" naming each disc's set, or rename the file in UTF-8");
    out.sets.push_back(default_set);
  }
  JointSetSpec shape;
  shape.size.distribution = SizeDistribution::fixed;
  shape.shape = JointShape::ellipse;
  shape.fit = opt.fit;
  std::int64_t row = 0;
  while (skip_comments()) {
    ++row;
    const auto v = lines.fields(sep);
    if (v.size() != names.size())
      lines.fail("the row has " + std::to_string(v.size()) + " values; the header has " +
                     std::to_string(names.size()) + " columns",
                 "give one value per column");
    DfnFracture f;
    f.line = lines.number();
    f.disc = true;
    f.id = col("id") ? unquoted(v[*col("id")]) : "row " + std::to_string(row);
    // Messages name the disc by its id: a long one or one that is no UTF-8 text, by an excerpt.
    if (f.id.size() > 40 || !dfn_text::name_problem(f.id).empty()) f.id = dfn_text::excerpt(f.id);
    const auto num = [&](std::string_view k) {
      return lines.number_at(v[*col(k)], std::string(k) + " of disc " + f.id);
    };
    f.centre = {num("x"), num("y"), num("z")};
    f.dip_deg = num("dip");
    f.dip_direction_deg = num("dip_direction");
    if (!(f.dip_deg >= 0 && f.dip_deg <= 90))
      lines.fail(
          "dip of disc " + f.id + " is " + dfn_text::excerpt(v[*col("dip")]) + ", outside [0, 90]",
          "give the dip in degrees from the horizontal, 0 to 90");
    if (!(f.dip_direction_deg >= 0 && f.dip_direction_deg < 360))
      lines.fail("dip_direction of disc " + f.id + " is " +
                     dfn_text::excerpt(v[*col("dip_direction")]) + ", outside [0, 360)",
                 "give the dip direction clockwise from North in [0, 360)");
    const double radius = num("radius");
    if (!(radius > 0))
      lines.fail(
          "radius of disc " + f.id + " is " + dfn_text::excerpt(v[*col("radius")]) + ", not > 0",
          "give the disc's radius (the long semi-axis of an ellipse), > 0");
    shape.sides = opt.sides;
    if (col("sides")) {
      const auto n = dfn_text::whole(v[*col("sides")]);
      if (!n || *n < 3 || *n > kMaxDiscSides)
        lines.fail("sides of disc " + f.id + " is " + dfn_text::excerpt(v[*col("sides")]) +
                       ", not a whole number from 3 to " + std::to_string(kMaxDiscSides),
                   "give the polygon's number of corners");
      shape.sides = *n;
    }
    shape.aspect = col("aspect") ? num("aspect") : 1.0;
    if (!(shape.aspect >= 1))
      lines.fail(
          "aspect of disc " + f.id + " is " + dfn_text::excerpt(v[*col("aspect")]) + ", below 1",
          "give long / short diameter, >= 1 (radius is the long semi-axis)");
    const double rotation = col("rotation") ? num("rotation") : 0.0;
    f.polygon_uv = joint_polygon(shape, 2 * radius, rotation);
    if (col("set")) {
      const std::string name = unquoted(v[*col("set")]);
      if (name.empty())
        lines.fail("disc " + f.id + " has an empty set", "name its set, or leave the column out");
      lines.check_name(name, "the set name of disc " + f.id + ",");
      const auto [it, added] = set_index.emplace(name, out.sets.size());
      if (added) out.sets.push_back(name);
      f.set = it->second;
    }
    out.fractures.push_back(std::move(f));
  }
  if (out.fractures.empty())
    lines.fail_at_end("the CSV file has a header but no disc", "add a row per disc");
  return out;
}

}  // namespace slice

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dfn_text.hpp"
#include "slice/dfn.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/output.hpp"
#include "slice/polytope.hpp"
#include "slice/utf8.hpp"
#include "slice/vertices.hpp"

// FracMan FAB files (dfn.hpp): read for [[dfn]], written from a joint system.
namespace slice {

namespace {

using dfn_text::Lines;

constexpr char kFabFix[] =
    "export the DFN from FracMan as an ASCII FAB file (docs/dfn.md describes what is read)";

// The upper-case copy of s, for keywords (FracMan writes them upper case; we do not insist).
std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

// "key = value" of FORMAT, PROPERTIES and SETS: both trimmed, the value without its quotes.
std::optional<std::pair<std::string, std::string>> key_value(std::string_view line) {
  const auto eq = line.find('=');
  if (eq == std::string_view::npos) return std::nullopt;
  std::string key(dfn_text::trim(line.substr(0, eq)));
  std::string value(dfn_text::trim(line.substr(eq + 1)));
  if (key.empty()) return std::nullopt;
  return std::pair{std::move(key), std::move(value)};
}

// The name of a set or property: the text between the last pair of quotes, else all of it.
std::string unquote(const std::string& v) {
  const auto close = v.rfind('"');
  if (close != std::string::npos && close > 0) {
    const auto open = v.rfind('"', close - 1);
    if (open != std::string::npos) return v.substr(open + 1, close - open - 1);
  }
  return v;
}

struct Format {
  std::optional<std::int64_t> fractures, tess, nodes, properties;
  std::int64_t line = 0;
};

// The keys "Set12" and "Prop3": the number after the prefix, or nothing.
std::optional<std::int64_t> numbered(const std::string& key, std::string_view prefix) {
  if (key.size() <= prefix.size() || upper(key.substr(0, prefix.size())) != upper(prefix))
    return std::nullopt;
  return dfn_text::whole(key.substr(prefix.size()));
}

class FabReader {
 public:
  FabReader(const std::filesystem::path& file, std::string text)
      : lines_(file, std::move(text)), stem_(file.stem().string()) {}

  DfnFile read() {
    while (lines_.next()) {
      const std::string head = upper(lines_.text());
      if (head.rfind("BEGIN", 0) != 0)
        lines_.fail("expected a section, BEGIN FORMAT, BEGIN FRACTURE, ..., not " +
                        dfn_text::excerpt(lines_.text()),
                    kFabFix);
      const std::string name(dfn_text::trim(std::string_view(head).substr(5)));
      lines_.check_name(name, "the section name");
      if (!seen_.insert({name, lines_.number()}).second)
        lines_.fail("a second " + name + " section (the first begins on line " +
                        std::to_string(seen_[name]) + ")",
                    "keep one");
      if (name == "FORMAT")
        read_format();
      else if (name == "PROPERTIES")
        read_properties();
      else if (name == "SETS")
        read_sets();
      else if (name == "FRACTURE")
        read_fractures();
      else if (name == "TESSFRACTURE")
        read_tess_fractures();
      else if (name == "ROCKBLOCK")
        read_empty(name);
      else
        lines_.fail("unknown section BEGIN " + dfn_text::excerpt(name),
                    "a FAB file has the sections FORMAT, PROPERTIES, SETS, FRACTURE, "
                    "TESSFRACTURE and ROCKBLOCK");
    }
    finish();
    return std::move(out_);
  }

 private:
  // The lines of a section up to its END; `body` gets each. A file that ends first fails.
  template <class Body>
  void section(const std::string& name, Body body) {
    const std::int64_t begin = lines_.number();
    while (lines_.next()) {
      const std::string u = upper(lines_.text());
      if (u.rfind("END", 0) == 0 && dfn_text::trim(std::string_view(u).substr(3)) == name) return;
      if (u.rfind("BEGIN", 0) == 0)
        lines_.fail("BEGIN inside the " + name + " section begun on line " + std::to_string(begin) +
                        ", which has no END " + name,
                    "add the line END " + name + " before it");
      body();
    }
    lines_.fail_at_end("the file ends inside the " + name + " section begun on line " +
                           std::to_string(begin) + ": END " + name + " is missing",
                       "add the line END " + name + " (or check that the file is complete)");
  }

  std::pair<std::string, std::string> entry(const std::string& section_name) {
    auto kv = key_value(lines_.text());
    if (!kv)
      lines_.fail(dfn_text::excerpt(lines_.text()) + " in " + section_name +
                      " is not of the form key = value",
                  kFabFix);
    return std::move(*kv);
  }

  std::int64_t count(const std::string& key, const std::string& value) {
    const auto v = dfn_text::whole(value);
    if (!v || *v < 0)
      lines_.fail(key + " = " + dfn_text::excerpt(value) + " is not a count (a whole number >= 0)",
                  kFabFix);
    return *v;
  }

  void read_format() {
    format_.line = lines_.number();
    section("FORMAT", [&] {
      const auto [key, value] = entry("FORMAT");
      const std::string k = upper(key);
      if (k == "FORMAT" && upper(unquote(value)) != "ASCII")
        lines_.fail("Format = " + dfn_text::excerpt(value) + ": only ASCII FAB files are read",
                    "export the DFN from FracMan with Format = Ascii");
      if (k == "XAXIS" && upper(unquote(value)) != "EAST")
        lines_.fail("XAxis = " + dfn_text::excerpt(value) +
                        ": rockslice's x axis is East (docs/scenes.md, Frame)",
                    "export the DFN with XAxis = East");
      if (k == "NO_FRACTURES") format_.fractures = count(key, value);
      if (k == "NO_NODES") format_.nodes = count(key, value);
      if (k == "NO_PROPERTIES") format_.properties = count(key, value);
      if (k == "NO_TESSFRACTURES") format_.tess = count(key, value);
    });
  }

  void read_properties() {
    section("PROPERTIES", [&] {
      const auto [key, value] = entry("PROPERTIES");
      if (!numbered(key, "Prop"))
        lines_.fail(dfn_text::excerpt(key) + " in PROPERTIES is not PropK",
                    "name them Prop1, Prop2, ...");
      ++declared_properties_;
      properties_line_ = lines_.number();
    });
  }

  void read_sets() {
    sets_line_ = lines_.number();
    section("SETS", [&] {
      const auto [key, value] = entry("SETS");
      const auto id = numbered(key, "Set");
      if (!id)
        lines_.fail(
            dfn_text::excerpt(key) + " in SETS is not SetK (K the set id the fractures give)",
            "name the sets Set1, Set2, ...");
      if (set_index_.count(*id))
        lines_.fail("set id " + std::to_string(*id) + " is declared twice in SETS",
                    "declare each set once");
      const std::string name = unquote(value);
      if (name.empty())
        lines_.fail(dfn_text::excerpt(key) + " has no name", "give it one: " + key + " = \"J1\"");
      lines_.check_name(name, "the name of " + key);
      set_index_[*id] = out_.sets.size();
      out_.sets.push_back(name);
    });
    declared_sets_ = !out_.sets.empty();
  }

  // The set index of set id `id` on the current line.
  std::size_t set_of(std::int64_t id, const std::string& fracture) {
    if (const auto it = set_index_.find(id); it != set_index_.end()) return it->second;
    if (declared_sets_)
      lines_.fail("fracture " + fracture + " is in set " + std::to_string(id) +
                      ", which SETS (line " + std::to_string(sets_line_) + ") does not declare",
                  "declare it there (Set" + std::to_string(id) +
                      " = \"name\") or correct the fracture's set id");
    // A file that declares no set (PorePy writes none): each set id is a set of its own, named
    // after the file.
    set_index_[id] = out_.sets.size();
    out_.sets.push_back(stem_ + " set " + std::to_string(id));
    if (const std::string why = dfn_text::name_problem(stem_); !why.empty())
      lines_.fail("fracture " + fracture + " is in set " + std::to_string(id) +
                      ", which SETS does not name, so the set takes the file's name, which " + why,
                  "name the sets in a SETS section (Set" + std::to_string(id) +
                      " = \"name\"), or rename the file in UTF-8");
    return out_.sets.size() - 1;
  }

  std::int64_t properties() const {
    return format_.properties ? *format_.properties : declared_properties_;
  }

  void read_fractures() {
    if (format_.line == 0)
      lines_.fail("the FRACTURE section comes before any FORMAT section",
                  "a FAB file begins with BEGIN FORMAT ... END FORMAT");
    section("FRACTURE", [&] { read_fracture(); });
  }

  // The id on the current fracture line, checked to be a whole number.
  std::string fracture_id(std::string_view field) {
    std::string id(field);
    if (!dfn_text::whole(field))
      lines_.fail("fracture id " + dfn_text::excerpt(id) + " is not a whole number", kFabFix);
    return id;
  }

  // A node or face count on a fracture's first line: >= `least`, and no more lines (of at least
  // `bytes` bytes each) than the rest of the file holds, refused before anything is allocated.
  std::int64_t line_count(std::string_view field, const std::string& id, const char* what,
                          std::int64_t least, std::uint64_t bytes) {
    const auto n = dfn_text::whole(field);
    if (!n || *n < least)
      lines_.fail("fracture " + id + " has " + what + " count " + dfn_text::excerpt(field) +
                      "; it needs a whole number >= " + std::to_string(least),
                  kFabFix);
    if (std::uint64_t(*n) > lines_.bytes_left() / bytes)
      lines_.fail(
          "fracture " + id + " claims " + std::to_string(*n) + " " + what + "s, but the " +
              std::to_string(lines_.bytes_left()) + " bytes left in the file hold at most " +
              std::to_string(lines_.bytes_left() / bytes) + " " + what + " lines",
          "correct the " + std::string(what) + " count (or check that the file is complete)");
    return *n;
  }

  std::size_t fracture_set(std::string_view field, const std::string& id) {
    const auto set = dfn_text::whole(field);
    if (!set)
      lines_.fail(
          "fracture " + id + ": set id " + dfn_text::excerpt(field) + " is not a whole number",
          kFabFix);
    return set_of(*set, id);
  }

  // Line k (from 0) of a fracture's n `item` lines ("node", "face"): its fields, and in `what`
  // its name for messages ("node 3 of fracture 7"). Fails where the file ends before it.
  std::vector<std::string_view> item_line(const char* item, std::int64_t k, std::int64_t n,
                                          const std::string& id, std::string& what) {
    what = std::string(item) + " " + std::to_string(k + 1) + " of fracture " + id;
    if (!lines_.next())
      lines_.fail_at_end("the file ends at " + what + " (of " + std::to_string(n) + ")",
                         "check that the file is complete");
    return lines_.fields();
  }

  // The `n` node lines "k x y z" after a fracture's first line.
  void read_nodes(DfnFracture& f, std::int64_t n) {
    std::string what;
    for (std::int64_t k = 0; k < n; ++k) {
      const auto v = item_line("node", k, n, f.id, what);
      if (v.size() != 4)
        lines_.fail(what + " has " + std::to_string(v.size()) + " values; expected 4 (k x y z)" +
                        (v.size() == 3 || (f.tessellated && v.size() >= 5)
                             ? ": the fracture has fewer nodes than its count, " +
                                   std::to_string(n) + ", says"
                             : ""),
                    "correct the node line or the fracture's node count");
      lines_.number_at(v[0], "the index of " + what);
      f.nodes.emplace_back(lines_.number_at(v[1], "x of " + what),
                           lines_.number_at(v[2], "y of " + what),
                           lines_.number_at(v[3], "z of " + what));
    }
  }

  void read_fracture() {
    const auto head = lines_.fields();
    const std::int64_t p = properties();
    if (std::int64_t(head.size()) != 3 + p)
      lines_.fail("a fracture's first line has " + std::to_string(head.size()) +
                      " values; expected " + std::to_string(3 + p) +
                      " (id, node count, set id and the No_Properties = " + std::to_string(p) +
                      " property values)",
                  "correct the line or No_Properties in FORMAT");
    DfnFracture f;
    f.line = lines_.number();
    f.id = fracture_id(head[0]);
    // Each node takes a line of at least 8 bytes ("1 0 0 0\n").
    const std::int64_t n = line_count(head[1], f.id, "node", 3, 8);
    const std::size_t set = fracture_set(head[2], f.id);
    for (std::size_t k = 3; k < head.size(); ++k)
      lines_.number_at(head[k], "property " + std::to_string(k - 2) + " of fracture " + f.id);
    f.set = set;
    read_nodes(f, n);
    nodes_ += std::uint64_t(n);
    const std::string what = "the normal line of fracture " + f.id;
    if (!lines_.next())
      lines_.fail_at_end("the file ends before " + what, "check that the file is complete");
    const auto v = lines_.fields();
    if (v.size() != 4 || lines_.number_at(v[0], what) != 0)
      lines_.fail(what + " is " + dfn_text::excerpt(lines_.text()) +
                      "; expected \"0 nx ny nz\" after the fracture's " + std::to_string(n) +
                      " nodes",
                  "correct the fracture's node count, or add the normal line");
    for (std::size_t k = 1; k < 4; ++k) lines_.number_at(v[k], what);
    out_.fractures.push_back(std::move(f));
  }

  // A tessellated fracture: "id nodes faces set", its node lines, then a line per triangle whose
  // first five values are whole numbers (the face's number and its three node indices, in one of
  // the two layouts docs/dfn.md names) and the rest numbers (the face's property values).
  void read_tess_fracture() {
    const auto head = lines_.fields();
    if (head.size() != 4)
      lines_.fail("a tessellated fracture's first line has " + std::to_string(head.size()) +
                      " values; expected 4 (id, node count, face count, set id)",
                  "correct the line");
    DfnFracture f;
    f.tessellated = true;
    f.line = lines_.number();
    f.id = fracture_id(head[0]);
    const std::int64_t n = line_count(head[1], f.id, "node", 3, 8);
    const std::int64_t faces = line_count(head[2], f.id, "face", 1, 10);  // "1 1 2 3 0\n"
    f.set = fracture_set(head[3], f.id);
    read_nodes(f, n);
    std::string what;
    for (std::int64_t k = 0; k < faces; ++k) {
      const auto v = item_line("face", k, faces, f.id, what);
      if (v.size() < 5)
        lines_.fail(what + " has " + std::to_string(v.size()) +
                        " values; expected at least 5 (the face's number and its node indices, "
                        "then its property values)",
                    "correct the face line or the fracture's face count");
      std::array<std::int64_t, 5> face{};
      for (std::size_t c = 0; c < v.size(); ++c) {
        lines_.number_at(v[c], "value " + std::to_string(c + 1) + " of " + what);
        if (c >= 5) continue;
        const auto w = dfn_text::whole(v[c]);
        if (!w)
          lines_.fail("value " + std::to_string(c + 1) + " of " + what + ", " +
                          dfn_text::excerpt(v[c]) +
                          ", is not a whole number (a face's first five values are its number "
                          "and node indices)",
                      "correct the face line or the fracture's face count");
        face[c] = *w;
      }
      f.faces.push_back(face);
    }
    tess_nodes_ += std::uint64_t(n);
    ++tess_;
    out_.fractures.push_back(std::move(f));
  }

  void read_tess_fractures() {
    if (format_.line == 0)
      lines_.fail("the TESSFRACTURE section comes before any FORMAT section",
                  "a FAB file begins with BEGIN FORMAT ... END FORMAT");
    section("TESSFRACTURE", [&] { read_tess_fracture(); });
  }

  void read_empty(const std::string& name) {
    section(name, [&] {
      lines_.fail("rock blocks (ROCKBLOCK) are not read: rockslice makes the blocks",
                  "export the DFN's fractures (FRACTURE, TESSFRACTURE) only");
    });
  }

  void finish() {
    if (seen_.count("FRACTURE") == 0)
      lines_.fail_at_end("the file has no FRACTURE section", kFabFix);
    const auto disagree = [&](const char* key, std::int64_t said, std::uint64_t found,
                              const std::string& what) {
      lines_.fail_on(format_.line,
                     std::string("FORMAT says ") + key + " = " + std::to_string(said) +
                         ", but the file has " + std::to_string(found) + " " + what,
                     "correct " + std::string(key) + " (or check that the file is complete)");
    };
    const std::uint64_t polygons = out_.fractures.size() - tess_;
    if (format_.fractures && std::uint64_t(*format_.fractures) != polygons)
      disagree("No_Fractures", *format_.fractures, polygons, "fractures in FRACTURE");
    if (format_.tess && std::uint64_t(*format_.tess) != tess_)
      disagree("No_TessFractures", *format_.tess, tess_, "tessellated fractures");
    // No_Nodes counts FRACTURE's nodes; whether it counts TESSFRACTURE's too, no public source
    // says: either count is accepted.
    if (format_.nodes && std::uint64_t(*format_.nodes) != nodes_ &&
        std::uint64_t(*format_.nodes) != nodes_ + tess_nodes_)
      disagree("No_Nodes", *format_.nodes, nodes_,
               "fracture nodes" + (tess_ > 0 ? " (" + std::to_string(nodes_ + tess_nodes_) +
                                                   " with the tessellated fractures' nodes)"
                                             : std::string()));
    if (format_.properties && declared_properties_ > 0 &&
        *format_.properties != declared_properties_)
      disagree("No_Properties", *format_.properties, std::uint64_t(declared_properties_),
               "properties in PROPERTIES (line " + std::to_string(properties_line_) + ")");
  }

  Lines lines_;
  std::string stem_;
  DfnFile out_;
  Format format_;
  std::map<std::string, std::int64_t> seen_;  // sections by their BEGIN line
  std::map<std::int64_t, std::size_t> set_index_;
  bool declared_sets_ = false;
  std::int64_t sets_line_ = 0;
  std::int64_t declared_properties_ = 0;
  std::int64_t properties_line_ = 0;
  std::uint64_t nodes_ = 0;  // FRACTURE's
  std::uint64_t tess_nodes_ = 0;
  std::uint64_t tess_ = 0;
};

// 17 significant digits: enough for any double to read back as itself.
std::string exact(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x == 0 ? 0.0 : x);  // no "-0"
  return buf;
}

// How a set's name is written after "SetK = " so that the reader above gives it back as it is
// (key_value, unquote): between double quotes; bare if it holds one double quote (the reader
// takes the text between the last two quotes, else the whole value). "" and `why` if it cannot
// be written: two double quotes, a control character or a line end (the reader's lines end at
// LF and CR), bytes that are no UTF-8 (which the reader refuses).
std::string fab_set_value(const std::string& name, std::string& why) {
  if (name.empty()) {
    why = "is empty (the reader refuses a set without a name)";
    return "";
  }
  for (std::size_t i = 0; i < name.size();) {
    const auto [c, len] = decode_utf8(name, i);
    if (len == 0) {
      why = "is not UTF-8 text";
      return "";
    }
    if (c < 0x20 || c == 0x7f) {
      why = "holds a control character";
      return "";
    }
    i += len;
  }
  for (const std::string& value : {'"' + name + '"', name})
    if (const auto kv = key_value("Set1 = " + value); kv && unquote(kv->second) == name)
      return value;
  why = std::count(name.begin(), name.end(), '"') > 1
            ? "holds two double quotes (FAB writes a name between two, and has no escape)"
            : "begins or ends with a space and holds a double quote";
  return "";
}

}  // namespace

DfnFile read_fab(const std::filesystem::path& file) {
  return FabReader(file, dfn_text::read_file(file, "FAB")).read();
}

FabStats write_fab(const std::filesystem::path& out, const JointSystem& js) {
  if (js.dimension != 3)  // slice-export names its input first: the input is 2-D, not `out`
    throw Error(out.string(),
                "not written: the joints are a 2-D section's (lines), and FAB holds 3-D polygons",
                "export the 3-D scene's joints");
  FabStats st;
  const PolytopeInfo dom =
      analyse_polytope(js.domain.planes, js.options.tolerance * js.length_scale);
  std::vector<std::vector<Vec3>> polys;
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < js.joints.size(); ++i) {
    const Joint& j = js.joints[i];
    std::vector<Vec3> poly = joint_polygon(j);
    if (poly.empty()) {  // persistent: a square of its plane larger than the domain, clipped
      const JointFrame fr = plane_frame(j.dip_deg, j.dip_direction_deg);
      const Vec3 mid = (dom.min + dom.max) / 2;
      const double half = (dom.max - dom.min).norm();
      const Vec3 c = mid - j.plane.distance(mid) * j.plane.normal;
      poly = {c + half * (-fr.u - fr.v), c + half * (fr.u - fr.v), c + half * (fr.u + fr.v),
              c + half * (-fr.u + fr.v)};
      for (const Plane& p : js.domain.planes)
        if (poly.size() >= 3) poly = clip_polygon(poly, p);
      if (poly.size() < 3) {
        ++st.left_out;
        continue;
      }
      ++st.persistent;
    }
    polys.push_back(std::move(poly));
    rows.push_back(i);
  }
  // Set ids 1.. for js.sets, then one for the joints of no set, under a name no set has.
  std::vector<std::string> names;
  for (const JointSetSpec& s : js.sets) names.push_back(s.name);
  std::string loose = "[[joints]]";
  while (std::find(names.begin(), names.end(), loose) != names.end()) loose += "'";
  bool any_loose = false;
  for (const std::size_t r : rows) any_loose = any_loose || js.joints[r].set < 0;
  if (any_loose) names.push_back(loose);
  for (const auto& p : polys) st.nodes += p.size();
  std::string s = "BEGIN FORMAT\n    Format = Ascii\n    XAxis = East\n    Scale = 100.0\n";
  s += "    No_Fractures = " + std::to_string(polys.size()) + "\n";
  s += "    No_TessFractures = 0\n    No_Nodes = " + std::to_string(st.nodes) + "\n";
  s += "    No_Properties = 0\nEND FORMAT\n\nBEGIN PROPERTIES\nEND PROPERTIES\n\nBEGIN SETS\n";
  for (std::size_t k = 0; k < names.size(); ++k) {
    // Written as it reads back (slice-joints keeps it), or refused: never another name.
    std::string why;
    const std::string value = fab_set_value(names[k], why);
    if (value.empty())
      throw Error(out.string(),
                  "not written: the name of set " + std::to_string(k + 1) + ", \"" + names[k] +
                      "\", " + why + ", so the FAB file could not give it back",
                  "rename the set (name of its [[sets]] entry) and run slice-joints again");
    s += "    Set" + std::to_string(k + 1) + " = " + value + "\n";
  }
  s += "END SETS\n\nBEGIN FRACTURE\n";
  for (std::size_t f = 0; f < polys.size(); ++f) {
    const Joint& j = js.joints[rows[f]];
    const std::size_t set = j.set >= 0 ? std::size_t(j.set) + 1 : js.sets.size() + 1;
    s += std::to_string(f + 1) + " " + std::to_string(polys[f].size()) + " " + std::to_string(set) +
         "\n";
    for (std::size_t k = 0; k < polys[f].size(); ++k) {
      const Vec3& x = polys[f][k];
      s += std::to_string(k + 1) + " " + exact(x.x()) + " " + exact(x.y()) + " " + exact(x.z()) +
           "\n";
    }
    const Vec3& n = j.plane.normal;
    s += "0 " + exact(n.x()) + " " + exact(n.y()) + " " + exact(n.z()) + "\n";
  }
  s += "END FRACTURE\n\nBEGIN TESSFRACTURE\nEND TESSFRACTURE\n";
  write_text_file(out, s);
  st.fractures = polys.size();
  st.sets = names.size();
  return st;
}

}  // namespace slice

// docs/scenes.md, the scene reference, against the parser: every key the parser accepts
// (slice::scene_keys(), the lists it checks scene files against) is named in backquotes in the
// section of its table, and every name a choice key takes appears in the document.
#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "slice/scene.hpp"

namespace {

std::string read_doc() {
  const std::string path = std::string(SLICE_DOCS_DIR) + "/scenes.md";
  std::ifstream in(path, std::ios::binary);
  INFO("reading " << path);
  REQUIRE(in);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Line {
  std::string text;
  bool in_code = false;  // inside a ``` fence
};

std::vector<Line> lines_of(const std::string& doc) {
  std::vector<Line> out;
  std::istringstream in(doc);
  bool code = false;
  for (std::string s; std::getline(in, s);) {
    const bool fence = s.rfind("```", 0) == 0;
    out.push_back({s, code || fence});
    if (fence) code = !code;
  }
  return out;
}

// The heading level of a line outside code (2 for "## ..."), 0 for other lines.
int level(const Line& l) {
  if (l.in_code) return 0;
  std::size_t n = 0;
  while (n < l.text.size() && l.text[n] == '#') ++n;
  return n > 0 && n < l.text.size() && l.text[n] == ' ' ? int(n) : 0;
}

bool has(std::string_view text, std::string_view what) {
  return text.find(what) != std::string_view::npos;
}

// open + s + close. (Built with +=: GCC 12 gives a false -Wrestrict for "literal" + std::string
// once inlined, GCC bug 105651.)
std::string wrap(std::string_view open, std::string_view s, std::string_view close) {
  std::string out(open);
  out += s;
  out += close;
  return out;
}

std::string ticked(std::string_view s) { return wrap("`", s, "`"); }

// The text under the headings of `depth` within [from, to) whose title satisfies `match`, each
// up to the next heading of that depth or higher; "" if there is none.
template <typename Match>
std::string section(const std::vector<Line>& lines, std::size_t from, std::size_t to, int depth,
                    Match match, std::size_t* count = nullptr) {
  std::string out;
  std::size_t found = 0;
  for (std::size_t i = from; i < to; ++i) {
    if (level(lines[i]) != depth || !match(lines[i].text)) continue;
    ++found;
    std::size_t j = i + 1;
    while (j < to && !(level(lines[j]) > 0 && level(lines[j]) <= depth)) ++j;
    for (std::size_t k = i; k < j; ++k) out += lines[k].text + "\n";
  }
  if (count) *count = found;
  return out;
}

// The lines of the level-2 section of table `name` ("## `[scene]`", "## `[[joints]]`").
std::pair<std::size_t, std::size_t> table_section(const std::vector<Line>& lines,
                                                  std::string_view name) {
  const std::string single = ticked(wrap("[", name, "]"));
  const std::string array = ticked(wrap("[[", name, "]]"));
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (level(lines[i]) != 2 || !(has(lines[i].text, single) || has(lines[i].text, array)))
      continue;
    std::size_t j = i + 1;
    while (j < lines.size() && !(level(lines[j]) > 0 && level(lines[j]) <= 2)) ++j;
    return {i, j};
  }
  return {0, 0};
}

}  // namespace

TEST_CASE("docs/scenes.md names every key the scene parser accepts, under its table",
          "[docs][scene]") {
  const std::vector<Line> lines = lines_of(read_doc());
  const std::vector<slice::SceneKeys> all = slice::scene_keys();
  REQUIRE(all.size() > 1);
  std::size_t checked = 0;
  for (const slice::SceneKeys& t : all) {
    if (t.table.empty()) {
      // The top level's keys are the tables: each has its own "## `[name]`" section.
      for (const auto& name : t.keys) {
        INFO("table " << name << ": docs/scenes.md needs a heading \"## `[" << name
                      << "]`\" (or `[[" << name << "]]`)");
        const auto [begin, end] = table_section(lines, name);
        CHECK(end > begin);
        ++checked;
      }
      continue;
    }
    const auto [begin, end] = table_section(lines, t.table);
    INFO("table [" << t.table << "]");
    REQUIRE(end > begin);
    std::string text;
    if (t.within.empty()) {
      for (std::size_t i = begin; i < end; ++i) text += lines[i].text + "\n";
    } else {
      // An inline table: a "### " heading naming it, in the table's section.
      std::size_t count = 0;
      text = section(
          lines, begin + 1, end, 3,
          [&](const std::string& title) { return has(title, ticked(t.within)); }, &count);
      INFO("inline table " << t.within << ": the section of [" << t.table
                           << "] needs a heading \"### `" << t.within << "`\"");
      REQUIRE(count > 0);
    }
    for (const auto& key : t.keys) {
      INFO("key " << ticked(key) << " of [" << t.table << "]"
                  << (t.within.empty() ? "" : wrap(" ", t.within, ""))
                  << " is missing from docs/scenes.md there");
      CHECK(has(text, ticked(key)));
      ++checked;
    }
  }
  CHECK(checked > 50);
}

TEST_CASE("docs/scenes.md names every value the scene parser's choice keys take", "[docs][scene]") {
  const std::string doc = read_doc();
  const auto check_all = [&](const auto& names, std::string_view key) {
    for (const std::string_view name : names) {
      if (name == "none") continue;  // a persistent set has no size: not a value in scenes
      INFO(key << " = \"" << name << "\" is missing from docs/scenes.md");
      CHECK((has(doc, ticked(name)) || has(doc, ticked(wrap("\"", name, "\"")))));
    }
  };
  check_all(slice::kJointOrderNames, "order");
  check_all(slice::kJointKindNames, "kind");
  check_all(slice::kSetIntensityNames, "intensity");
  check_all(slice::kSizeDistributionNames, "distribution");
  check_all(slice::kJointShapeNames, "shape");
  check_all(slice::kEllipseFitNames, "fit");
  check_all(slice::kBoxFaceNames, "fixed_faces");
}

// slice-export --format fab and the names of the sets (issue 42 item 15): a name is written so
// that slice-joints reads it back as it was (a' b and a"b were both written as a'b), or refused
// with one line; a 2-D section's joints are refused naming the input, not the output.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "slice/dfn.hpp"
#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using test::check_refused;
using test::run_tool;

namespace {

constexpr char kHead[] = R"([scene]
name = "fab-names"
[domain]
box = { min = [0, 0, 0], max = [10, 10, 10] }
)";

// A scene with one persistent set per name, `name` given as a TOML string literal.
std::string scene_of(const std::vector<std::string>& toml_names) {
  std::string s = kHead;
  for (std::size_t i = 0; i < toml_names.size(); ++i)
    s += "[[sets]]\nname = " + toml_names[i] + "\ndip = " + std::to_string(20 + 10 * i) +
         "\ndip_direction = " + std::to_string(40 * i) + "\nspacing = 4\n";
  return s;
}

}  // namespace

TEST_CASE("slice-export --format fab: set names read back by slice-joints as they were",
          "[tools][dfn][fab]") {
  test::TempDir tmp;
  // As TOML literals, and as the names they are.
  const std::vector<std::string> toml = {R"("a'b")",    R"('a"b')",       R"(" padded ")",
                                         R"('k = "v')", R"("ünï ✓")",     R"('"lead')",
                                         R"('trail"')", R"("[[joints]]")"};
  const std::vector<std::string> names = {"a'b",   "a\"b",   " padded ", "k = \"v",
                                          "ünï ✓", "\"lead", "trail\"",  "[[joints]]"};
  test::write_text(tmp / "s.toml", scene_of(toml));
  const auto j = (tmp / "j.h5").string(), fab = (tmp / "out.fab").string();
  const auto r1 = run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", j});
  INFO(r1.err);
  REQUIRE(r1.exit_code == 0);
  REQUIRE(slice::read_joints(j).sets.size() == names.size());
  const auto r = run_tool("slice-export", {j, "--format", "fab", "-o", fab, "-q"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  // The library's reader, and slice-joints on the file as a [[dfn]] entry.
  const slice::DfnFile file = slice::read_fab(fab);
  REQUIRE(file.sets.size() == names.size());
  for (std::size_t s = 0; s < names.size(); ++s) CHECK(file.sets[s] == names[s]);
  test::write_text(tmp / "back.toml", std::string(kHead) + "[[dfn]]\nfile = \"out.fab\"\n");
  const auto j2 = (tmp / "j2.h5").string();
  const auto r2 = run_tool("slice-joints", {(tmp / "back.toml").string(), "-o", j2});
  INFO(r2.err);
  REQUIRE(r2.exit_code == 0);
  const slice::JointSystem back = slice::read_joints(j2);
  REQUIRE(back.sets.size() == names.size());
  for (std::size_t s = 0; s < names.size(); ++s) CHECK(back.sets[s].name == names[s]);
}

TEST_CASE("slice-export --format fab refuses a set name a FAB file cannot give back",
          "[tools][dfn][fab]") {
  test::TempDir tmp;
  const auto fab = (tmp / "out.fab").string();
  // Two double quotes (the reader takes the text between the last two); one with a space at an
  // end (a bare value is trimmed).
  for (const std::string& name :
       {std::string(R"('a"b"c')"), std::string(R"('"quoted"')"), std::string(R"(' a"b')")}) {
    INFO(name);
    test::write_text(tmp / "s.toml", scene_of({R"("fine")", name}));
    const auto j = (tmp / "j.h5").string();
    REQUIRE(run_tool("slice-joints", {(tmp / "s.toml").string(), "-o", j}).exit_code == 0);
    const auto r = run_tool("slice-export", {j, "--format", "fab", "-o", fab});
    check_refused(r, "slice-export", {fab, "set 2", "rename the set"});
    CHECK_FALSE(test::fs::exists(fab));
    CHECK_FALSE(test::fs::exists(fab + ".partial"));
  }
}

TEST_CASE("slice-export --format fab of a 2-D section names the input, not the output",
          "[tools][dfn][fab]") {
  test::TempDir tmp;
  const auto j = (tmp / "section.h5").string(), fab = (tmp / "out.fab").string();
  REQUIRE(run_tool("slice-joints", {test::data_path("tunnel-section.toml").string(), "-o", j})
              .exit_code == 0);
  const auto r = run_tool("slice-export", {j, "--format", "fab", "-o", fab});
  check_refused(r, "slice-export", {"slice-export: error: " + j + ": ", "2-D"});
  CHECK_THAT(r.err, !Catch::Contains("out.fab"));
  CHECK_FALSE(test::fs::exists(fab));
}

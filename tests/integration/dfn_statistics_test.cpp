// slice-info's statistics of a DFN's sets (docs/dfn-statistics.md), through the real tools: a FAB
// of three stochastic sets of known orientation, scatter and sizes (two steep ones, as on a
// jointed hillside, one nearly vertical), read as a [[dfn]] and on its own; and the round trip
// FAB -> slice-info -> [[sets]] -> slice-joints -> slice-info.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <utility>

#include "slice/dfn.hpp"
#include "slice/h5io.hpp"
#include "slice/orientation.hpp"
#include "support/support.hpp"

using Catch::Matchers::Contains;
using Catch::Matchers::WithinRel;
using nlohmann::json;
using slice::Vec3;
using test::run_tool;

namespace {

const char* kDomain = R"([domain]
box = { min = [0, 0, 0], max = [60, 60, 60] }
)";

// The sets the FAB is drawn from: the hillside's J1 77.1/020 and J2 69.3/140, and J3 nearly
// vertical (its poles straddle the horizontal), each with its own size distribution.
struct Truth {
  const char* name;
  double dip, ddir, kappa;
  const char* size;  // the distribution the sizes come from
};
const Truth kTruth[] = {{"J1", 77.1, 20, 25, "lognormal"},
                        {"J2", 69.3, 140, 15, "exponential"},
                        {"J3", 88, 290, 40, "power-law"}};

const char* kSets = R"([[sets]]
name = "J1"
dip = 77.1
dip_direction = 20
fisher_kappa = 25
count = 400
size = { distribution = "lognormal", mean = 10, sd = 4 }
[[sets]]
name = "J2"
dip = 69.3
dip_direction = 140
fisher_kappa = 15
count = 300
size = { distribution = "exponential", mean = 6 }
shape = "polygon"
sides = 6
[[sets]]
name = "J3"
dip = 88
dip_direction = 290
fisher_kappa = 40
count = 300
size = { distribution = "power-law", exponent = 2.5, min = 3, max = 60 }
)";

double axis_angle_deg(double dip1, double ddir1, double dip2, double ddir2) {
  const double c =
      std::abs(slice::normal_from_dip(dip1, ddir1).dot(slice::normal_from_dip(dip2, ddir2)));
  return std::acos(std::min(1.0, c)) * 180 / std::numbers::pi;
}

// As in tests/unit/orientation_stats_test.cpp: the angle the mean of n poles of concentration
// kappa is off by with probability 1e-6, and the factors kappa's estimate stays within.
double mean_tolerance_deg(double kappa, double n) {
  return std::acos(std::max(-1.0, 1 - std::log(1e6) / (kappa * n))) * 180 / std::numbers::pi;
}
std::pair<double, double> kappa_factors(double n) {
  const double df = 2 * (n - 1), z = 4.753;
  const auto q = [&](double zz) {
    const double c = 1 - 2 / (9 * df) + zz * std::sqrt(2 / (9 * df));
    return c * c * c;
  };
  return {1 / q(z), 1 / q(-z)};
}

json info_json(const std::string& file) {
  const auto r = run_tool("slice-info", {file, "--json"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  return json::parse(r.out);
}

std::map<std::string, json> by_name(const json& j) {
  std::map<std::string, json> out;
  for (const auto& s : j["joints"]["by_set"]) out[s["name"].get<std::string>()] = s;
  return out;
}

// A FAB of the three sets: drawn by slice-joints, written by the library's FAB writer.
void make_fab(const test::TempDir& tmp) {
  test::write_text(tmp / "source.toml",
                   std::string("[scene]\nname = \"source\"\nseed = 43\n") + kDomain + kSets);
  const auto r = run_tool("slice-joints",
                          {(tmp / "source.toml").string(), "-o", (tmp / "source.h5").string()});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  slice::write_fab(tmp / "net.fab", slice::read_joints(tmp / "source.h5"));
  test::write_text(tmp / "dfn.toml", std::string("[scene]\nname = \"dfn\"\n") + kDomain +
                                         "[[dfn]]\nfile = \"net.fab\"\n");
  const auto d =
      run_tool("slice-joints", {(tmp / "dfn.toml").string(), "-o", (tmp / "dfn.h5").string()});
  INFO(d.err);
  REQUIRE(d.exit_code == 0);
}

}  // namespace

TEST_CASE("slice-info measures a FAB's sets: orientation, Fisher kappa, sizes, intensity",
          "[tools][dfn][statistics]") {
  test::TempDir tmp;
  make_fab(tmp);
  const json j = info_json((tmp / "dfn.h5").string());
  auto sets = by_name(j);
  for (const Truth& t : kTruth) {
    CAPTURE(t.name);
    REQUIRE(sets.count(t.name));
    const json& s = sets[t.name];
    CAPTURE(s.dump());
    const double n = s["joints"].get<double>();
    // The public contract: these three names, in degrees.
    const double dip = s["mean_dip"], ddir = s["mean_dip_direction"], kappa = s["fisher_kappa"];
    CHECK(axis_angle_deg(dip, ddir, t.dip, t.ddir) < mean_tolerance_deg(t.kappa, n));
    const auto [lo, hi] = kappa_factors(n);
    CHECK(kappa > t.kappa * lo);
    CHECK(kappa < t.kappa * hi);
    CHECK(s["alpha95"].get<double>() > 0);
    CHECK(s["alpha95"].get<double>() < 3);
    // The sizes: the distribution they were drawn from fits best, and well.
    const json& z = s["statistics"]["sizes"];
    CHECK(z["best"] == t.size);
    for (const auto& f : z["fits"])
      if (f["distribution"] == t.size) CHECK(f["ks"].get<double>() < z["ks_critical_95"]);
    // Intensity as joints.h5 records it; P10 on the chord along the mean pole.
    CHECK(s["statistics"]["p32"] == s["p32"]);
    CHECK(s["p10"].get<double>() > 0);
    const auto& sl = s["statistics"]["scanline"];
    const Vec3 along = Vec3(sl["to"][0], sl["to"][1], sl["to"][2]) -
                       Vec3(sl["from"][0], sl["from"][1], sl["from"][2]);
    CHECK(std::abs(along.normalized().dot(slice::normal_from_dip(dip, ddir))) > 1 - 1e-9);
    CHECK_THAT(s["statistics"]["sets_entry"].get<std::string>(),
               Contains("[[sets]]\nname = \"" + std::string(t.name) + "\""));
  }
  // The lognormal set's parameters (mean 10, sd 4).
  const json& fit = sets["J1"]["statistics"]["sizes"]["fits"][0];
  CHECK(fit["distribution"] == "lognormal");
  CHECK_THAT(fit["mean"].get<double>(), WithinRel(10, 0.15));
  CHECK_THAT(fit["sd"].get<double>(), WithinRel(4, 0.3));
  CHECK(sets["J2"]["statistics"]["sizes"]["shape"] == "polygon");
  CHECK(sets["J2"]["statistics"]["sizes"]["sides"] == 6);
  // The set's own dip and dip direction in joints.h5 are the same folded mean.
  const slice::JointSystem js = slice::read_joints(tmp / "dfn.h5");
  for (const auto& spec : js.sets) {
    if (!sets.count(spec.name)) continue;
    CHECK(axis_angle_deg(spec.dip_deg, spec.dip_direction_deg, sets[spec.name]["mean_dip"],
                         sets[spec.name]["mean_dip_direction"]) < 1e-6);
  }

  SECTION("the FAB file on its own gives the same orientation statistics") {
    const json f = info_json((tmp / "net.fab").string());
    CHECK(f["kind"] == "dfn");
    auto direct = by_name(f);
    for (const Truth& t : kTruth) {
      CAPTURE(t.name);
      REQUIRE(direct.count(t.name));
      CHECK_THAT(direct[t.name]["fisher_kappa"].get<double>(),
                 WithinRel(sets[t.name]["fisher_kappa"].get<double>(), 1e-9));
      CHECK(axis_angle_deg(direct[t.name]["mean_dip"], direct[t.name]["mean_dip_direction"],
                           sets[t.name]["mean_dip"], sets[t.name]["mean_dip_direction"]) < 1e-6);
      CHECK(direct[t.name]["statistics"]["sizes"]["best"] == t.size);
    }
  }
  SECTION("text: a line per set and the [[sets]] entries") {
    const auto r = run_tool("slice-info", {(tmp / "dfn.h5").string()});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.out, Contains("set statistics"));
    CHECK_THAT(r.out, Contains("J1: "));
    CHECK_THAT(r.out, Contains("Fisher kappa"));
    CHECK_THAT(r.out, Contains("alpha95"));
    CHECK_THAT(r.out, Contains("best lognormal"));
    CHECK_THAT(r.out, Contains("P10"));
    CHECK_THAT(r.out, Contains("\n[[sets]]\nname = \"J3\"\n"));
    CHECK_THAT(r.out, Contains("mean_dip="));
    // The order the joints were joined in, which the entries do not carry: named beside them.
    CHECK_THAT(r.out, Contains("these have [options] order = \"as-given\""));
    test::write_text(tmp / "ordered.toml", std::string("[scene]\nname = \"dfn\"\n") + kDomain +
                                               "[options]\norder = \"largest-first\"\n"
                                               "[[dfn]]\nfile = \"net.fab\"\n");
    const auto o = run_tool("slice-joints",
                            {(tmp / "ordered.toml").string(), "-o", (tmp / "ordered.h5").string()});
    REQUIRE(o.exit_code == 0);
    const auto ri = run_tool("slice-info", {(tmp / "ordered.h5").string()});
    CHECK_THAT(ri.out, Contains("these have [options] order = \"largest-first\""));
  }
  SECTION("a file that is not a DFN: exit 1, one line naming it") {
    test::write_text(tmp / "bad.fab", "BEGIN FORMAT\n");
    const auto r = run_tool("slice-info", {(tmp / "bad.fab").string()});
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Contains("bad.fab"));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
}

TEST_CASE("the [[sets]] entries slice-info prints draw sets with the DFN's statistics",
          "[tools][dfn][statistics]") {
  test::TempDir tmp;
  make_fab(tmp);
  const json dfn = info_json((tmp / "dfn.h5").string());
  std::string scene = std::string("[scene]\nname = \"again\"\nseed = 5\n") + kDomain;
  for (const auto& s : dfn["joints"]["by_set"]) scene += s["statistics"]["sets_entry"];
  test::write_text(tmp / "again.toml", scene);
  const auto r =
      run_tool("slice-joints", {(tmp / "again.toml").string(), "-o", (tmp / "again.h5").string()});
  INFO(scene);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  auto before = by_name(dfn);
  auto after = by_name(info_json((tmp / "again.h5").string()));
  for (const Truth& t : kTruth) {
    CAPTURE(t.name);
    const json &a = before[t.name], &b = after[t.name];
    CAPTURE(a["mean_dip"], a["mean_dip_direction"], a["fisher_kappa"], b["mean_dip"],
            b["mean_dip_direction"], b["fisher_kappa"], a["p32"], b["p32"]);
    const double n = b["joints"].get<double>(), kappa = a["fisher_kappa"];
    // Drawn about the printed mean with the printed kappa: off by what kappa and N allow.
    CHECK(axis_angle_deg(a["mean_dip"], a["mean_dip_direction"], b["mean_dip"],
                         b["mean_dip_direction"]) < mean_tolerance_deg(kappa, n));
    CHECK(axis_angle_deg(a["mean_dip"], a["mean_dip_direction"], b["mean_dip"],
                         b["mean_dip_direction"]) < 5);
    const auto [lo, hi] = kappa_factors(n);
    CHECK(b["fisher_kappa"].get<double>() > kappa * lo);
    CHECK(b["fisher_kappa"].get<double>() < kappa * hi);
    // p32 is the target the set draws to; the sizes come from the fit.
    CHECK_THAT(b["p32"].get<double>(), WithinRel(a["p32"].get<double>(), 0.05));
    CHECK(b["statistics"]["sizes"]["best"] == a["statistics"]["sizes"]["best"]);
  }
}

TEST_CASE(
    "slice-info tells an ellipse set by its joints' second moments, and its entry draws the same "
    "shape and areas back",
    "[tools][dfn][statistics]") {
  // Elliptical joints (12 corners, aspect 2.5) were measured as regular 12-gons of the same
  // area: the printed entry drew round joints. A stretched regular polygon's principal second
  // moments give its aspect exactly.
  test::TempDir tmp;
  test::write_text(tmp / "ellipses.toml",
                   std::string("[scene]\nname = \"ell\"\nseed = 7\n") + kDomain + R"([[sets]]
name = "E"
dip = 40
dip_direction = 100
fisher_kappa = 30
count = 300
size = { distribution = "lognormal", mean = 8, sd = 2 }
shape = "ellipse"
aspect = 2.5
sides = 12
[[sets]]
name = "P"
dip = 70
dip_direction = 250
count = 200
size = { distribution = "exponential", mean = 5 }
shape = "polygon"
sides = 7
)");
  const auto r = run_tool("slice-joints",
                          {(tmp / "ellipses.toml").string(), "-o", (tmp / "ellipses.h5").string()});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  auto sets = by_name(info_json((tmp / "ellipses.h5").string()));
  const json& e = sets["E"]["statistics"];
  CHECK(e["sizes"]["shape"] == "ellipse");
  CHECK(e["sizes"]["aspect"].get<double>() == Approx(2.5).epsilon(1e-9));
  CHECK(e["sizes"]["sides"] == 12);
  const std::string entry = e["sets_entry"];
  CHECK_THAT(entry,
             Contains("shape = \"ellipse\"\naspect = 2.5\nsides = 12\nfit = \"equal-area\""));
  // Regular polygons stay polygons, with no aspect.
  const json& p = sets["P"]["statistics"];
  CHECK(p["sizes"]["shape"] == "polygon");
  CHECK(p["sizes"]["sides"] == 7);
  CHECK_FALSE(p["sizes"].contains("aspect"));

  // Drawn again from the entry: the same shape, and sizes of the same areas (the lognormal's
  // mean within the scatter of 300 draws).
  test::write_text(tmp / "again.toml",
                   std::string("[scene]\nname = \"again\"\nseed = 9\n") + kDomain + entry);
  const auto a =
      run_tool("slice-joints", {(tmp / "again.toml").string(), "-o", (tmp / "again.h5").string()});
  INFO(a.err);
  REQUIRE(a.exit_code == 0);
  const json again = by_name(info_json((tmp / "again.h5").string()))["E"]["statistics"];
  CHECK(again["sizes"]["shape"] == "ellipse");
  CHECK(again["sizes"]["aspect"].get<double>() == Approx(2.5).epsilon(1e-9));
  CHECK(again["sizes"]["sides"] == 12);
  const auto lognormal_mean = [](const json& sizes) {
    for (const auto& f : sizes["fits"])
      if (f["distribution"] == "lognormal") return f["mean"].get<double>();
    FAIL("no lognormal fit");
    return 0.0;
  };
  CHECK(lognormal_mean(again["sizes"]) == Approx(lognormal_mean(e["sizes"])).epsilon(0.08));
}

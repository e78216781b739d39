// slice-extract: geom.h5 -> a sub-model geom.h5, the blocks within a region (issue 26 item 3,
// docs/submodels.md). The rule lives in the library (slice/extract.hpp); this parses and reports.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/tool.hpp"
#include "slice/error.hpp"
#include "slice/extract.hpp"
#include "slice/h5io.hpp"
#include "slice/output.hpp"

namespace {

// "1,2.5,-3" -> its numbers; exactly `count` finite ones, or Error naming the option.
std::vector<double> numbers(const std::string& option, const std::string& text, std::size_t count,
                            const std::string& form) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string word =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(word.c_str(), &end);
    if (word.empty() || end != word.c_str() + word.size() || errno == ERANGE || !std::isfinite(x))
      throw slice::Error(option + " " + text, "'" + word + "' is not a finite number",
                         "give " + form + " (numbers separated by commas, no spaces)");
    out.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (out.size() != count)
    throw slice::Error(
        option + " " + text,
        "has " + std::to_string(out.size()) + " numbers; expected " + std::to_string(count),
        "give " + form);
  return out;
}

// "all" -> every zone; "0,2" -> those indices. Zones have no names in a geom.h5.
std::vector<std::size_t> zone_indices(const std::string& text) {
  std::vector<std::size_t> out;
  if (text == "all") return out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string word =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (word.empty() || word.size() > 9 || word.find_first_not_of("0123456789") != word.npos)
      throw slice::Error("--near-zone " + text, "'" + word + "' is not a zone index",
                         "zones have no names in a geom.h5: give all, or indices such as 0 or "
                         "0,2 (slice-info counts the zones)");
    out.push_back(std::stoul(word));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  tool::Tool t{"slice-extract",
               "Take the blocks within a region out of a geom.h5 into a new geom.h5 (a sub-model): "
               "blocks the region's boundary cuts are kept whole and fixed, the others outside "
               "left out (docs/submodels.md)."};
  std::string in, out, ids, box, sphere, cylinder, zone, distance, ring = "0";
  slice::ExtractOptions opt;  // defaults live in the library
  t.cli.add_option("geometry", in, "geom.h5 from slice-vertices")->required();
  t.cli.add_option("-o,--output", out, "the sub-model's geom.h5")->required();
  t.cli.add_option("--box", box, "the region: the box xmin,ymin,zmin,xmax,ymax,zmax");
  t.cli.add_option("--sphere", sphere, "the region: the ball x,y,z,r");
  t.cli.add_option("--cylinder", cylinder,
                   "the region: the cylinder of radius r about the axis from x0,y0,z0 to "
                   "x1,y1,z1, with flat ends there: x0,y0,z0,x1,y1,z1,r");
  t.cli.add_option("--near-zone", zone,
                   "the region: the points within --distance of these zones of the file: all, or "
                   "indices (/zones regions from 0, then /zones meshes), e.g. 0,2");
  t.cli.add_option("--distance", distance, "--near-zone: the distance from the zones");
  t.cli
      .add_option("--ring", ring,
                  "thickness of the fixed outer ring: blocks that come within it of the region's "
                  "boundary are fixed too (0: only the blocks the boundary cuts or touches)")
      ->capture_default_str();
  t.cli.add_option("--ids", ids,
                   "also write the source row (0-based /blocks index) of each kept block, one a "
                   "line, in the sub-model's order");
  t.add_compress_option();
  return t.run(argc, argv, [&] {
    const int regions =
        int(!box.empty()) + int(!sphere.empty()) + int(!cylinder.empty()) + int(!zone.empty());
    if (regions != 1)
      throw slice::Error(
          regions ? "the region options" : "slice-extract",
          regions ? "give one region, not " + std::to_string(regions) : "no region given",
          "give one of --box, --sphere, --cylinder or --near-zone with --distance");
    if (zone.empty() != distance.empty())
      throw slice::Error(zone.empty() ? "--distance" : "--near-zone",
                         zone.empty() ? "is for --near-zone" : "needs --distance",
                         zone.empty() ? "drop it, or give --near-zone too"
                                      : "give --distance d, the distance from the zones");
    slice::ExtractRegion& r = opt.region;
    if (!box.empty()) {
      const auto v = numbers("--box", box, 6, "xmin,ymin,zmin,xmax,ymax,zmax");
      r.shape = slice::RegionShape::box;
      r.a = {v[0], v[1], v[2]};
      r.b = {v[3], v[4], v[5]};
    } else if (!sphere.empty()) {
      const auto v = numbers("--sphere", sphere, 4, "x,y,z,r");
      r.shape = slice::RegionShape::sphere;
      r.a = {v[0], v[1], v[2]};
      r.radius = v[3];
    } else if (!cylinder.empty()) {
      const auto v = numbers("--cylinder", cylinder, 7, "x0,y0,z0,x1,y1,z1,r");
      r.shape = slice::RegionShape::cylinder;
      r.a = {v[0], v[1], v[2]};
      r.b = {v[3], v[4], v[5]};
      r.radius = v[6];
    } else {
      r.shape = slice::RegionShape::near_zone;
      r.zones = zone_indices(zone);
      r.radius = numbers("--distance", distance, 1, "a distance d")[0];
    }
    opt.ring = numbers("--ring", ring, 1, "a thickness t >= 0")[0];
    opt.validate();  // before anything is read
    tool::check_distinct_paths({{"geometry", in, false}, {"-o", out}, {"--ids", ids}});
    const slice::BlockSystem bs = slice::read_blocks(in);
    const slice::SubModel sub = slice::extract_blocks(bs, opt, in);
    slice::write_blocks(out, sub.blocks, t.provenance(in), t.write_options());
    if (!ids.empty()) {
      std::string text;
      for (const std::int64_t b : sub.source_block) text += std::to_string(b) + '\n';
      slice::write_text_file(ids, text);
    }
    const slice::ExtractStats& s = sub.stats;
    t.say(describe(r) + ": " + std::to_string(s.kept) + " of " + std::to_string(s.source_blocks) +
          " blocks kept (" + std::to_string(s.removed) + " of them removed in the source; " +
          std::to_string(s.reached) + " that the region reaches between their vertices), " +
          std::to_string(s.clusters) + " clusters whole, volume " + tool::sig(s.volume, 6) +
          " -> " + out);
    t.say("fixed: " + std::to_string(s.cut) + " blocks the boundary cuts, " +
          std::to_string(s.ring) + " more within the ring of " + tool::sig(opt.ring, 6) + ", " +
          std::to_string(s.was_fixed) + " of the kept blocks were fixed in the source");
    t.exit_now();
  });
}

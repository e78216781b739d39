// slice-joints: scene file (TOML) -> joints.h5 (DESIGN sections 3, 6, 7).
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "common/tool.hpp"
#include "slice/h5io.hpp"
#include "slice/scene.hpp"

int main(int argc, char** argv) {
  tool::Tool t{"slice-joints",
               "Read a scene file, generate its joints and write them to an HDF5 file."};
  std::string scene_file;
  std::string out = "joints.h5";
  t.cli.add_option("scene", scene_file, "scene file (TOML, see docs/scenes.md)")->required();
  t.cli.add_option("-o,--output", out, "output file")->capture_default_str();
  std::optional<std::int64_t> seed;  // as [scene] seed: an integer from 0 to 2^63 - 1
  t.cli
      .add_option("--seed", seed,
                  "seed of the random joint sets, in place of the scene's [scene] seed (for "
                  "realization sweeps: joints.h5 records the seed used)")
      ->check(CLI::NonNegativeNumber);
  t.add_compress_option();
  return t.run(argc, argv, [&] {
    tool::check_distinct_paths({{"scene", scene_file, false}, {"-o", out}});
    slice::Scene scene = slice::load_scene(scene_file);
    if (seed) scene.seed = static_cast<std::uint64_t>(*seed);
    const slice::JointSystem js = slice::generate_joints(scene);
    slice::write_joints(out, js, t.provenance(scene_file), t.write_options());
    std::size_t persistent = 0;
    for (const auto& j : js.joints) persistent += j.persistent() ? 1 : 0;
    t.say(std::to_string(js.joints.size()) + " joints (" + std::to_string(persistent) +
          " persistent, " + std::to_string(js.joints.size() - persistent) +
          (js.dimension == 2 ? " segments) in " : " polygons) in ") +
          std::to_string(js.sets.size()) + " sets, seed " + std::to_string(js.seed) + " -> " + out);
  });
}

// Uses the installed library as any program would: a unit cube cut by the planes x = 0.5,
// y = 0.5 and z = 0.5 is 8 blocks. Exit 0 only if it is.
#include <cstddef>
#include <exception>
#include <iostream>
#include <slice/cut.hpp>
#include <slice/scene.hpp>
#include <string>

int main() {
  // dip 90, dip direction 90: normal +x; dip 90, dip direction 0: normal +y; dip 0: normal +z.
  const std::string scene = R"([domain]
box = { min = [0, 0, 0], max = [1, 1, 1] }
[[joints]]
dip = 90
dip_direction = 90
point = [0.5, 0.5, 0.5]
[[joints]]
dip = 90
dip_direction = 0
point = [0.5, 0.5, 0.5]
[[joints]]
dip = 0
dip_direction = 0
point = [0.5, 0.5, 0.5]
)";
  constexpr std::size_t kExpected = 8;
  try {
    const auto js = slice::generate_joints(slice::parse_scene(scene, "consumer.toml"));
    const auto r = slice::cut_blocks(js, slice::CutOptions{});
    const std::size_t got = r.blocks.blocks.size();
    std::cout << "consumer: " << got << " blocks, expected " << kExpected << '\n';
    return got == kExpected ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "consumer: error: " << e.what() << '\n';
    return 1;
  }
}

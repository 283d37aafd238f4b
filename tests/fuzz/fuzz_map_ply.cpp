// libFuzzer target: the layered mesh of a map directory, traversability.ply, as `terramesh plan
// MAP_DIR` reads it (traversability::readMapDirectory), beside a valid robot.yaml and map_frame.yaml.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz_support.h"
#include "traversability/map_directory.h"
#include "traversability/robot_profile.h"
#include "traversability/robot_profile_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  static const std::filesystem::path dir = [] {
    const std::filesystem::path map = fuzz::scratchDir() / "map";
    std::filesystem::create_directories(map);
    traversability::writeRobotProfile(map / "robot.yaml", traversability::RobotProfile{});
    fuzz::writeFile(map / "map_frame.yaml", "up: [0, 0, 1]\nmetres_per_unit: 1\n");
    return map;
  }();
  fuzz::writeFile(dir / "traversability.ply", fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] { traversability::readMapDirectory(dir); });
  return 0;
}

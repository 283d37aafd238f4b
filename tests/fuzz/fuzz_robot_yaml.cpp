// libFuzzer target: a robot profile (YAML), traversability::loadRobotProfile.
#include <cstddef>
#include <cstdint>

#include "traversability/robot_profile.h"
#include "traversability/robot_profile_yaml.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const auto path = fuzz::writeFile(fuzz::scratchDir() / "robot.yaml", fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] { traversability::loadRobotProfile(path); });
  return 0;
}

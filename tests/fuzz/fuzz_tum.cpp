// libFuzzer target: a TUM RGB-D trajectory, datasets::readTumTrajectory.
#include <cstddef>
#include <cstdint>

#include "datasets/tum_trajectory.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const auto path = fuzz::writeFile(fuzz::scratchDir() / "trajectory.txt", fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] { datasets::readTumTrajectory(path); });
  return 0;
}

// libFuzzer target: the KITTI odometry text files, each reader on the same bytes:
// calib.txt (datasets::readKittiVelodyneToCam0), poses (readKittiPoses), times.txt
// (readKittiTimes).
#include <cstddef>
#include <cstdint>

#include "datasets/kitti_odometry_reader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const auto path = fuzz::writeFile(fuzz::scratchDir() / "calib.txt", fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] { datasets::readKittiVelodyneToCam0(path); });
  fuzz::expectOnlyInputErrors([&] { datasets::readKittiPoses(path); });
  fuzz::expectOnlyInputErrors([&] { datasets::readKittiTimes(path); });
  return 0;
}

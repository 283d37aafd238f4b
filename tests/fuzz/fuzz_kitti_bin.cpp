// libFuzzer target: a KITTI Velodyne scan (.bin, float32 x y z reflectance), datasets::readVelodyneScan.
#include <cstddef>
#include <cstdint>

#include "datasets/kitti_odometry_reader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const auto path = fuzz::writeFile(fuzz::scratchDir() / "000000.bin", fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] { datasets::readVelodyneScan(path); });
  return 0;
}

// libFuzzer target: the authors' incremental JSON (slam_data_version 0.1, 0.2, 0.3), datasets::readSlamJson.
#include <cstddef>
#include <cstdint>

#include "datasets/slam_json.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const auto path = fuzz::writeFile(fuzz::scratchDir() / "slam.json", fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] { datasets::readSlamJson(path); });
  return 0;
}

// libFuzzer target: OpenMVG sfm_data.json, datasets::readOpenMvgSfmData.
#include <cstddef>
#include <cstdint>

#include "datasets/openmvg_reader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const auto path = fuzz::writeFile(fuzz::scratchDir() / "sfm_data.json", fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] { datasets::readOpenMvgSfmData(path); });
  return 0;
}

// libFuzzer target: terramesh's own .tmstream format, datasets::readStreamFile.
#include <cstddef>
#include <cstdint>

#include "datasets/stream_format.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const auto path = fuzz::writeFile(fuzz::scratchDir() / "input.tmstream", fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] { datasets::readStreamFile(path); });
  return 0;
}

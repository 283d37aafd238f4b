// libFuzzer target: a COLMAP binary model, datasets::readColmapStream. The input holds
// cameras.bin, images.bin and points3D.bin separated by fuzz::kFileSeparator.
#include <cstddef>
#include <cstdint>

#include "datasets/colmap_reader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const auto parts = fuzz::splitFiles(fuzz::asText(data, size), 3);
  const auto& dir = fuzz::scratchDir();
  fuzz::writeFile(dir / "cameras.bin", parts[0]);
  fuzz::writeFile(dir / "images.bin", parts[1]);
  fuzz::writeFile(dir / "points3D.bin", parts[2]);
  fuzz::expectOnlyInputErrors([&] { datasets::readColmapStream(dir, datasets::ColmapFileType::kBinary); });
  return 0;
}

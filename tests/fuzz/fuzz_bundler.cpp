// libFuzzer target: a Bundler v0.3 bundle file and its image list, datasets::readBundler. The
// input holds bundle.out, then optionally (after fuzz::kFileSeparator) list.txt.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "datasets/bundler_reader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const std::string_view input = fuzz::asText(data, size);
  const bool has_list = input.find(fuzz::kFileSeparator) != std::string_view::npos;
  const auto parts = fuzz::splitFiles(input, 2);
  const auto bundle = fuzz::writeFile(fuzz::scratchDir() / "bundle.out", parts[0]);
  std::filesystem::path list;
  if (has_list) list = fuzz::writeFile(fuzz::scratchDir() / "list.txt", parts[1]);
  fuzz::expectOnlyInputErrors([&] { datasets::readBundler(bundle, list); });
  return 0;
}

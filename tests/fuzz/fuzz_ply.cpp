// libFuzzer target: the generic PLY reader of common/ (ascii and binary, either endianness),
// terramesh::ply::read from a stream.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "common/ply.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  std::istringstream in(std::string(fuzz::asText(data, size)), std::ios::binary);
  fuzz::expectOnlyInputErrors([&] { ply::read(in, "fuzz.ply"); });
  return 0;
}

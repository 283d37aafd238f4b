// libFuzzer target: the mesh input of `terramesh traverse`, mesher::readMesh. The extension it
// dispatches on follows the input's first bytes: "ply" -> .ply, "OFF" -> .off, else .obj.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.h"
#include "mesher/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace terramesh;
  const std::string_view input = fuzz::asText(data, size);
  const char* name = input.substr(0, 3) == "ply" ? "mesh.ply" : input.substr(0, 3) == "OFF" ? "mesh.off" : "mesh.obj";
  const auto path = fuzz::writeFile(fuzz::scratchDir() / name, input);
  fuzz::expectOnlyInputErrors([&] { mesher::readMesh(path); });
  return 0;
}

#pragma once
// Shared by the libFuzzer targets: a private temporary folder for readers that take a path,
// splitting one fuzz input into several files, and the rule that only InputError is expected.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "common/input_error.h"

namespace terramesh::fuzz {

/// Separates the files of a multi-file input (COLMAP's three files, Bundler's bundle and list).
inline constexpr std::string_view kFileSeparator = "\n@@terramesh-fuzz-next-file@@\n";

/// A folder of this process's own under $TMPDIR (or /tmp), removed when the process exits.
class ScratchDir {
 public:
  ScratchDir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/terramesh_fuzz_XXXXXX";
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (mkdtemp(buffer.data()) == nullptr) std::abort();
    path_ = buffer.data();
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The process's scratch folder (created on first use).
inline const std::filesystem::path& scratchDir() {
  static const ScratchDir dir;
  return dir.path();
}

/// Writes `bytes` to `path` (replacing it) and returns the path.
inline std::filesystem::path writeFile(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) std::abort();
  return path;
}

/// The fuzz input as text.
inline std::string_view asText(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// Splits `input` at kFileSeparator into exactly `count` parts (missing parts are empty; the last
/// part keeps any further separators).
inline std::vector<std::string_view> splitFiles(std::string_view input, std::size_t count) {
  std::vector<std::string_view> parts;
  while (parts.size() + 1 < count) {
    const std::size_t at = input.find(kFileSeparator);
    if (at == std::string_view::npos) break;
    parts.push_back(input.substr(0, at));
    input.remove_prefix(at + kFileSeparator.size());
  }
  parts.push_back(input);
  while (parts.size() < count) parts.emplace_back();
  return parts;
}

/// Runs `read`; a terramesh::InputError is an expected outcome of bad input, anything else
/// (another exception type, a crash, a sanitizer report) escapes and fails the run.
template <typename Read>
void expectOnlyInputErrors(Read&& read) {
  try {
    read();
  } catch (const terramesh::InputError&) {
  }
}

}  // namespace terramesh::fuzz

#include "common/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <random>
#include <stdexcept>
#include <system_error>

namespace terramesh {
namespace {

std::filesystem::path temporarySibling(const std::filesystem::path& path) {
  std::random_device device;
  const auto suffix = std::to_string(device()) + std::to_string(::getpid());
  return path.parent_path() / ("." + path.filename().string() + ".tmp" + suffix);
}

void syncFile(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write) {
  const std::filesystem::path temporary = temporarySibling(path);
  try {
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) throw std::runtime_error(path.string() + ": cannot create file");
      write(out);
      out.flush();
      if (!out) throw std::runtime_error(path.string() + ": write failed");
    }
    syncFile(temporary);
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) throw std::runtime_error(path.string() + ": cannot rename into place: " + error.message());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void writeFileAtomically(const std::filesystem::path& path, const std::string& content) {
  writeFileAtomically(path, [&content](std::ostream& out) { out << content; });
}

}  // namespace terramesh

#include "process_memory.h"

#include <fstream>
#include <string>

namespace terramesh::cli {
namespace {

/// The value of field `key` ("VmRSS:") of /proc/self/status, in MiB (the file gives kB).
double statusMib(const std::string& key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(key, 0) == 0) return std::stod(line.substr(key.size())) / 1024.0;
  }
  return 0;
}

}  // namespace

double residentMib() { return statusMib("VmRSS:"); }
double peakResidentMib() { return statusMib("VmHWM:"); }

}  // namespace terramesh::cli

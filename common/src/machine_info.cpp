#include "common/machine_info.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

namespace terramesh {

std::string describeMachine() {
  std::string model = "unknown CPU";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  long memory_kib = 0;
  std::ifstream meminfo("/proc/meminfo");
  for (std::string line; std::getline(meminfo, line);) {
    if (line.rfind("MemTotal:", 0) == 0) {
      std::istringstream(line.substr(9)) >> memory_kib;
      break;
    }
  }
  std::ostringstream out;
  out << model << ", " << ::sysconf(_SC_NPROCESSORS_ONLN) << " cores, "
      << (memory_kib + 512 * 1024) / (1024 * 1024) << " GiB";
  return out.str();
}

}  // namespace terramesh

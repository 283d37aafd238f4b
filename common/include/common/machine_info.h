#pragma once

#include <string>

namespace terramesh {

/// "CPU model, N cores, M GiB" for benchmark reports, read from /proc (Linux).
std::string describeMachine();

}  // namespace terramesh

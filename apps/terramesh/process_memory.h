#pragma once

// What this process holds in memory, from /proc/self/status (Linux; 0 where it is missing).

namespace terramesh::cli {

/// Resident memory now (VmRSS), MiB.
double residentMib();
/// Peak resident memory so far (VmHWM), MiB.
double peakResidentMib();

}  // namespace terramesh::cli

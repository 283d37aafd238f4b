#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "bench_run.h"

namespace terramesh::cli {

/// What the stream stands for, to turn keyframe rates into camera-frame rates.
struct BenchContext {
  std::string stream_name;
  std::string machine;
  std::size_t camera_frames = 0;  ///< frames the stream covers (0: unknown)
  double camera_rate_hz = 10.0;
};

/// Prints Table II (per-step totals, rates, speed-ups), Table IV (per-keyframe averages), the
/// per-keyframe latency distribution, the growth of the per-keyframe time over the run, the
/// next-cell cache hit rate and memory, for runs of the same stream in one invocation.
void printBenchReport(std::ostream& out, const BenchContext& context,
                      const std::vector<BenchRun>& runs);

/// Writes the per-keyframe timing plots (like the paper's Figures 5 and 6) into `dir`: total time
/// per keyframe for every mode, and per step for each mode. Returns the files written.
std::vector<std::filesystem::path> writeBenchPlots(const std::filesystem::path& dir,
                                                   const BenchContext& context,
                                                   const std::vector<BenchRun>& runs);

}  // namespace terramesh::cli

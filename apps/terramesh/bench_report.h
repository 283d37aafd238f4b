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

/// Writes `dir/runs.csv`, the index of the runs for scripts/figures/bench_figures.py: header
/// `mode,stream,keyframes_csv,summary`, one row per run in `runs` order, paths relative to `dir`
/// (fields quoted as in RFC 4180 where needed). Written atomically. Returns the file's path.
/// @throw std::runtime_error if the file cannot be written.
std::filesystem::path writeBenchIndex(const std::filesystem::path& dir, const BenchContext& context,
                                      const std::vector<BenchRun>& runs);

/// The command line that draws the figures of a bench folder (like the paper's Figures 5 and 6).
std::string benchFiguresCommand(const std::filesystem::path& dir);

}  // namespace terramesh::cli

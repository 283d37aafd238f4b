#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "datasets/slam_stream.h"
#include "mesher/mesher_config.h"

namespace terramesh::cli {

/// One row of a run's per-update CSV, as numbers keyed by column name.
using CsvRow = std::map<std::string, double>;

/// What one mode did over a stream.
struct BenchRun {
  std::string mode;
  std::vector<CsvRow> keyframes;  ///< rows of keyframe events only, in order
  long peak_rss_kib = 0;          ///< peak resident memory of the process that ran it
  std::map<std::string, double> summary;  ///< end-of-run sizes (summary.txt of the run)
};

/// Runs the mesher with `config` over the stream in a child process (so that its peak memory is
/// its own), writing `dir/keyframes.csv` and `dir/summary.txt`, and reads them back.
/// @throw std::runtime_error if the child fails.
BenchRun runModeIsolated(const datasets::SlamStream& stream, const mesher::MesherConfig& config,
                         const std::filesystem::path& dir, std::size_t max_keyframes);

}  // namespace terramesh::cli

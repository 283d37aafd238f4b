#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace terramesh::planning {

/// Runs of one planner: property declarations as OMPL writes them ("time REAL",
/// "solved BOOLEAN", "surface_length REAL", ...) and one value per property per run (NaN for
/// "no value"; booleans as 0 or 1).
struct BenchmarkPlannerRuns {
  std::string planner;  ///< e.g. "geometric_RRTstar"
  std::vector<std::string> properties;
  std::vector<std::vector<double>> runs;
};

/// One experiment in OMPL's benchmark log format (ompl.kavrakilab.org/benchmark.html), which
/// ompl_benchmark_statistics turns into an SQLite database.
struct BenchmarkExperiment {
  std::string name;
  /// Experiment parameters ("map_type" -> "mesh"), stored as TEXT columns of `experiments`.
  std::vector<std::pair<std::string, std::string>> parameters;
  std::string hostname = "unknown";
  std::string setup;  ///< free text: the problem and the map
  std::uint32_t seed = 1;
  double time_limit_s = 0;
  double memory_limit_mb = 0;
  std::size_t run_count = 0;
  double total_time_s = 0;
  std::vector<BenchmarkPlannerRuns> planners;

  /// @throw std::invalid_argument if a run's value count differs from its planner's property
  ///        count, a property is not "name TYPE", or a name or parameter is empty.
  void validate() const;
};

/// The log text. @throw std::invalid_argument if the experiment does not validate.
std::string formatOmplBenchmarkLog(const BenchmarkExperiment& experiment);

/// Writes the log atomically. @throw std::invalid_argument (see validate), std::runtime_error if
/// the file cannot be written.
void writeOmplBenchmarkLog(const std::filesystem::path& path, const BenchmarkExperiment& experiment);

}  // namespace terramesh::planning

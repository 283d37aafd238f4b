#include "planning/ompl_benchmark_log.h"

#include <cmath>
#include <ctime>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"

namespace terramesh::planning {
namespace {

/// Spaces would split names in the log; OMPL's own names use underscores in the database.
std::string withoutSpaces(std::string text) {
  for (char& c : text) {
    if (c == ' ' || c == '\n' || c == ';') c = '_';
  }
  return text;
}

std::string formatValue(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return "inf";
  std::ostringstream out;
  out << std::setprecision(12) << value;
  return out.str();
}

}  // namespace

void BenchmarkExperiment::validate() const {
  std::ostringstream problems;
  if (name.empty()) problems << " name is empty;";
  for (const auto& [key, value] : parameters) {
    if (key.empty() || value.empty()) problems << " parameter \"" << key << "\" has an empty name or value;";
  }
  for (const BenchmarkPlannerRuns& planner : planners) {
    if (planner.planner.empty()) problems << " a planner has no name;";
    for (const std::string& property : planner.properties) {
      if (property.find(' ') == std::string::npos) {
        problems << " property \"" << property << "\" of " << planner.planner << " is not \"name TYPE\";";
      }
    }
    for (std::size_t r = 0; r < planner.runs.size(); ++r) {
      if (planner.runs[r].size() != planner.properties.size()) {
        problems << ' ' << planner.planner << " run " << r << " has " << planner.runs[r].size() << " values for "
                 << planner.properties.size() << " properties;";
      }
    }
  }
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("BenchmarkExperiment:" + text);
}

std::string formatOmplBenchmarkLog(const BenchmarkExperiment& experiment) {
  experiment.validate();
  std::ostringstream out;
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  out << "OMPL version 1.5.2\n";
  out << "Experiment " << withoutSpaces(experiment.name) << '\n';
  out << experiment.parameters.size() << " experiment properties\n";
  for (const auto& [key, value] : experiment.parameters) out << withoutSpaces(key) << " TEXT = " << value << '\n';
  out << "Running on " << withoutSpaces(experiment.hostname) << '\n';
  out << "Starting at " << std::put_time(&utc, "%Y-%m-%d %H:%M:%S") << '\n';
  out << "<<<|\n" << experiment.setup << (experiment.setup.empty() || experiment.setup.back() == '\n' ? "" : "\n") << "|>>>\n";
  out << "<<<|\n|>>>\n";
  out << experiment.seed << " is the random seed\n";
  out << formatValue(experiment.time_limit_s) << " seconds per run\n";
  out << formatValue(experiment.memory_limit_mb) << " MB per run\n";
  out << experiment.run_count << " runs per planner\n";
  out << formatValue(experiment.total_time_s) << " seconds spent to collect the data\n";
  out << "0 enum types\n";
  out << experiment.planners.size() << " planners\n";
  for (const BenchmarkPlannerRuns& planner : experiment.planners) {
    out << withoutSpaces(planner.planner) << '\n';
    out << "0 common properties\n";
    out << planner.properties.size() << " properties for each run\n";
    for (const std::string& property : planner.properties) out << property << '\n';
    out << planner.runs.size() << " runs\n";
    for (const std::vector<double>& run : planner.runs) {
      for (double value : run) out << formatValue(value) << "; ";
      out << '\n';
    }
    out << ".\n";
  }
  return out.str();
}

void writeOmplBenchmarkLog(const std::filesystem::path& path, const BenchmarkExperiment& experiment) {
  writeFileAtomically(path, formatOmplBenchmarkLog(experiment));
}

}  // namespace terramesh::planning

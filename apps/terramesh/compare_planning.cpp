#include "compare_planning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "evaluation/path_trials.h"
#include "evaluation/truth_checker.h"
#include "planning/path_planner.h"
#include "planning/surface_planner.h"

namespace terramesh::cli {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

std::string PlanningOutcome::summary() const {
  std::ostringstream out;
  out.precision(4);
  out << solved << "/" << pairs << " solved";
  if (no_start_or_goal > 0) out << "; " << no_start_or_goal << " with no walkable face within the snap radius of an end";
  if (unreachable > 0) out << "; " << unreachable << " with start and goal on different walkable components";
  const std::size_t other = pairs - solved - no_start_or_goal - unreachable;
  if (other > 0) out << "; " << other << " not found";
  if (truth_checked > 0) out << "; " << truth_valid << "/" << truth_checked << " valid on the truth";
  out << " (walkable: " << walkable_faces << " faces, " << walkable_area_m2 << " m^2 in " << walkable_components
      << " components, the largest " << largest_component_m2 << " m^2)";
  return out.str();
}

PlanningOutcome planComparePairs(const traversability::LayeredMesh& map,
                                 const std::vector<evaluation::ComparePair>& pairs,
                                 const planning::WalkabilityConfig& walkability, double snap_radius_m,
                                 const PathTruth& truth) {
  PlanningOutcome outcome;
  outcome.pairs = pairs.size();
  outcome.mean_length_m = outcome.mean_cost = outcome.mean_length_ratio = kNaN;
  if (map.mesh.faces.empty()) {
    outcome.no_start_or_goal = pairs.size();
    outcome.statuses.assign(pairs.size(), "no_start");
    outcome.truth_reasons.assign(pairs.size(), "");
    return outcome;
  }
  const planning::FaceGraph graph(map, walkability);
  const double area_scale = graph.metresPerUnit() * graph.metresPerUnit();
  outcome.walkable_faces = graph.walkableFaceCount();
  outcome.walkable_components = graph.componentCount();
  for (std::uint32_t c = 0; c < graph.componentCount(); ++c) {
    outcome.walkable_area_m2 += graph.componentArea(c) * area_scale;
    outcome.largest_component_m2 = std::max(outcome.largest_component_m2, graph.componentArea(c) * area_scale);
  }
  planning::PlannerConfig config;
  config.planner = "rrtstar";  // not used by the graph baseline; validated all the same
  config.snap_radius_m = snap_radius_m;
  const planning::SurfacePlanner graph_astar(graph, config, true);
  std::optional<evaluation::TruthChecker> checker;
  if (truth.mesh && truth.bvh) checker.emplace(*truth.mesh, *truth.bvh);
  evaluation::PathTruth path_truth;
  path_truth.checker = checker ? &*checker : nullptr;
  path_truth.config = truth.config;
  path_truth.up_W = truth.up_W;
  path_truth.metres_per_unit = graph.metresPerUnit();
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> ends;
  for (const evaluation::ComparePair& pair : pairs) ends.emplace_back(pair.start_W, pair.goal_W);
  const evaluation::PlannerTrials tally = evaluation::runPathTrials({&graph_astar}, ends, path_truth).front();
  outcome.solved = tally.solved;
  outcome.no_start_or_goal = tally.no_start_or_goal;
  outcome.unreachable = tally.unreachable;
  outcome.truth_checked = tally.truth_checked;
  outcome.truth_valid = tally.truth_valid;
  double ratio = 0;
  std::size_t ratios = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const evaluation::PathTrial& trial = tally.trials[i];
    outcome.statuses.push_back(planning::toString(trial.result.status));
    outcome.truth_reasons.push_back(trial.check.reason);
    const double truth_length_m = pairs[i].truth_length_m;
    if (trial.result.solved() && std::isfinite(truth_length_m) && truth_length_m > 0) {
      ratio += trial.result.length_m / truth_length_m;
      ++ratios;
    }
  }
  const double length = tally.length_m, cost = tally.cost;
  if (outcome.solved > 0) {
    outcome.mean_length_m = length / static_cast<double>(outcome.solved);
    outcome.mean_cost = cost / static_cast<double>(outcome.solved);
  }
  if (ratios > 0) outcome.mean_length_ratio = ratio / static_cast<double>(ratios);
  return outcome;
}

}  // namespace terramesh::cli

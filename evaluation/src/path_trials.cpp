#include "evaluation/path_trials.h"

#include <stdexcept>
#include <utility>

#include "common/plan_frame.h"

namespace terramesh::evaluation {

std::vector<PlannerTrials> runPathTrials(const std::vector<const planning::PathPlanner*>& planners,
                                         const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& pairs,
                                         const PathTruth& truth) {
  for (const planning::PathPlanner* planner : planners) {
    if (planner == nullptr) throw std::invalid_argument("runPathTrials: a planner is null");
  }
  // Checked again by every check; here so that a bad config fails before any planning time is spent.
  if (truth.checker != nullptr) truth.config.validate();
  std::vector<PlannerTrials> out(planners.size());
  const Eigen::Vector3d up = truth.up_W.normalized();
  for (const auto& [start, goal] : pairs) {
    for (std::size_t p = 0; p < planners.size(); ++p) {
      PlannerTrials& tally = out[p];
      PathTrial trial;
      trial.result = planners[p]->plan(start, goal);
      const planning::PlanResult& r = trial.result;
      tally.time_s += r.planning_time_s;
      switch (r.status) {
        case planning::PlanStatus::kSolved:
          ++tally.solved;
          tally.length_m += r.length_m;
          tally.cost += r.cost;
          if (truth.checker != nullptr) {
            trial.checked = true;
            std::vector<Eigen::Vector3d> body;  // the body's heading at each point, if it keeps its own
            for (const planning::PathState& state : r.states) {
              if (truth.config.own_heading) body.push_back(geometry::headingDirection(state.yaw_rad, up));
            }
            trial.check = truth.checker->check(r.points(), truth.up_W, truth.metres_per_unit, truth.config, body);
            ++tally.truth_checked;
            tally.truth_valid += trial.check.valid ? 1 : 0;
          }
          break;
        case planning::PlanStatus::kNoStart:
        case planning::PlanStatus::kNoGoal: ++tally.no_start_or_goal; break;
        case planning::PlanStatus::kUnreachable: ++tally.unreachable; break;
        case planning::PlanStatus::kNotFound: break;
      }
      tally.trials.push_back(std::move(trial));
    }
  }
  return out;
}

}  // namespace terramesh::evaluation

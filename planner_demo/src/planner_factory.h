#pragma once

#include <chrono>
#include <ompl/base/Planner.h>
#include <ompl/geometric/SimpleSetup.h>
#include <string>

namespace terramesh::planning::internal {

/// A new planner of that name over `si`. `range_m` (> 0) is the steering range of the RRT
/// family (state-space units); other planners ignore it.
/// @throw std::invalid_argument for an unknown name.
ompl::base::PlannerPtr makePlanner(const std::string& name, const ompl::base::SpaceInformationPtr& si, double range_m);

/// What `solveWithinCap` ended with: OMPL's status, or the message of the ompl::Exception a planner
/// threw (LazyPRM* throws when its roadmap holds no valid path at the deadline: an expected outcome).
struct SolveOutcome {
  ompl::base::PlannerStatus status{ompl::base::PlannerStatus::UNKNOWN};
  std::string planner_error;  ///< empty unless the planner threw
};

/// Sets `setup` up and calls `setup.solve(budget_s)` and, while no exact path is found and `cap_s` > 0, resumes for
/// another budget until `cap_s` seconds have passed since `started` (every planner made by
/// makePlanner keeps its tree or roadmap between solve() calls; SimpleSetup does not clear it).
SolveOutcome solveWithinCap(ompl::geometric::SimpleSetup& setup, double budget_s, double cap_s,
                            std::chrono::steady_clock::time_point started);

/// Clears a planner's data when it goes out of scope. OMPL 1.5.2's LazyPRM frees its roadmap's
/// states only in clear(), not in its destructor (`LazyPRM::~LazyPRM() = default`), so a
/// SimpleSetup destroyed without clear() leaks every state LazyPRM* sampled. Declare it after the
/// SimpleSetup so it runs first; the solution path holds its own copies of its states.
class PlannerClearer {
 public:
  explicit PlannerClearer(ompl::geometric::SimpleSetup& setup) : setup_(setup) {}
  PlannerClearer(const PlannerClearer&) = delete;
  PlannerClearer& operator=(const PlannerClearer&) = delete;
  ~PlannerClearer() {
    if (const ompl::base::PlannerPtr& planner = setup_.getPlanner()) planner->clear();
  }

 private:
  ompl::geometric::SimpleSetup& setup_;
};

}  // namespace terramesh::planning::internal

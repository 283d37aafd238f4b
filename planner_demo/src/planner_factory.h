#pragma once

#include <ompl/base/Planner.h>
#include <optional>
#include <string>

namespace terramesh::planning::internal {

/// The canonical name ("rrtstar", "informed-rrtstar", "prmstar", "lazyprmstar", "bitstar",
/// "aitstar") of a planner name as users write it ("RRT*", "informed_rrt_star", "BIT*", ...), or
/// nothing if it names none of them.
std::optional<std::string> canonicalPlannerName(const std::string& name);

/// A new planner of that name over `si`. `range_m` (> 0) is the steering range of the RRT
/// family (state-space units); other planners ignore it.
/// @throw std::invalid_argument for an unknown name.
ompl::base::PlannerPtr makePlanner(const std::string& name, const ompl::base::SpaceInformationPtr& si, double range_m);

}  // namespace terramesh::planning::internal

#include "planner_factory.h"

#include <algorithm>
#include <cctype>
#include <ompl/geometric/planners/informedtrees/AITstar.h>
#include <ompl/util/Exception.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/prm/LazyPRMstar.h>
#include <ompl/geometric/planners/prm/PRMstar.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <stdexcept>

#include "planning/surface_planner.h"

namespace terramesh::planning {

std::vector<std::string> plannerNames() {
  return {"rrtstar", "informed-rrtstar", "prmstar", "lazyprmstar", "bitstar", "aitstar"};
}

std::optional<std::string> canonicalPlannerName(const std::string& name) {
  std::string key;
  for (char c : name) {
    if (c == '*') key += "star";
    else if (std::isalnum(static_cast<unsigned char>(c))) key += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  if (key == "informedrrtstar") return "informed-rrtstar";
  for (const std::string& known : plannerNames()) {
    if (key == known) return known;
  }
  return std::nullopt;
}

namespace internal {

ompl::base::PlannerPtr makePlanner(const std::string& name, const ompl::base::SpaceInformationPtr& si, double range_m) {
  const std::optional<std::string> canonical = canonicalPlannerName(name);
  if (!canonical) throw std::invalid_argument("unknown planner \"" + name + "\"");
  if (*canonical == "rrtstar") {
    auto planner = std::make_shared<ompl::geometric::RRTstar>(si);
    planner->setRange(range_m);
    return planner;
  }
  if (*canonical == "informed-rrtstar") {
    auto planner = std::make_shared<ompl::geometric::InformedRRTstar>(si);
    planner->setRange(range_m);
    return planner;
  }
  if (*canonical == "prmstar") return std::make_shared<ompl::geometric::PRMstar>(si);
  if (*canonical == "lazyprmstar") return std::make_shared<ompl::geometric::LazyPRMstar>(si);
  if (*canonical == "bitstar") return std::make_shared<ompl::geometric::BITstar>(si);
  return std::make_shared<ompl::geometric::AITstar>(si);
}

SolveOutcome solveWithinCap(ompl::geometric::SimpleSetup& setup, double budget_s, double cap_s,
                            std::chrono::steady_clock::time_point started) {
  SolveOutcome outcome;
  try {
    setup.setup();
    outcome.status = setup.solve(budget_s);
    while (!setup.haveExactSolutionPath() && cap_s > 0) {
      const double left = cap_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      if (left <= 0) break;
      outcome.status = setup.solve(std::min(budget_s, left));
    }
  } catch (const ompl::Exception& error) {
    outcome.planner_error = error.what();
  }
  return outcome;
}

}  // namespace internal
}  // namespace terramesh::planning

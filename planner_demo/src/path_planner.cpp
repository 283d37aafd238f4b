#include "planning/path_planner.h"

namespace terramesh::planning {

SurfacePlanner::SurfacePlanner(const FaceGraph& graph, const PlannerConfig& config, bool graph_astar)
    : graph_(graph), config_(config), graph_astar_(graph_astar) {
  config_.validate();
}

PlanResult SurfacePlanner::plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W) const {
  return graph_astar_ ? planOnFaceGraph(graph_, start_W, goal_W, config_) : planOnSurface(graph_, start_W, goal_W, config_);
}

}  // namespace terramesh::planning

#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "planning/face_graph.h"
#include "planning/surface_planner.h"

namespace terramesh::planning {

/// One interface for every planner a comparison runs: a query from a start to a goal (map frame,
/// map units) answered with a PlanResult, whatever the map. The surface planners here
/// (OMPL on the walkable surface, A* on the face graph) and the OctoMap baseline's grid planner
/// (terramesh::baselines::GridPlanner) implement it.
class PathPlanner {
 public:
  virtual ~PathPlanner() = default;
  /// Plans; expected failures are statuses of the result, not exceptions.
  /// @throw std::invalid_argument if a point is not finite.
  virtual PlanResult plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W) const = 0;
};

/// planOnSurface (`graph_astar` false) or planOnFaceGraph (true) over `graph` with `config`. Keeps
/// references: `graph` and `config` must outlive it.
class SurfacePlanner final : public PathPlanner {
 public:
  /// @throw std::invalid_argument if the config does not validate.
  SurfacePlanner(const FaceGraph& graph, const PlannerConfig& config, bool graph_astar);
  PlanResult plan(const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W) const override;

 private:
  const FaceGraph& graph_;
  const PlannerConfig& config_;
  bool graph_astar_;
};

}  // namespace terramesh::planning

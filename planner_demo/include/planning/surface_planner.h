#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "planning/face_graph.h"

namespace terramesh::planning {

/// How planOnSurface (and planOnGrid) plan.
struct PlannerConfig {
  /// One of plannerNames(); "RRT*", "BIT*" etc. are accepted too.
  std::string planner = "rrtstar";
  /// Wall-clock budget of the planner (the optimizing planners use all of it).
  double time_budget_s = 1.0;
  /// When > time_budget_s: a planner without an exact path after time_budget_s keeps searching
  /// (it resumes its tree or roadmap, in rounds of time_budget_s) until it has one or this much
  /// wall-clock time has passed in all. Whether a path is found then depends on the machine's
  /// speed and load only through how long it takes (tests use it; planOnSurface and planOnGrid).
  /// 0 or <= time_budget_s: no extension.
  double time_cap_s = 0.0;
  /// Seed of the surface samplers (their ompl::RNG local seeds). The planners' own generators
  /// draw from OMPL's process-wide seed: call seedOmpl once at start-up for reproducible runs.
  std::uint32_t seed = 1;
  /// Shortcut and smooth the solution (OMPL's PathSimplifier), keeping it valid.
  bool simplify = true;
  /// Start and goal are moved to the nearest walkable surface point within this distance.
  double snap_radius_m = 0.5;
  /// Steering range of RRT* and informed RRT*.
  double range_m = 5.0;
  /// Weight of the heading in the state-space distance, metres per radian.
  double yaw_weight_m_per_rad = 0.1;
  /// The state-space distance (nearest neighbours, steering range) scales the component along
  /// "up" by this: floors 3 m apart are then 3 * w apart, so trees do not try to connect a state
  /// to the one on the floor below (which can never succeed) instead of growing along its floor.
  double vertical_distance_weight = 10.0;
  /// A surface walk between two states fails when longer than this times their distance.
  double max_detour = 3.0;
  /// @throw std::invalid_argument listing every bad field (unknown planner, non-positive budget...).
  void validate() const;
};

/// The planners by canonical name: rrtstar, informed-rrtstar, prmstar, lazyprmstar, bitstar,
/// aitstar (all in OMPL 1.5.2).
std::vector<std::string> plannerNames();

/// The canonical name (one of plannerNames()) of a planner name as users write it ("RRT*",
/// "informed_rrt_star", "BIT*", ...), or nothing if it names none of them.
std::optional<std::string> canonicalPlannerName(const std::string& name);

/// What a planning query came to. Expected outcomes, not errors.
enum class PlanStatus {
  kSolved,       ///< an exact path was found
  kNoStart,      ///< no known walkable face within the snap radius of the start
  kNoGoal,       ///< ... of the goal
  kUnreachable,  ///< start and goal are on different walkable components: no path exists
  kNotFound,     ///< reachable, but the planner found no path within its budget
};

/// "solved", "no_start", "no_goal", "unreachable", "not_found".
const char* toString(PlanStatus status);

/// One state of an output path: on the surface, with the heading of travel (radians about up,
/// see docs/planning.md) and the cost the planner used for its face (FaceGraph::plannedCost:
/// the traversability cost, or unknown_cost on an unknown face).
struct PathState {
  SurfaceLocation location;
  double yaw_rad = 0;
  double face_cost = 0;
};

/// The result of one query. Lengths and costs in metres (cost: see SurfaceWalk::cost).
struct PlanResult {
  PlanStatus status = PlanStatus::kNotFound;
  /// One line saying why, when not solved.
  std::string reason;
  std::string planner;
  SurfaceLocation start, goal;
  /// The path as a dense polyline on the surface: the planner's states and every edge crossing
  /// between them.
  std::vector<PathState> states;
  /// The planner's own states (after simplification, when `simplified`).
  std::vector<PathState> waypoints;
  /// Whether the path is the simplified one. False when simplification is off, or when a piece of
  /// its result did not walk the surface; then the path is the planner's, every piece validated.
  bool simplified = false;
  double length_m = 0;
  double cost = 0;
  /// The part of length_m over unknown faces (only with WalkabilityConfig::allow_unknown).
  double unknown_length_m = 0;
  double planning_time_s = 0;
  double simplify_time_s = 0;
  /// Cost of the first solution found (NaN if none) and the time it took.
  double first_cost = 0;
  double first_time_s = 0;
  bool solved() const { return status == PlanStatus::kSolved; }
  /// The points of `states`, in order.
  std::vector<Eigen::Vector3d> points() const;
};

/// Plans from `start_W` to `goal_W` (map frame, map units) over the walkable surface of `graph`
/// with the configured OMPL planner: a state space of surface points plus heading, sampled only
/// on walkable faces (area-weighted), motions validated by walking the surface, cost = surface
/// length weighted by traversability cost. Reports kUnreachable without planning when the face
/// graph shows no connection. Thread-safe for distinct calls (each builds its own OMPL setup).
/// @throw std::invalid_argument if the config does not validate or a point is not finite.
PlanResult planOnSurface(const FaceGraph& graph, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                         const PlannerConfig& config);

/// The same query answered by the face-graph baseline (A*), as a PlanResult with the same
/// fields (planner "graph-astar").
/// @throw std::invalid_argument if the config does not validate or a point is not finite.
PlanResult planOnFaceGraph(const FaceGraph& graph, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                           const PlannerConfig& config);

/// `count` start/goal pairs drawn area-weighted from the largest walkable component, each pair at
/// least `min_distance_m` apart (straight line), deterministic for a seed. Fewer if the component
/// is too small to find such pairs in 100 * count tries; none if nothing is walkable.
std::vector<std::pair<SurfaceLocation, SurfaceLocation>> drawRandomPairs(const FaceGraph& graph, std::size_t count,
                                                                         std::uint64_t seed, double min_distance_m);

/// Sets OMPL's process-wide seed (ompl::RNG::setSeed). Call once, before any planning: OMPL
/// ignores it (with an error message) once a generator exists.
void seedOmpl(std::uint32_t seed);

/// Turns OMPL's console messages off (false) or back to warnings and errors (true). OMPL's
/// logging is process-wide; the library itself never calls this.
void setOmplLogging(bool enabled);

}  // namespace terramesh::planning

#include "planning/surface_planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <ompl/base/ScopedState.h>
#include <ompl/base/goals/GoalState.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include "geometry.h"
#include "planner_factory.h"
#include "surface_ompl.h"

namespace terramesh::planning {
namespace {

/// The same walk travelled the other way. A walk's point i carries the face that its piece i (to
/// point i + 1) lies on; going back, piece k runs over the face the forward walk labelled on the
/// point after it. The end keeps the face of the forward walk's start.
SurfaceWalk reversed(SurfaceWalk walk) {
  std::reverse(walk.points.begin(), walk.points.end());
  for (std::size_t k = 0; k + 1 < walk.points.size(); ++k) walk.points[k].face = walk.points[k + 1].face;
  return walk;
}

using Clock = std::chrono::steady_clock;
using internal::SurfaceStateSpace;

std::string describePoint(const Eigen::Vector3d& p) {
  std::ostringstream out;
  out << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
  return out.str();
}

/// Snaps both ends and checks the face graph; a result if the query is decided already.
std::optional<PlanResult> prepare(const FaceGraph& graph, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                                  const PlannerConfig& config, PlanResult& result) {
  config.validate();
  if (!start_W.allFinite() || !goal_W.allFinite()) throw std::invalid_argument("plan: start or goal is not finite");
  const auto start = graph.snap(start_W, config.snap_radius_m);
  const auto goal = graph.snap(goal_W, config.snap_radius_m);
  std::ostringstream radius;
  radius << config.snap_radius_m;
  if (!start) {
    result.status = PlanStatus::kNoStart;
    result.reason = "no known walkable face within " + radius.str() + " m of the start " + describePoint(start_W);
    return result;
  }
  result.start = *start;
  if (!goal) {
    result.status = PlanStatus::kNoGoal;
    result.reason = "no known walkable face within " + radius.str() + " m of the goal " + describePoint(goal_W);
    return result;
  }
  result.goal = *goal;
  if (graph.component(start->face) != graph.component(goal->face)) {
    result.status = PlanStatus::kUnreachable;
    result.reason = "start and goal lie on different walkable components: no drivable connection over the surface";
    return result;
  }
  return std::nullopt;
}

PathState pathState(const FaceGraph& graph, const SurfaceLocation& location, double yaw) {
  return PathState{location, yaw, graph.plannedCost(location.face)};
}

/// Dense states through the given polyline points. Headings follow the direction of travel, or,
/// with one yaw per point (a body that keeps its own heading), are those yaws; then a point
/// repeated with another yaw (a turn on the spot) is kept.
void densify(const FaceGraph& graph, const std::vector<SurfaceLocation>& points, PlanResult& result,
             const std::vector<double>& body_yaws = {}) {
  const bool own_heading = !body_yaws.empty();
  result.states.clear();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double yaw = own_heading ? body_yaws[i] : 0.0;
    if (i > 0 && points[i].point_W == points[i - 1].point_W && !result.states.empty() &&
        (!own_heading || yaw == result.states.back().yaw_rad)) {
      result.states.back().location.face = points[i].face;
      continue;
    }
    result.states.push_back(pathState(graph, points[i], yaw));
  }
  for (std::size_t i = 0; i < result.states.size() && !own_heading; ++i) {
    const std::size_t a = i + 1 < result.states.size() ? i : (i > 0 ? i - 1 : i);
    const std::size_t b = std::min(a + 1, result.states.size() - 1);
    const Eigen::Vector3d direction = result.states[b].location.point_W - result.states[a].location.point_W;
    result.states[i].yaw_rad = direction.norm() > 0 ? headingAbout(direction, graph.up()) : 0.0;
  }
  // Piece i (states i to i + 1) lies on state i's face.
  result.unknown_length_m = 0;
  for (std::size_t i = 0; i + 1 < result.states.size(); ++i) {
    if (!graph.walkableUnknown(result.states[i].location.face)) continue;
    result.unknown_length_m +=
        (result.states[i + 1].location.point_W - result.states[i].location.point_W).norm() * graph.metresPerUnit();
  }
}

/// The heading of an OMPL start or goal state on `face`: along `straight`, or, for a body that
/// keeps its own heading and does not fit that one there, the judged heading nearest it that fits.
double endYaw(const FaceGraph& graph, std::uint32_t face, const Eigen::Vector3d& straight) {
  const double along = straight.norm() > 0 ? headingAbout(straight, graph.up()) : 0.0;
  const int n = graph.config().heading_count;
  if (!graph.keepsOwnHeading()) return along;
  if (graph.headingFits(face, geometry::headingDirection(along, graph.up()))) return along;
  double best = along, best_turn = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 2 * n; ++k) {  // both ends of each judged heading
    const Eigen::Vector3d heading = k < n ? graph.judgedHeading(k) : Eigen::Vector3d(-graph.judgedHeading(k - n));
    const double yaw = headingAbout(heading, graph.up());
    const double turn = std::abs(angleDifference(along, yaw));
    if (graph.judgedHeadingFits(face, k % n) && turn < best_turn) {
      best = yaw;
      best_turn = turn;
    }
  }
  return best;
}

/// The yaw at each point of a walk from a state at `yaw_from` to one at `yaw_to`: turned in
/// proportion to the length walked.
void appendWalkYaws(const SurfaceWalk& walk, double yaw_from, double yaw_to, std::vector<double>& yaws) {
  double total = 0;
  for (std::size_t i = 1; i < walk.points.size(); ++i) {
    total += (walk.points[i].point_W - walk.points[i - 1].point_W).norm();
  }
  double walked = 0;
  for (std::size_t i = 1; i < walk.points.size(); ++i) {
    walked += (walk.points[i].point_W - walk.points[i - 1].point_W).norm();
    const double t = i + 1 == walk.points.size() || total <= 0 ? 1.0 : walked / total;
    yaws.push_back(std::remainder(yaw_from + t * angleDifference(yaw_from, yaw_to), 2.0 * M_PI));
  }
}

/// Fills `result`'s waypoints, dense states, length and cost from the planner's `path`, walking
/// the surface between its states (either way round: PRM-family roadmaps are undirected). The
/// walk's stop reason when a piece does not walk either way, else empty.
std::string walkSolution(const FaceGraph& graph, const ompl::geometric::PathGeometric& path,
                         const PlannerConfig& config, PlanResult& result) {
  result.waypoints.clear();
  result.length_m = 0;
  result.cost = 0;
  std::vector<SurfaceLocation> dense;
  std::vector<double> body_yaws;  // a body that keeps its own heading: its yaw at each dense point
  const bool own_heading = graph.keepsOwnHeading();
  for (std::size_t i = 0; i < path.getStateCount(); ++i) {
    const auto* state = path.getState(i)->as<SurfaceStateSpace::StateType>();
    result.waypoints.push_back(pathState(graph, state->location(), state->yaw));
    if (i == 0) {
      dense.push_back(state->location());
      if (own_heading) body_yaws.push_back(state->yaw);
      continue;
    }
    const auto* previous = path.getState(i - 1)->as<SurfaceStateSpace::StateType>();
    SurfaceWalk walk = graph.walk(previous->location(), state->location(), true, config.max_detour,
                                  internal::bodyTurn(graph, previous->yaw, state->yaw));
    if (!walk.reached()) {
      // The surface walk is not symmetric: OMPL may have validated this edge from its other end.
      walk = reversed(graph.walk(state->location(), previous->location(), true, config.max_detour,
                                 internal::bodyTurn(graph, state->yaw, previous->yaw)));
    }
    if (!walk.reached()) return toString(walk.stop);
    dense.insert(dense.end(), walk.points.begin() + 1, walk.points.end());
    if (own_heading) appendWalkYaws(walk, previous->yaw, state->yaw, body_yaws);
    result.length_m += walk.length_m;
    result.cost += walk.cost;
  }
  densify(graph, dense, result, body_yaws);
  return {};
}

}  // namespace

void PlannerConfig::validate() const {
  std::ostringstream problems;
  if (!canonicalPlannerName(planner)) {
    problems << " planner: \"" << planner << "\" (expected one of";
    for (const std::string& name : plannerNames()) problems << ' ' << name;
    problems << ");";
  }
  if (!(time_budget_s > 0) || !std::isfinite(time_budget_s)) problems << " time_budget_s: " << time_budget_s << " (expected > 0);";
  if (!(time_cap_s >= 0) || !std::isfinite(time_cap_s)) problems << " time_cap_s: " << time_cap_s << " (expected >= 0);";
  if (seed == 0) problems << " seed: 0 (expected > 0, OMPL's seeds are positive);";
  if (!(snap_radius_m >= 0) || !std::isfinite(snap_radius_m)) problems << " snap_radius_m: " << snap_radius_m << " (expected >= 0);";
  if (!(range_m > 0) || !std::isfinite(range_m)) problems << " range_m: " << range_m << " (expected > 0);";
  if (!(yaw_weight_m_per_rad >= 0) || !std::isfinite(yaw_weight_m_per_rad)) {
    problems << " yaw_weight_m_per_rad: " << yaw_weight_m_per_rad << " (expected >= 0);";
  }
  if (!(vertical_distance_weight >= 1) || !std::isfinite(vertical_distance_weight)) {
    problems << " vertical_distance_weight: " << vertical_distance_weight << " (expected >= 1);";
  }
  if (!(max_detour >= 1) || !std::isfinite(max_detour)) problems << " max_detour: " << max_detour << " (expected >= 1);";
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("PlannerConfig:" + text);
}

const char* toString(PlanStatus status) {
  switch (status) {
    case PlanStatus::kSolved: return "solved";
    case PlanStatus::kNoStart: return "no_start";
    case PlanStatus::kNoGoal: return "no_goal";
    case PlanStatus::kUnreachable: return "unreachable";
    case PlanStatus::kNotFound: return "not_found";
  }
  return "?";
}

PlanResult planOnSurface(const FaceGraph& graph, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                         const PlannerConfig& config) {
  PlanResult result;
  result.planner = canonicalPlannerName(config.planner).value_or(config.planner);
  if (auto decided = prepare(graph, start_W, goal_W, config, result)) return *decided;

  auto space = std::make_shared<SurfaceStateSpace>(graph, config.yaw_weight_m_per_rad, config.vertical_distance_weight,
                                                   config.max_detour, config.seed);
  ompl::geometric::SimpleSetup setup(space);
  const ompl::base::SpaceInformationPtr si = setup.getSpaceInformation();
  setup.setStateValidityChecker(std::make_shared<internal::SurfaceValidityChecker>(si, graph));
  si->setMotionValidator(std::make_shared<internal::SurfaceMotionValidator>(si, *space));
  auto objective = std::make_shared<internal::SurfaceCostObjective>(si, *space);
  const Eigen::Vector3d goal_point = result.goal.point_W;
  const double mpu = graph.metresPerUnit();
  objective->setCostToGoHeuristic([goal_point, mpu](const ompl::base::State* state, const ompl::base::Goal*) {
    return ompl::base::Cost((state->as<SurfaceStateSpace::StateType>()->point_W - goal_point).norm() * mpu);
  });
  setup.setOptimizationObjective(objective);
  ompl::base::ScopedState<> start(space), goal(space);
  auto* s = start->as<SurfaceStateSpace::StateType>();
  auto* g = goal->as<SurfaceStateSpace::StateType>();
  s->face = result.start.face;
  s->point_W = result.start.point_W;
  g->face = result.goal.face;
  g->point_W = result.goal.point_W;
  const Eigen::Vector3d straight = result.goal.point_W - result.start.point_W;
  s->yaw = endYaw(graph, s->face, straight);
  g->yaw = endYaw(graph, g->face, straight);
  setup.setStartAndGoalStates(start, goal, 1e-9);
  setup.setPlanner(internal::makePlanner(config.planner, si, config.range_m));

  result.first_cost = std::numeric_limits<double>::quiet_NaN();
  result.first_time_s = std::numeric_limits<double>::quiet_NaN();
  const auto started = Clock::now();
  setup.getProblemDefinition()->setIntermediateSolutionCallback(
      [&result, started](const ompl::base::Planner*, const std::vector<const ompl::base::State*>&, const ompl::base::Cost cost) {
        if (!std::isnan(result.first_cost)) return;
        result.first_cost = cost.value();
        result.first_time_s = std::chrono::duration<double>(Clock::now() - started).count();
      });
  const internal::PlannerClearer clearer(setup);
  const auto [status, planner_error] = internal::solveWithinCap(setup, config.time_budget_s, config.time_cap_s, started);
  result.planning_time_s = std::chrono::duration<double>(Clock::now() - started).count();
  if (status != ompl::base::PlannerStatus::EXACT_SOLUTION || !setup.haveExactSolutionPath()) {
    result.status = PlanStatus::kNotFound;
    result.reason = "the planner found no path within " + std::to_string(result.planning_time_s) + " s (" +
                    (planner_error.empty() ? status.asString() : planner_error) + ")";
    return result;
  }
  if (std::isnan(result.first_cost)) {
    result.first_cost = setup.getSolutionPath().cost(objective).value();
    result.first_time_s = result.planning_time_s;
  }
  const ompl::geometric::PathGeometric planned = setup.getSolutionPath();
  if (config.simplify) {
    const auto simplify_started = Clock::now();
    setup.simplifySolution(std::max(0.05, 0.25 * config.time_budget_s));
    result.simplified = true;
    result.simplify_time_s = std::chrono::duration<double>(Clock::now() - simplify_started).count();
  }
  const ompl::geometric::PathGeometric& path = setup.getSolutionPath();
  std::string stop = walkSolution(graph, path, config, result);
  if (!stop.empty() && config.simplify) {
    // OMPL's shortcuts keep the parts of a validated piece unchecked, as parts of a straight
    // motion would be; a surface walk from a point part-way along a piece need not follow it. The
    // path as planned had every piece validated: keep it.
    stop = walkSolution(graph, planned, config, result);
    result.simplified = false;
  }
  if (!stop.empty()) {
    // Cannot happen for a path OMPL validated with the same walk; refuse rather than report it.
    result.status = PlanStatus::kNotFound;
    result.reason = "internal: a solution segment does not walk (" + stop + ")";
    return result;
  }
  result.status = PlanStatus::kSolved;
  return result;
}

std::vector<Eigen::Vector3d> PlanResult::points() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(states.size());
  for (const PathState& state : states) out.push_back(state.location.point_W);
  return out;
}

PlanResult planOnFaceGraph(const FaceGraph& graph, const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W,
                           const PlannerConfig& config) {
  PlanResult result;
  result.planner = "graph-astar";
  if (auto decided = prepare(graph, start_W, goal_W, config, result)) return *decided;
  const auto started = Clock::now();
  const GraphPath path = graph.shortestPath(result.start, result.goal);
  result.planning_time_s = std::chrono::duration<double>(Clock::now() - started).count();
  if (!path.found) {
    result.status = PlanStatus::kUnreachable;
    result.reason = "no path over the face graph";
    return result;
  }
  std::vector<SurfaceLocation> dense;
  std::vector<double> body_yaws;
  for (std::size_t i = 0; i < path.points_W.size(); ++i) {
    dense.push_back(SurfaceLocation{i < path.faces.size() ? path.faces[i] : result.goal.face, path.points_W[i]});
    if (!path.body_headings_W.empty()) body_yaws.push_back(headingAbout(path.body_headings_W[i], graph.up()));
  }
  densify(graph, dense, result, body_yaws);
  result.waypoints = result.states;
  result.length_m = path.length_m;
  result.cost = path.cost;
  result.first_cost = path.cost;
  result.first_time_s = result.planning_time_s;
  result.status = PlanStatus::kSolved;
  return result;
}

std::vector<std::pair<SurfaceLocation, SurfaceLocation>> drawRandomPairs(const FaceGraph& graph, std::size_t count,
                                                                         std::uint64_t seed, double min_distance_m) {
  std::vector<std::pair<SurfaceLocation, SurfaceLocation>> pairs;
  if (graph.componentCount() == 0) return pairs;
  std::uint32_t largest = 0;
  for (std::uint32_t c = 1; c < graph.componentCount(); ++c) {
    if (graph.componentArea(c) > graph.componentArea(largest)) largest = c;
  }
  std::vector<std::uint32_t> faces;
  std::vector<double> cumulative;
  double total = 0;
  for (std::uint32_t f : graph.walkableFaces()) {
    if (graph.component(f) != largest) continue;
    total += graph.area(f);
    faces.push_back(f);
    cumulative.push_back(total);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto sample = [&]() {
    const double pick = unit(rng) * total;
    const std::size_t i = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin()),
        faces.size() - 1);
    const auto& t = graph.face(faces[i]);
    const double r1 = std::sqrt(unit(rng)), r2 = unit(rng);
    return SurfaceLocation{faces[i], (1 - r1) * graph.vertex(t[0]) + r1 * (1 - r2) * graph.vertex(t[1]) +
                                         r1 * r2 * graph.vertex(t[2])};
  };
  const double min_units = min_distance_m / graph.metresPerUnit();
  for (std::size_t tries = 0; pairs.size() < count && tries < 100 * count; ++tries) {
    const SurfaceLocation a = sample(), b = sample();
    if ((a.point_W - b.point_W).norm() >= min_units) pairs.emplace_back(a, b);
  }
  return pairs;
}

void seedOmpl(std::uint32_t seed) { ompl::RNG::setSeed(seed); }

void setOmplLogging(bool enabled) {
  ompl::msg::setLogLevel(enabled ? ompl::msg::LOG_WARN : ompl::msg::LOG_NONE);
}

}  // namespace terramesh::planning

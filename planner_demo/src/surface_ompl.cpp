#include "surface_ompl.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "common/plan_frame.h"
#include "geometry.h"

namespace terramesh::planning::internal {
namespace {

using State = SurfaceStateSpace::StateType;

const State& st(const ompl::base::State* state) { return *state->as<State>(); }
State& st(ompl::base::State* state) { return *state->as<State>(); }

/// The point at fraction t of a walk's polyline length.
SurfaceLocation pointAlong(const SurfaceWalk& walk, double t) {
  const auto& points = walk.points;
  double total = 0;
  for (std::size_t i = 1; i < points.size(); ++i) total += (points[i].point_W - points[i - 1].point_W).norm();
  if (points.size() < 2 || total <= 0) return points.front();
  double remaining = std::clamp(t, 0.0, 1.0) * total;
  for (std::size_t i = 1; i < points.size(); ++i) {
    const double piece = (points[i].point_W - points[i - 1].point_W).norm();
    if (remaining <= piece || i + 1 == points.size()) {
      if (remaining >= piece) return points[i];
      const double s = piece > 0 ? remaining / piece : 0.0;
      return SurfaceLocation{points[i - 1].face, points[i - 1].point_W + s * (points[i].point_W - points[i - 1].point_W)};
    }
    remaining -= piece;
  }
  return points.back();
}

/// Two unit vectors spanning the plane orthogonal to n.
std::pair<Eigen::Vector3d, Eigen::Vector3d> tangentBasis(const Eigen::Vector3d& n) {
  const geometry::PlanFrame frame = geometry::planFrame(n, geometry::acrossFrameRule());
  return {frame.e1, frame.e2};
}

}  // namespace

std::optional<BodyTurn> bodyTurn(const FaceGraph& graph, double yaw_from, double yaw_to) {
  if (!graph.keepsOwnHeading()) return std::nullopt;
  return BodyTurn{geometry::headingDirection(yaw_from, graph.up()), angleDifference(yaw_from, yaw_to)};
}

SurfaceStateSpace::SurfaceStateSpace(const FaceGraph& graph, double yaw_weight_m_per_rad, double vertical_weight,
                                     double max_detour, std::uint32_t seed)
    : graph_(graph), yaw_weight_(yaw_weight_m_per_rad), vertical_weight_(vertical_weight), max_detour_(max_detour),
      seed_(seed) {
  setName("Surface" + getName());
  type_ = ompl::base::STATE_SPACE_UNKNOWN;
  Eigen::AlignedBox3d box;
  double area = 0;
  for (std::uint32_t f : graph_.walkableFaces()) {
    for (std::uint32_t v : graph_.face(f)) box.extend(graph_.vertex(v));
    area += graph_.area(f);
  }
  const double mpu = graph_.metresPerUnit();
  extent_ = (box.isEmpty() ? 1.0 : std::max(box.diagonal().norm() * mpu * std::max(1.0, vertical_weight_), 1e-3)) +
            yaw_weight_ * M_PI;
  measure_ = std::max(area * mpu * mpu, 1e-6) * 2.0 * M_PI;
}

void SurfaceStateSpace::enforceBounds(ompl::base::State* state) const {
  st(state).yaw = std::remainder(st(state).yaw, 2.0 * M_PI);
}

bool SurfaceStateSpace::satisfiesBounds(const ompl::base::State* state) const {
  return st(state).face < graph_.faceCount() && std::abs(st(state).yaw) <= M_PI + 1e-9;
}

void SurfaceStateSpace::copyState(ompl::base::State* destination, const ompl::base::State* source) const {
  st(destination).assign(st(source));
}

double SurfaceStateSpace::distance(const ompl::base::State* a, const ompl::base::State* b) const {
  const Eigen::Vector3d d = st(a).point_W - st(b).point_W;
  const double vertical = d.dot(graph_.up());
  const double horizontal2 = std::max(0.0, d.squaredNorm() - vertical * vertical);
  return std::sqrt(horizontal2 + vertical_weight_ * vertical_weight_ * vertical * vertical) * graph_.metresPerUnit() +
         yaw_weight_ * std::abs(angleDifference(st(a).yaw, st(b).yaw));
}

bool SurfaceStateSpace::equalStates(const ompl::base::State* a, const ompl::base::State* b) const {
  return st(a).face == st(b).face && st(a).point_W == st(b).point_W && st(a).yaw == st(b).yaw;
}

void SurfaceStateSpace::interpolate(const ompl::base::State* from, const ompl::base::State* to, double t,
                                    ompl::base::State* state) const {
  const State& s0 = st(from);
  const State& s1 = st(to);
  const double yaw = s0.yaw + t * angleDifference(s0.yaw, s1.yaw);
  if (t <= 0) {
    st(state).assign(s0);
    return;
  }
  const SurfaceWalk walk = graph_.walk(s0.location(), s1.location(), false, max_detour_);
  if (walk.reached() && t >= 1) {
    st(state).assign(s1);
    return;
  }
  const SurfaceLocation location = pointAlong(walk, t);
  State& out = st(state);
  out.face = location.face;
  out.point_W = location.point_W;
  out.yaw = std::remainder(yaw, 2.0 * M_PI);
}

ompl::base::StateSamplerPtr SurfaceStateSpace::allocDefaultStateSampler() const {
  // Distinct, reproducible streams per sampler (0 is not a valid OMPL seed).
  const std::uint32_t index = samplers_.fetch_add(1);
  return std::make_shared<SurfaceStateSampler>(this, seed_ * 2654435761u + index * 40503u + 1u);
}

ompl::base::State* SurfaceStateSpace::allocState() const { return new State(); }

void SurfaceStateSpace::freeState(ompl::base::State* state) const { delete static_cast<State*>(state); }

SurfaceStateSampler::SurfaceStateSampler(const SurfaceStateSpace* space, std::uint32_t seed)
    : ompl::base::StateSampler(space), graph_(space->graph()) {
  rng_.setLocalSeed(seed == 0 ? 1 : seed);
  double total = 0;
  cumulative_area_.reserve(graph_.walkableFaceCount());
  for (std::uint32_t f : graph_.walkableFaces()) {
    total += graph_.area(f);
    cumulative_area_.push_back(total);
  }
}

double SurfaceStateSampler::sampleYaw(std::uint32_t f) {
  const int n = graph_.config().heading_count;
  if (!graph_.keepsOwnHeading() || rng_.uniform01() < 0.5) return rng_.uniformReal(-M_PI, M_PI);
  std::vector<int> fitting;
  for (int k = 0; k < n; ++k) {
    if (graph_.judgedHeadingFits(f, k)) fitting.push_back(k);
  }
  if (fitting.empty()) return rng_.uniformReal(-M_PI, M_PI);
  const int k = fitting[static_cast<std::size_t>(rng_.uniformInt(0, static_cast<int>(fitting.size()) - 1))];
  const double yaw = headingAbout(graph_.judgedHeading(k), graph_.up());
  return rng_.uniform01() < 0.5 ? yaw : std::remainder(yaw + M_PI, 2.0 * M_PI);
}

void SurfaceStateSampler::sampleUniform(ompl::base::State* state) {
  State& out = st(state);
  out.yaw = rng_.uniformReal(-M_PI, M_PI);
  if (cumulative_area_.empty()) return;
  const double pick = rng_.uniformReal(0.0, cumulative_area_.back());
  const auto it = std::upper_bound(cumulative_area_.begin(), cumulative_area_.end(), pick);
  const std::size_t index = std::min<std::size_t>(static_cast<std::size_t>(it - cumulative_area_.begin()),
                                                  cumulative_area_.size() - 1);
  const std::uint32_t f = graph_.walkableFaces()[index];
  const auto& t = graph_.face(f);
  const double r1 = std::sqrt(rng_.uniform01()), r2 = rng_.uniform01();
  out.face = f;
  // (A body facing its travel keeps the draw above: the same stream of numbers as before.)
  if (graph_.keepsOwnHeading()) out.yaw = sampleYaw(f);
  out.point_W = (1 - r1) * graph_.vertex(t[0]) + r1 * (1 - r2) * graph_.vertex(t[1]) + r1 * r2 * graph_.vertex(t[2]);
}

void SurfaceStateSampler::walkFrom(ompl::base::State* state, const ompl::base::State* near, double distance_m) {
  const State& from = st(near);
  const auto [e1, e2] = tangentBasis(graph_.normal(from.face));
  const double angle = rng_.uniformReal(-M_PI, M_PI);
  const Eigen::Vector3d target = from.point_W + (distance_m / graph_.metresPerUnit()) * (std::cos(angle) * e1 + std::sin(angle) * e2);
  const SurfaceWalk walk = graph_.walk(from.location(), SurfaceLocation{FaceGraph::kNoFace, target}, false, 2.0);
  State& out = st(state);
  out.face = walk.points.back().face;
  out.point_W = walk.points.back().point_W;
  out.yaw = sampleYaw(out.face);
}

void SurfaceStateSampler::sampleUniformNear(ompl::base::State* state, const ompl::base::State* near, double distance) {
  walkFrom(state, near, rng_.uniformReal(0.0, std::max(distance, 0.0)));
}

void SurfaceStateSampler::sampleGaussian(ompl::base::State* state, const ompl::base::State* mean, double std_dev) {
  walkFrom(state, mean, std::abs(rng_.gaussian(0.0, std_dev)));
}

SurfaceValidityChecker::SurfaceValidityChecker(const ompl::base::SpaceInformationPtr& si, const FaceGraph& graph)
    : ompl::base::StateValidityChecker(si), graph_(graph) {}

bool SurfaceValidityChecker::isValid(const ompl::base::State* state) const {
  const std::uint32_t f = st(state).face;
  if (f >= graph_.faceCount() || !graph_.walkable(f)) return false;
  // A body that keeps its own heading must fit at it.
  return !graph_.keepsOwnHeading() || graph_.headingFits(f, geometry::headingDirection(st(state).yaw, graph_.up()));
}

double SurfaceValidityChecker::clearance(const ompl::base::State* state) const {
  const std::uint32_t f = st(state).face;
  if (f >= graph_.faceCount()) return 0;
  return std::min(static_cast<double>(graph_.layers(f).lethal_distance_m), 1e3);
}

SurfaceMotionValidator::SurfaceMotionValidator(const ompl::base::SpaceInformationPtr& si, const SurfaceStateSpace& space)
    : ompl::base::MotionValidator(si), space_(space) {}

bool SurfaceMotionValidator::checkMotion(const ompl::base::State* s1, const ompl::base::State* s2) const {
  const FaceGraph& graph = space_.graph();
  const auto body = bodyTurn(graph, st(s1).yaw, st(s2).yaw);
  return graph.walk(st(s1).location(), st(s2).location(), true, space_.maxDetour(), body).reached();
}

bool SurfaceMotionValidator::checkMotion(const ompl::base::State* s1, const ompl::base::State* s2,
                                         std::pair<ompl::base::State*, double>& last_valid) const {
  const FaceGraph& graph = space_.graph();
  const SurfaceWalk walk = graph.walk(st(s1).location(), st(s2).location(), true, space_.maxDetour(),
                                      bodyTurn(graph, st(s1).yaw, st(s2).yaw));
  if (walk.reached()) return true;
  const SurfaceLocation& end = walk.points.back();
  std::uint32_t face = end.face;
  if (!graph.walkable(face)) face = walk.points.size() >= 2 ? walk.points[walk.points.size() - 2].face : st(s1).face;
  const double remaining = (st(s2).point_W - end.point_W).norm() * graph.metresPerUnit();
  last_valid.second = walk.length_m + remaining > 0 ? walk.length_m / (walk.length_m + remaining) : 0.0;
  if (last_valid.first != nullptr) {
    State& out = st(last_valid.first);
    out.face = face;
    out.point_W = end.point_W;
    out.yaw = st(s1).yaw + last_valid.second * angleDifference(st(s1).yaw, st(s2).yaw);
  }
  return false;
}

SurfaceCostObjective::SurfaceCostObjective(const ompl::base::SpaceInformationPtr& si, const SurfaceStateSpace& space)
    : ompl::base::OptimizationObjective(si), space_(space) {
  description_ = "surface length weighted by traversability cost";
}

ompl::base::Cost SurfaceCostObjective::motionCost(const ompl::base::State* s1, const ompl::base::State* s2) const {
  const FaceGraph& graph = space_.graph();
  const SurfaceWalk walk = graph.walk(st(s1).location(), st(s2).location(), false, space_.maxDetour());
  if (walk.reached()) return ompl::base::Cost(walk.cost);
  // A motion the walk does not complete is invalid, but lazy planners (LazyPRM*) weigh their
  // edges before they validate them, and an infinite weight joins two roadmap components by an
  // edge their A* can never take: it then finds start and goal joined and no path between them.
  // A finite weight, the rest of the way at the dearest walkable rate, gets the edge validated
  // and removed instead.
  const double remaining_m = (st(s2).point_W - walk.points.back().point_W).norm() * graph.metresPerUnit();
  return ompl::base::Cost(walk.cost + remaining_m * (1.0 + graph.config().cost_weight) * space_.maxDetour());
}

ompl::base::Cost SurfaceCostObjective::motionCostHeuristic(const ompl::base::State* s1,
                                                          const ompl::base::State* s2) const {
  return ompl::base::Cost((st(s1).point_W - st(s2).point_W).norm() * space_.graph().metresPerUnit());
}

}  // namespace terramesh::planning::internal

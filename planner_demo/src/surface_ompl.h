#pragma once

// OMPL's view of the surface: state space, sampler, validity checker, motion validator and cost
// objective over a FaceGraph. Internal: only planning's sources include OMPL.

#include <atomic>
#include <optional>
#include <ompl/base/MotionValidator.h>
#include <ompl/base/OptimizationObjective.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/StateSpace.h>
#include <ompl/base/StateValidityChecker.h>

#include "planning/face_graph.h"

namespace terramesh::planning::internal {

/// The body's turn from heading `yaw_from` to `yaw_to` (radians, docs/planning.md) by the smaller
/// angle, for a graph whose body keeps its own heading (WalkabilityConfig::omni with headings);
/// nothing when the body faces its travel.
std::optional<BodyTurn> bodyTurn(const FaceGraph& graph, double yaw_from, double yaw_to);

/// A robot on the surface: a face, a point on it (map frame, map units) and a heading (radians
/// about "up", see docs/planning.md). Multi-level maps are fine: nothing assumes z = f(x, y).
class SurfaceStateSpace : public ompl::base::StateSpace {
 public:
  class StateType : public ompl::base::State {
   public:
    std::uint32_t face = 0;
    Eigen::Vector3d point_W = Eigen::Vector3d::Zero();
    double yaw = 0;
    SurfaceLocation location() const { return SurfaceLocation{face, point_W}; }
    void assign(const StateType& other) {
      face = other.face;
      point_W = other.point_W;
      yaw = other.yaw;
    }
  };

  /// `graph` must outlive the space. Distances: metres between positions, the component along
  /// up scaled by `vertical_weight`, plus `yaw_weight_m_per_rad` times the heading difference.
  /// Samplers get local seeds derived from `seed` in the order they are allocated.
  SurfaceStateSpace(const FaceGraph& graph, double yaw_weight_m_per_rad, double vertical_weight, double max_detour,
                    std::uint32_t seed);

  const FaceGraph& graph() const { return graph_; }
  double maxDetour() const { return max_detour_; }

  unsigned int getDimension() const override { return 3; }
  double getMaximumExtent() const override { return extent_; }
  double getMeasure() const override { return measure_; }
  void enforceBounds(ompl::base::State* state) const override;
  bool satisfiesBounds(const ompl::base::State* state) const override;
  void copyState(ompl::base::State* destination, const ompl::base::State* source) const override;
  double distance(const ompl::base::State* a, const ompl::base::State* b) const override;
  bool equalStates(const ompl::base::State* a, const ompl::base::State* b) const override;
  /// The point at fraction t of the surface walk from `from` to `to` (of the part walked, when the
  /// walk stops early: such a state is then reachable from `from`).
  void interpolate(const ompl::base::State* from, const ompl::base::State* to, double t,
                   ompl::base::State* state) const override;
  ompl::base::StateSamplerPtr allocDefaultStateSampler() const override;
  ompl::base::State* allocState() const override;
  void freeState(ompl::base::State* state) const override;
  void sanityChecks() const override {}
  void sanityChecks(double, double, unsigned int) const override {}

 private:
  const FaceGraph& graph_;
  double yaw_weight_;
  double vertical_weight_;
  double max_detour_;
  double extent_ = 1;
  double measure_ = 1;
  std::uint32_t seed_;
  mutable std::atomic<std::uint32_t> samplers_{0};
};

/// Area-weighted uniform sampling over the walkable faces; "near" samples walk a random
/// tangent direction from the given state. Each sampler has its own generator (OMPL's RNG).
class SurfaceStateSampler : public ompl::base::StateSampler {
 public:
  SurfaceStateSampler(const SurfaceStateSpace* space, std::uint32_t seed);
  void sampleUniform(ompl::base::State* state) override;
  void sampleUniformNear(ompl::base::State* state, const ompl::base::State* near, double distance) override;
  void sampleGaussian(ompl::base::State* state, const ompl::base::State* mean, double std_dev) override;

 private:
  void walkFrom(ompl::base::State* state, const ompl::base::State* near, double distance_m);
  /// A heading for a state on face f: uniform; or, for a body that keeps its own heading, half
  /// the time one of the judged headings f fits (either way round), which a uniform draw meets
  /// with probability 0 where f fits no two neighbouring ones.
  double sampleYaw(std::uint32_t f);
  const FaceGraph& graph_;
  std::vector<double> cumulative_area_;
};

/// A state is valid when its face is walkable (free class, clearance and contact folded into
/// the class by the traversability layers, far enough from lethal faces, facing up).
class SurfaceValidityChecker : public ompl::base::StateValidityChecker {
 public:
  SurfaceValidityChecker(const ompl::base::SpaceInformationPtr& si, const FaceGraph& graph);
  bool isValid(const ompl::base::State* state) const override;
  /// Distance (metres) to the nearest lethal face from the layer, capped at 1e3.
  double clearance(const ompl::base::State* state) const override;

 private:
  const FaceGraph& graph_;
};

/// A motion is valid when the surface walk between its ends reaches the end and crosses only
/// walkable faces: no jumps between floors or off ledges, no cutting through walls.
class SurfaceMotionValidator : public ompl::base::MotionValidator {
 public:
  SurfaceMotionValidator(const ompl::base::SpaceInformationPtr& si, const SurfaceStateSpace& space);
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2) const override;
  bool checkMotion(const ompl::base::State* s1, const ompl::base::State* s2,
                   std::pair<ompl::base::State*, double>& last_valid) const override;

 private:
  const SurfaceStateSpace& space_;
};

/// Path cost: integral over the surface walk of (1 + w * cost(face)) ds, in metres. The
/// heuristic is the straight distance (multipliers are >= 1, a surface walk is no shorter).
class SurfaceCostObjective : public ompl::base::OptimizationObjective {
 public:
  SurfaceCostObjective(const ompl::base::SpaceInformationPtr& si, const SurfaceStateSpace& space);
  ompl::base::Cost stateCost(const ompl::base::State*) const override { return identityCost(); }
  ompl::base::Cost motionCost(const ompl::base::State* s1, const ompl::base::State* s2) const override;
  ompl::base::Cost motionCostHeuristic(const ompl::base::State* s1, const ompl::base::State* s2) const override;

 private:
  const SurfaceStateSpace& space_;
};

}  // namespace terramesh::planning::internal

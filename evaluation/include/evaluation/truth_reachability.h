#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "datasets/triangle_bvh.h"
#include "evaluation/ground_truth_traversability.h"

namespace terramesh::evaluation {

/// How the truth's traversable faces are joined and where start and goal points land. Metres.
struct ReachabilityConfig {
  /// Two face edges are one shared edge when both ends of each lie within this distance of the
  /// other's line and they overlap by more than it along it (so a long edge meets the shorter
  /// edges that split it: the truth's refined faces are a soup with T-junctions).
  double edge_tolerance_m = 1e-4;
  /// A start or goal lands on the first truth face below a point this far above it (a ray down,
  /// twice this long): on the ground under it, on a slab's top, on a pit's floor.
  double snap_height_m = 0.5;

  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Whether the truth joins a start and a goal, and if not, why. The numeric values are written
/// to reports: never renumber.
enum class ReachStatus : std::uint8_t {
  kReachable = 0,            ///< both on traversable faces of one connected component
  kNoSurfaceUnderStart = 1,  ///< no truth face within snap_height_m above or below the start
  kNoSurfaceUnderGoal = 2,
  kStartNotTraversable = 3,  ///< the face under the start is not traversable for the robot
  kGoalNotTraversable = 4,
  kDifferentComponents = 5,  ///< both traversable, but no chain of traversable faces joins them
};

/// Lower-case name of a status ("reachable", "no_surface_under_start", ...).
std::string_view toString(ReachStatus status);

/// The answer for one start and goal.
struct ReachAnswer {
  ReachStatus status = ReachStatus::kReachable;
  /// Faces (of GroundTruthTraversability::mesh) under the start and the goal, when there is one.
  std::optional<std::uint32_t> start_face, goal_face;

  bool reachable() const { return status == ReachStatus::kReachable; }
};

/// The connectivity of a robot's traversable truth: faces joined through shared edges when both
/// are traversable (a robot drives from one onto the other), split into connected components.
/// Whether a start reaches a goal is then whether they land on one component. Keeps its own copy
/// of what it needs (the truth may be destroyed after construction). Const member functions are
/// thread-safe.
class TruthReachability {
 public:
  /// Component of a face that is not traversable.
  static constexpr std::uint32_t kNoComponent = std::numeric_limits<std::uint32_t>::max();

  /// Builds the components: O(E * edges per neighbourhood) over the E edges of the traversable
  /// faces (hashed by midpoint in cells as large as the longest), plus O(F log F) for the tree
  /// that places points.
  /// @throw std::invalid_argument if `config` is invalid or `truth` has no answer per face.
  explicit TruthReachability(const GroundTruthTraversability& truth, const ReachabilityConfig& config = {});

  std::size_t componentCount() const { return component_area_m2_.size(); }
  /// Component of face `face` (of truth.mesh), or kNoComponent.
  /// @throw std::out_of_range for a face not in the truth.
  std::uint32_t component(std::size_t face) const { return component_.at(face); }
  /// Area (m^2) of component `c`. @throw std::out_of_range for a bad index.
  double componentArea(std::uint32_t c) const { return component_area_m2_.at(c); }

  /// The truth face a point lands on (see ReachabilityConfig::snap_height_m), or nothing.
  /// @throw std::invalid_argument if `point_W` is not finite.
  std::optional<std::uint32_t> faceUnder(const Eigen::Vector3d& point_W) const;

  /// Whether the truth joins `start_W` and `goal_W` (truth frame, metres), and if not, why.
  /// O(log F). @throw std::invalid_argument if a point is not finite.
  ReachAnswer connects(const Eigen::Vector3d& start_W, const Eigen::Vector3d& goal_W) const;

 private:
  ReachabilityConfig config_;
  Eigen::Vector3d up_W_;
  std::vector<std::uint32_t> component_;
  std::vector<double> component_area_m2_;
  datasets::TriangleBvh bvh_;
};

}  // namespace terramesh::evaluation

#include "keyframe_validation.h"

#include <cstdio>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace terramesh::mesher::internal {
namespace {

/// The Steiner grid may hold at most this many nodes (~10 GB of triangulation). Beyond it the
/// data cannot be meant for this grid step: coordinates in other units than metres_per_unit says,
/// or a camera thousands of kilometres from the others.
constexpr double kMaxSteinerNodes = 16.0 * 1024 * 1024;

}  // namespace

void validateKeyframe(const Keyframe& keyframe) {
  const std::string where = "keyframe " + std::to_string(keyframe.id.value);
  if (!keyframe.position_W_C.allFinite()) {
    throw std::invalid_argument(where + ": camera centre is not finite");
  }
  const Eigen::Vector4d q = keyframe.rotation_W_C.coeffs();
  if (!q.allFinite() || q.norm() < 1e-12) {
    throw std::invalid_argument(where + ": rotation is not a finite non-zero quaternion");
  }
  std::unordered_set<PointId> seen;
  seen.reserve(keyframe.observations.size());
  for (std::size_t i = 0; i < keyframe.observations.size(); ++i) {
    const PointObservation& observation = keyframe.observations[i];
    const std::string what = where + ": observation " + std::to_string(i) + " (point " +
                             std::to_string(observation.point.value) + ")";
    if (!observation.position_W.allFinite()) {
      throw std::invalid_argument(what + ": position is not finite");
    }
    if (!seen.insert(observation.point).second) {
      throw std::invalid_argument(what + ": the point is listed twice");
    }
  }
}

/// Refuses a keyframe that would grow the Steiner grid beyond kMaxSteinerNodes, before anything
/// changes: its camera and the observations within range are what the grid must come to cover.
/// Counted in doubles, so that absurd coordinates cannot overflow the grid's integer keys.
void validateGridGrowth(const Keyframe& keyframe, const SteinerGrid& grid,
                        const MesherConfig& config) {
  const double step = config.steinerStepUnits();
  const double range = config.maxCameraDistanceUnits();
  Eigen::Vector3d lo = keyframe.position_W_C;
  Eigen::Vector3d hi = keyframe.position_W_C;
  for (const PointObservation& observation : keyframe.observations) {
    if ((observation.position_W - keyframe.position_W_C).norm() > range) continue;
    lo = lo.cwiseMin(observation.position_W);
    hi = hi.cwiseMax(observation.position_W);
  }
  if (!grid.empty()) {
    lo = lo.cwiseMin(grid.nodePosition(grid.lowerNode()));
    hi = hi.cwiseMax(grid.nodePosition(grid.upperNode()));
  } else if (!config.incremental_steiner_grid && config.fixed_grid_bounds_W) {
    lo = lo.cwiseMin(config.fixed_grid_bounds_W->min_W);
    hi = hi.cwiseMax(config.fixed_grid_bounds_W->max_W);
  }
  const Eigen::Vector3d cells = ((hi - lo) / step).array() + 2.0 * config.steiner_margin_cells + 3.0;
  const double nodes = cells.prod();
  if (!(nodes <= kMaxSteinerNodes)) {
    char count[32];
    std::snprintf(count, sizeof count, "%.3g", nodes);
    throw std::invalid_argument("keyframe " + std::to_string(keyframe.id.value) +
                                ": its camera and points would grow the Steiner grid to about " +
                                count + " nodes (limit " +
                                std::to_string(static_cast<long>(kMaxSteinerNodes)) +
                                "): the map spans too many grid steps; check metres_per_unit "
                                "and steiner_step_m");
  }
}

}  // namespace terramesh::mesher::internal

#pragma once

// Checks on a keyframe before the mesher changes anything for it.

#include "mesher/mesher.h"
#include "steiner_grid.h"

namespace terramesh::mesher::internal {

/// Throws std::invalid_argument naming the keyframe (and the observation) when its camera centre
/// or rotation is not finite, an observation's position is not finite, or a point is listed twice.
void validateKeyframe(const Keyframe& keyframe);

/// Throws std::invalid_argument when the keyframe's camera and its observations within range would
/// grow `grid` beyond the node limit (coordinates in other units than metres_per_unit says).
void validateGridGrowth(const Keyframe& keyframe, const SteinerGrid& grid, const MesherConfig& config);

}  // namespace terramesh::mesher::internal

#pragma once
// The things beside and on a street: building facades with gaps, parked cars, trees and
// loading ramps, placed at random (from the scene's seed) where they stay clear of the camera
// path, of junctions and of each other.

#include "mesh_builder.h"
#include "street_layout.h"

namespace terramesh::datasets::synthetic {

/// Ramps first (buildings keep clear of them), then buildings, cars and trees; each kind draws
/// from its own random stream.
void addStreetObjects(const StreetLayout& layout, LabeledMeshBuilder& builder);

/// Height of every loading ramp's high end.
inline constexpr double kStreetRampHeightM = 0.8;

}  // namespace terramesh::datasets::synthetic

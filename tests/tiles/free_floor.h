#pragma once

// The tiles tests' floor: a level map of free, measured faces.
#include "test_support/traversability_scenes.h"
#include "traversability/layered_mesh.h"

namespace terramesh::tiling::test_floor {

/// A floor over [x0, x1] x [0, 10] m (1 m grid) at height `z`, up +z: every face free, cost 0, 10
/// rays, measured, 1 cm height uncertainty.
inline traversability::LayeredMesh freeFloor(double x0, double x1, double z = 0) {
  traversability::LayeredMesh map;
  map.mesh = test::heightFieldMesh(x0, x1, 0, 10, 1.0, [z](double, double) { return z; });
  map.layers.resize(map.mesh.faces.size());
  for (traversability::FaceLayers& layers : map.layers) {
    layers.face_class = traversability::FaceClass::kFree;
    layers.cost = 0;
    layers.rays = 10;
    layers.evidence = traversability::Evidence::kMeasured;
    layers.height_uncertainty_m = 0.01f;
  }
  return map;
}

}  // namespace terramesh::tiling::test_floor

#pragma once

// Paths against the synthetic scene's ground truth (evaluation only: links terramesh::datasets).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "datasets/labeled_mesh.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::planning::demo {

/// Whether a path is drivable on the true scene.
struct TruthCheck {
  bool valid = true;
  /// First problem found: "obstacle under the path at (x, y, z)", "slope 35 deg > 20", ...
  std::string reason;
  std::size_t samples = 0;
};

/// Samples the polyline every `spacing_m`; at each sample casts a ray down (from 0.5 m above,
/// along -up, up to 1.5 m): the first true face hit must be drivable (road, sidewalk, curb,
/// vegetation or ramp, not wall, obstacle or ceiling) with a true slope <= max_slope_deg; and the
/// segment between consecutive samples lifted by `lift_m` must not cross the true surface
/// (driving through a wall, a car, a rock). Positions in map units, lengths in metres.
TruthCheck checkAgainstTruth(const datasets::LabeledMesh& truth, const datasets::TriangleBvh& bvh,
                             const std::vector<Eigen::Vector3d>& path_W, const Eigen::Vector3d& up_W,
                             double metres_per_unit, double max_slope_deg, double spacing_m = 0.1, double lift_m = 0.3);

}  // namespace terramesh::planning::demo

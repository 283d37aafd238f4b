#pragma once

#include <cstddef>

#include "datasets/slam_simulation.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::datasets {

/// How measureGroundDensity samples the ground. Lengths in metres, angles in degrees.
struct GroundDensityConfig {
  /// Ground faces are cut into sub-triangles with edges at most this long; each is seen or not
  /// as its centroid is.
  double sample_spacing_m = 0.5;
  /// Faces sloped less than this are ground (the simulation's own rule for
  /// ground_feature_probability).
  double ground_slope_deg = 30.0;

  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// How densely a simulated stream samples the ground its camera sees, and how noisy its points are.
struct GroundDensity {
  /// Area of every ground face (m^2).
  double ground_area_m2 = 0.0;
  /// Ground area some keyframe sees as the simulation could put a feature there: in the image,
  /// within [min_range_m, max_range_m], within max_incidence_deg of the face normal, unoccluded.
  double seen_area_m2 = 0.0;
  /// Inlier points on ground faces, and those of them seen at two keyframes or more (the ones a
  /// mesher inserts).
  std::size_t ground_points = 0;
  std::size_t ground_points_seen_twice = 0;
  /// ground_points / seen_area_m2 and ground_points_seen_twice / seen_area_m2 (points per m^2).
  double points_per_m2 = 0.0;
  double points_seen_twice_per_m2 = 0.0;
  /// Distance of every inlier's final estimate to its true position (metres): root mean square
  /// and median, over all inliers (ground or not).
  double rms_error_m = 0.0;
  double median_error_m = 0.0;
};

/// Measures `slam` (simulated on `scene` with `simulation`) against the scene's ground. `bvh` is
/// built over scene.ground_truth.mesh. O(ground samples * keyframes) visibility tests, each a ray
/// cast when the sample is in view.
/// @throw std::invalid_argument for a bad config or a bvh of another mesh.
GroundDensity measureGroundDensity(const SyntheticScene& scene, const TriangleBvh& bvh, const SimulatedSlam& slam,
                                   const SlamSimulationConfig& simulation, const GroundDensityConfig& config = {});

}  // namespace terramesh::datasets

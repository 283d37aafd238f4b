#pragma once
// Scenes built from primitives with known geometry, for mesher tests: cameras move through the
// free space and observe points sampled on the surfaces they can see.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "mesher/keyframe.h"
#include "mesher/mesher_config.h"

namespace terramesh::test {

/// A scene: keyframes in order, plus what the tests need to judge the result.
struct AnalyticScene {
  std::vector<mesher::Keyframe> keyframes;
  /// True for points of free space (where cameras can be), false for matter and the unseen.
  std::function<bool(const Eigen::Vector3d&)> in_free_space;
  /// Box that should end up mostly carved (free) and one that should stay matter.
  Eigen::Vector3d free_probe_min, free_probe_max;
  Eigen::Vector3d matter_probe_min, matter_probe_max;
  /// Genus the free-space surface should have.
  int expected_genus = 0;
};

struct SceneOptions {
  std::uint32_t seed = 7;
  /// Surface points per square metre.
  double density_per_m2 = 2.0;
  /// Keyframes along the camera path.
  int keyframes = 24;
  /// Observations farther than this are not made.
  double max_range_m = 15.0;
  /// Cameras look along their direction of travel and see points within this half-angle.
  double half_fov_deg = 60.0;
};

/// Cameras 3 m above the plane z = 0, moving along x, looking forward and 35 degrees down;
/// points on [-12, 12]^2.
AnalyticScene planeScene(const SceneOptions& options);

/// A closed room [0,12]x[0,9]x[0,3.5]; cameras walk a loop inside at 1.5 m; points on all six
/// faces. Free space: the room.
AnalyticScene boxRoomScene(const SceneOptions& options);

/// A square ring corridor around a pillar: outer walls [-10,10]^2, pillar [-4,4]^2, floor z = 0,
/// ceiling z = 3. Cameras loop around the pillar. The free space is a solid torus: genus 1.
AnalyticScene corridorScene(const SceneOptions& options);

/// Returns a copy in which every observation of a point moves by a random offset of up to
/// `magnitude` that shrinks as the point is re-observed (as SLAM estimates do).
std::vector<mesher::Keyframe> withMovingEstimates(const std::vector<mesher::Keyframe>& keyframes,
                                                  double magnitude, std::uint32_t seed);

/// The final estimate of every point (its position in the last keyframe that observes it),
/// applied to every observation: the stream a SLAM system would give if it had known the end.
std::vector<mesher::Keyframe> withFinalEstimates(const std::vector<mesher::Keyframe>& keyframes);

/// The box around every camera centre and observed point of `keyframes` (a fixed Steiner grid's
/// bounds for the modes that need one).
mesher::AxisAlignedBox keyframeBounds(const std::vector<mesher::Keyframe>& keyframes);

}  // namespace terramesh::test

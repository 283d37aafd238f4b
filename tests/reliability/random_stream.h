#pragma once
// A randomised SLAM event stream for soak tests: a camera circles inside a ring corridor (floor,
// ceiling, an outer wall and a central pillar) and sends keyframes whose observations move, are
// culled, and include outliers; earlier keyframes are corrected or removed, and a sliding window
// removes the oldest keyframes so that the map stays bounded however long the stream runs.

#include <cstdint>
#include <deque>
#include <random>
#include <unordered_map>
#include <vector>

#include "mesher/keyframe.h"
#include "mesher/mesher_config.h"

namespace terramesh::test {

struct RandomStreamConfig {
  std::uint64_t seed = 1;
  /// New keyframes to send (corrections and removals come in between).
  std::size_t keyframes = 1000;
  /// At most this many keyframes alive: older ones are removed (0: keep them all).
  std::size_t window = 30;
  /// Features created per keyframe.
  int new_points_per_keyframe = 20;
  /// Points created within this many keyframes can be observed again.
  std::size_t track_keyframes = 20;
  /// Chance that a recent point within range is observed again.
  double match_probability = 0.5;
  /// Chance that a re-observed point comes with a new estimate.
  double move_probability = 0.3;
  /// Standard deviation of an estimate around the true position.
  double noise_std_m = 0.05;
  /// Fraction of new points that are gross outliers (off the surfaces, in front or behind).
  double outlier_fraction = 0.05;
  /// Per keyframe: chance that SLAM culls some recent points, the fraction culled.
  double cull_probability = 0.1;
  double cull_fraction = 0.05;
  /// Per keyframe: chance that an earlier keyframe is re-sent with a corrected pose.
  double correction_probability = 0.05;
  /// Per keyframe: chance that an earlier keyframe (not the newest) is removed.
  double keyframe_removal_probability = 0.03;
  /// Per keyframe: chance of an observation placed exactly on another point (a duplicate).
  double duplicate_probability = 0.02;
  /// Camera advance per keyframe along the circle of radius 8 m.
  double step_rad = 0.05;
  double range_m = 8.0;
};

/// One event of the stream.
struct StreamEvent {
  enum class Kind { kKeyframe, kRemovePoints, kRemoveKeyframe };
  Kind kind = Kind::kKeyframe;
  mesher::Keyframe keyframe;  ///< kKeyframe: new or corrected keyframe
  std::vector<mesher::PointId> points;  ///< kRemovePoints
  mesher::KeyframeId removed;           ///< kRemoveKeyframe
};

/// Counts of what the stream sent so far.
struct RandomStreamCounts {
  std::size_t keyframes = 0;     ///< new keyframes
  std::size_t corrections = 0;   ///< earlier keyframes re-sent
  std::size_t keyframe_removals = 0;  ///< window evictions included
  std::size_t point_removals = 0;     ///< points culled
  std::size_t observations = 0;
  std::size_t moved_observations = 0;
  std::size_t outliers = 0;
  std::size_t duplicates = 0;
};

/// Generates events lazily: memory stays bounded by the window, not by the stream length.
class RandomStream {
 public:
  explicit RandomStream(const RandomStreamConfig& config);

  /// The next event; false once every keyframe was sent and the pending events are out.
  bool next(StreamEvent& event);
  const RandomStreamCounts& counts() const { return counts_; }

  /// Bounds of everything the stream can send (cameras and points), for fixed Steiner grids.
  static mesher::AxisAlignedBox bounds();

 private:
  struct Point {
    mesher::PointId id;
    Eigen::Vector3d true_W;
    Eigen::Vector3d estimate_W;
    std::size_t created = 0;  ///< keyframe counter at creation
    bool culled = false;
  };
  struct SentKeyframe {
    mesher::KeyframeId id;
    Eigen::Vector3d centre_W;
    std::vector<std::uint64_t> points;
  };

  void makeKeyframe(StreamEvent& event);
  void makeCorrection(StreamEvent& event);
  void makeCull(StreamEvent& event);
  Eigen::Vector3d surfaceSample(const Eigen::Vector3d& camera_W);
  Eigen::Vector3d noisy(const Eigen::Vector3d& p);
  double uniform(double lo, double hi);
  bool chance(double p);

  RandomStreamConfig config_;
  std::mt19937_64 rng_;
  RandomStreamCounts counts_;
  std::deque<StreamEvent> pending_;
  std::unordered_map<std::uint64_t, Point> points_;
  std::deque<std::uint64_t> recent_points_;  ///< ids in creation order, pruned as they age
  std::deque<SentKeyframe> alive_;            ///< alive keyframes, oldest first
  std::uint64_t next_point_id_ = 0;
  std::uint64_t next_keyframe_id_ = 0;
};

}  // namespace terramesh::test

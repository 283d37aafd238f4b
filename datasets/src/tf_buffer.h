#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rosbag_poses.h"

namespace terramesh::datasets::internal {

/// How a TfBuffer matches a time-varying edge to a lookup time: the rule of poseAt(). Seconds.
struct TfBufferConfig {
  /// Interpolate (linear position, slerp rotation) between two transforms at most this far apart.
  double max_interval_s = 0.2;
  /// Otherwise the nearest transform within this; else the edge has none at that time.
  double tolerance_s = 0.01;

  /// Every problem with these values (empty when valid).
  std::vector<std::string> problems() const;
  /// @throw std::invalid_argument listing every problem.
  void validate() const;
};

/// A tf tree the data breaks: a frame with two parents, a cycle, an edge both static and
/// time-varying. The message names the frames.
class TfProblem : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class TfLookupStatus {
  kOk,
  kUnknownFrame,       ///< a frame no edge names
  kNotConnected,       ///< both frames known, in different trees
  kNoTransformAtTime,  ///< a time-varying edge of the path has no transform within the rule
};

/// The answer of TfBuffer::lookup.
struct TfLookup {
  TfLookupStatus status = TfLookupStatus::kOk;
  /// kOk: x_target = pose.rotation_W_S * x_source + pose.position_W, at pose.time_s.
  TimedPose pose;
  /// kUnknownFrame: the frame; kNoTransformAtTime: the edge, "parent -> child".
  std::string detail;
};

/// A small tf buffer, as tf2's: edges parent -> child, each the pose of the child in the parent
/// (x_parent = R x_child + p), static (one transform, valid at any time; a later one replaces
/// it, as a re-latched /tf_static does) or time-varying (transforms by stamp). Every frame has
/// at most one parent, so the frames form trees. Frame ids are taken without leading '/'.
/// Not thread-safe for writes; lookups are const.
class TfBuffer {
 public:
  /// @throw std::invalid_argument if `config` is invalid.
  explicit TfBuffer(TfBufferConfig config = {});

  /// Sets the static edge parent -> child.
  /// @throw TfProblem: child already has another parent (naming both), the edge would close a
  ///        cycle (or parent == child), or the edge is already time-varying.
  void addStatic(std::string_view parent, std::string_view child, const TimedPose& transform);
  /// Adds a transform at transform.time_s to the time-varying edge parent -> child (equal stamps
  /// keep their order of arrival).
  /// @throw TfProblem as addStatic; also if the edge is static.
  void addDynamic(std::string_view parent, std::string_view child, const TimedPose& transform);

  bool hasFrame(std::string_view frame) const;
  /// The frames, sorted (for error messages).
  std::vector<std::string> frames() const;
  /// The root of the tree holding `frame` (itself without a parent).
  /// @throw std::out_of_range if the frame is unknown.
  std::string root(std::string_view frame) const;
  /// The frames without children in the tree under `root`, sorted.
  std::vector<std::string> leaves(std::string_view root) const;

  /// The transform from `source` to `target` at `time_s`: up from `source` and from `target` to
  /// their nearest common ancestor, each edge at `time_s` (static as it is; time-varying by the
  /// config's rule), composed. A path of one edge gives that edge's transform bit for bit.
  /// O(depth * log(transforms per edge)).
  TfLookup lookup(std::string_view target, std::string_view source, double time_s) const;

  /// The path from `target` to `source` for a report, e.g. "map -> odom -> base_link ->
  /// velodyne (base_link -> velodyne static)"; a step up is written "<-". Empty when not
  /// connected.
  std::string describePath(std::string_view target, std::string_view source) const;

  const TfBufferConfig& config() const { return config_; }
  std::size_t staticEdges() const;
  std::size_t dynamicEdges() const;
  /// The first and last stamp over every time-varying edge, if any.
  std::optional<std::pair<double, double>> dynamicSpan() const;

 private:
  struct Edge {
    std::string parent;
    bool is_static = false;
    std::vector<TimedPose> transforms;  ///< by time; one for a static edge
  };

  Edge& edgeFor(std::string_view parent, std::string_view child, bool is_static);
  /// `frame`, its parent, ..., its root.
  std::vector<std::string> ancestry(const std::string& frame) const;
  /// The common ancestor of two ancestries (index into each), if any.
  std::optional<std::pair<std::size_t, std::size_t>> meet(const std::vector<std::string>& a,
                                                          const std::vector<std::string>& b) const;
  /// T_ancestor_frame along path[0..count] (path[0] = frame, path[count] = the ancestor), or the
  /// edge that has none.
  TfLookup down(const std::vector<std::string>& path, std::size_t count, double time_s) const;

  TfBufferConfig config_;
  std::map<std::string, Edge, std::less<>> edges_;  ///< by child frame
  std::set<std::string, std::less<>> frames_;
};

/// a_T_c = a_T_b * b_T_c (position a.p + a.R b.p, rotation a.q b.q normalized).
TimedPose composePoses(const TimedPose& a_T_b, const TimedPose& b_T_c);
/// b_T_a of a_T_b.
TimedPose invertPose(const TimedPose& a_T_b);

}  // namespace terramesh::datasets::internal

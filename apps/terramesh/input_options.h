#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <vector>
#include <string>

#include "cli_args.h"
#include "datasets/stream_reader.h"

namespace terramesh::cli {

/// How to read the input stream (options shared by `mesh` and `bench`): the format, Bundler's
/// image list, for KITTI LiDAR sequences the poses file, frame range and thinning, for ROS bags
/// the topics, the clouds' frame and the pose matching, and for LiDAR input of either the range
/// limits, voxels and merging (on by default: datasets::LidarScanOptions).
struct InputOptions {
  std::string input_format = "auto";
  std::optional<std::string> image_list;
  std::optional<std::string> poses;
  std::optional<std::string> frames;  ///< "A[:B[:S]]"
  std::size_t max_returns_per_scan = 0;
  /// LiDAR input (KITTI sequences, bags without point ids): range limits, voxels, view cap.
  double min_range_m = datasets::LidarScanOptions().min_range_m;
  double max_range_m = datasets::LidarScanOptions().max_range_m;
  double lidar_voxel_m = datasets::LidarScanOptions().voxel_size_m;
  std::uint32_t lidar_max_views = datasets::LidarScanOptions().max_views_per_point;
  std::string cloud_topic;
  std::string pose_topic;
  std::vector<std::string> tf_frames;  ///< PARENT CHILD
  std::string tf_topic = "/tf";
  std::string tf_static_topic = "/tf_static";
  std::string cloud_frame = "auto";
  double max_pose_interval_s = datasets::RosbagOptions().max_pose_interval_s;
  double pose_time_tolerance_s = datasets::RosbagOptions().pose_time_tolerance_s;
  std::string point_id_field = datasets::RosbagOptions().point_id_field;
};

/// What the reader inferred and dropped (`SlamStream::reader_notes`, `reader_warnings`), one
/// "terramesh: input: ..." or "terramesh: warning: ..." line each, on `out`.
void printReaderNotes(std::ostream& out, const datasets::SlamStream& stream);

/// Adds the input options to `app`, filling `options` when it parses.
void addInputOptions(CLI::App& app, InputOptions& options);

/// The read options from the parsed values.
/// @throw UsageError for an unknown format, a malformed --frames, invalid KITTI or ROS bag options
/// (every problem listed).
datasets::StreamReadOptions streamReadOptionsFrom(const InputOptions& options);

}  // namespace terramesh::cli

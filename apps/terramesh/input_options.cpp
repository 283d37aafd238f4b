#include "input_options.h"

#include <limits>
#include <sstream>

namespace terramesh::cli {
namespace {

/// "A", "A:B" or "A:B:STEP" into the KITTI frame range.
void parseFrames(const std::string& text, datasets::KittiOdometryOptions& kitti) {
  const auto fields = parseColonIntegers(text, "--frames", "FIRST[:LAST[:STEP]]", 3);
  for (const auto& field : fields) {
    if (!field) throw UsageError("--frames expects FIRST[:LAST[:STEP]] with no empty field, got \"" + text + "\"");
  }
  kitti.first_frame = *fields[0];
  kitti.last_frame = fields.size() > 1 ? *fields[1] : std::numeric_limits<std::size_t>::max();
  if (fields.size() > 2) kitti.frame_step = *fields[2];
}

/// Every problem as one UsageError, or nothing.
void throwProblems(const std::string& what, const std::vector<std::string>& problems) {
  if (problems.empty()) return;
  std::string message = "invalid " + what + " options:";
  for (const std::string& problem : problems) message += " " + problem + ";";
  message.pop_back();
  throw UsageError(message);
}

/// " (default V s)" for a help text.
std::string defaultSeconds(double value) {
  std::ostringstream text;
  text << " (default " << value << " s)";
  return text.str();
}

void addRosbagOptions(CLI::App& app, InputOptions& options) {
  const datasets::RosbagOptions defaults;
  app.add_option("--cloud-topic", options.cloud_topic,
                 "ROS bag: the sensor_msgs/PointCloud2 topic (default: the bag's only one)")
      ->option_text("TOPIC");
  app.add_option("--pose-topic", options.pose_topic,
                 "ROS bag: the nav_msgs/Odometry or geometry_msgs/PoseStamped topic (default: the bag's only one)")
      ->option_text("TOPIC");
  app.add_option("--tf-frames", options.tf_frames,
                 "ROS bag: poses from the tf tree, world frame PARENT and sensor frame CHILD (default without a "
                 "pose topic: the root of the cloud frame's tree, and the cloud's frame)")
      ->expected(2)
      ->option_text("PARENT CHILD");
  app.add_option("--tf-topic", options.tf_topic, "ROS bag: the time-varying tf2_msgs/TFMessage topic (default /tf)")
      ->option_text("TOPIC");
  app.add_option("--tf-static-topic", options.tf_static_topic,
                 "ROS bag: the static tf2_msgs/TFMessage topic (default /tf_static)")
      ->option_text("TOPIC");
  app.add_option("--cloud-frame", options.cloud_frame,
                 "ROS bag: the clouds' points are in the sensor frame or already in the world (auto: from "
                 "header.frame_id vs the poses' frames and the tf tree)")
      ->option_text("auto|sensor|world");
  app.add_option("--max-pose-interval-s", options.max_pose_interval_s,
                 "ROS bag: interpolate a cloud's pose between two poses at most this far apart" +
                     defaultSeconds(defaults.max_pose_interval_s))
      ->option_text("S")
      ->check(nonNegativeNumber());
  app.add_option("--pose-time-tolerance-s", options.pose_time_tolerance_s,
                 "ROS bag: else take the nearest pose within this; clouds with none are dropped" +
                     defaultSeconds(defaults.pose_time_tolerance_s))
      ->option_text("S")
      ->check(nonNegativeNumber());
  app.add_option("--point-id-field", options.point_id_field,
                 "ROS bag: the integer PointCloud2 field that holds point ids (without it every return is a new point)")
      ->option_text("NAME");
}

/// LiDAR input (KITTI sequences, bags of untracked returns): range, voxels, merging.
void addLidarOptions(CLI::App& app, InputOptions& options) {
  app.add_option("--min-range-m", options.min_range_m,
                 "LiDAR input: drop returns nearer than D to the sensor (default 0)")
      ->option_text("D")
      ->check(nonNegativeNumber());
  app.add_option("--max-range-m", options.max_range_m,
                 "LiDAR input: drop returns farther than D from the sensor (default 40, the mesher's default "
                 "--max-distance-m)")
      ->option_text("D")
      ->check(positiveNumber());
  app.add_option("--lidar-voxel-m", options.lidar_voxel_m,
                 "LiDAR input: keep one return per voxel of this size and scan (the one nearest its centre) and "
                 "merge later scans' returns into that voxel's point (default 0.15; 0: every return its own point)")
      ->option_text("M")
      ->check(nonNegativeNumber());
  app.add_option("--lidar-max-views", options.lidar_max_views,
                 "LiDAR input with voxels: a voxel's point takes at most N views (rays); later returns in it are "
                 "dropped (default 2; 0: no cap)")
      ->option_text("N");
}

datasets::LidarScanOptions lidarOptionsFrom(const InputOptions& values) {
  datasets::LidarScanOptions options;
  options.min_range_m = values.min_range_m;
  options.max_range_m = values.max_range_m;
  options.voxel_size_m = values.lidar_voxel_m;
  options.max_views_per_point = values.lidar_max_views;
  throwProblems("LiDAR input", options.problems());
  return options;
}

datasets::RosbagOptions rosbagOptionsFrom(const InputOptions& values) {
  datasets::RosbagOptions options;
  options.cloud_topic = values.cloud_topic;
  options.pose_topic = values.pose_topic;
  if (values.tf_frames.size() == 2) {
    options.tf_parent_frame = values.tf_frames[0];
    options.tf_child_frame = values.tf_frames[1];
  }
  options.tf_topic = values.tf_topic;
  options.tf_static_topic = values.tf_static_topic;
  if (values.cloud_frame == "sensor") {
    options.cloud_frame = datasets::CloudFrame::kSensor;
  } else if (values.cloud_frame == "world") {
    options.cloud_frame = datasets::CloudFrame::kWorld;
  } else if (values.cloud_frame != "auto") {
    throw UsageError("--cloud-frame must be auto, sensor or world, got \"" + values.cloud_frame + "\"");
  }
  options.max_pose_interval_s = values.max_pose_interval_s;
  options.pose_time_tolerance_s = values.pose_time_tolerance_s;
  options.point_id_field = values.point_id_field;
  throwProblems("ROS bag input", options.problems());
  return options;
}

}  // namespace

void printReaderNotes(std::ostream& out, const datasets::SlamStream& stream) {
  for (const std::string& note : stream.reader_notes) out << "terramesh: input: " << note << '\n';
  for (const std::string& warning : stream.reader_warnings) out << "terramesh: warning: " << warning << '\n';
}

void addInputOptions(CLI::App& app, InputOptions& options) {
  app.add_option("--input-format", options.input_format, "how to read the input: " + datasets::streamFormatNames())
      ->option_text("FMT");
  app.add_option("--image-list", options.image_list,
                 "Bundler input: the image list (default: list_r000.out, list.txt... found beside the .out file, "
                 "else none: meshing needs no image names)")
      ->option_text("FILE");
  app.add_option("--poses", options.poses,
                 "KITTI input: cam0 poses (KITTI or TUM format; default: found beside the sequence)")
      ->option_text("FILE");
  app.add_option("--frames", options.frames, "KITTI input: frames A to B (inclusive), every S-th")
      ->option_text("A[:B[:S]]");
  app.add_option("--max-returns-per-scan", options.max_returns_per_scan,
                 "KITTI input: keep N returns per scan, a seeded uniform subset (0: all)")
      ->option_text("N")
      ->check(nonNegativeNumber());
  addRosbagOptions(app, options);
  addLidarOptions(app, options);
}

datasets::StreamReadOptions streamReadOptionsFrom(const InputOptions& values) {
  datasets::StreamReadOptions options;
  const auto format = datasets::parseStreamFormat(values.input_format);
  if (!format) throw UsageError("--input-format must be one of " + datasets::streamFormatNames());
  options.format = *format;
  if (values.image_list) options.bundler_image_list = *values.image_list;
  datasets::KittiOdometryOptions& kitti = options.kitti;
  if (values.poses) kitti.poses_path = *values.poses;
  if (values.frames) parseFrames(*values.frames, kitti);
  kitti.max_returns_per_scan = values.max_returns_per_scan;
  kitti.lidar = lidarOptionsFrom(values);
  throwProblems("KITTI input", kitti.problems());
  options.rosbag = rosbagOptionsFrom(values);
  options.rosbag.lidar = kitti.lidar;
  return options;
}

}  // namespace terramesh::cli

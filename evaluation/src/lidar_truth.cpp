#include "evaluation/lidar_truth.h"

#include <cmath>
#include <cstdio>

#include "common/input_error.h"
#include "datasets/kitti_odometry_reader.h"

namespace terramesh::evaluation {

LidarTruth readLidarTruth(const std::filesystem::path& sequence_directory, const LidarTruthOptions& options,
                          const PinholeCamera& camera, const DepthComparisonConfig& config) {
  const std::vector<Eigen::Isometry3d> poses = datasets::readKittiPoses(options.poses_path);
  const Eigen::Isometry3d cam0_from_velodyne = datasets::readKittiVelodyneToCam0(sequence_directory / "calib.txt");
  LidarTruth truth;
  truth.max_elevation_deg = options.max_elevation_deg;
  truth.min_elevation_deg = options.min_elevation_deg;
  for (std::size_t frame = options.first_frame; frame <= options.last_frame; ++frame) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.bin", frame);
    const std::filesystem::path scan_path = sequence_directory / "velodyne" / name;
    if (!std::filesystem::exists(scan_path)) continue;
    if (frame >= poses.size()) {
      throw InputError(options.poses_path.string(), "frame " + std::to_string(frame),
                       "no pose (the file has " + std::to_string(poses.size()) + " lines)");
    }
    const Eigen::Isometry3d& world_from_cam0 = poses[frame];
    const Eigen::Isometry3d world_from_velodyne = world_from_cam0 * cam0_from_velodyne;
    const Eigen::Isometry3d cam0_from_world = world_from_cam0.inverse();
    const Eigen::Vector3d origin_W = world_from_velodyne.translation();
    const std::vector<datasets::VelodyneReturn> scan = datasets::readVelodyneScan(scan_path);
    truth.returns_read += scan.size();
    truth.world_from_sensor.push_back(world_from_velodyne);
    truth.world_from_camera.push_back(world_from_cam0);
    for (const datasets::VelodyneReturn& ret : scan) {
      const Eigen::Vector3d point_W = world_from_velodyne * ret.position_S.cast<double>();
      const Eigen::Vector3d offset = point_W - origin_W;
      const double depth = offset.norm();
      if (!(depth > 0 && depth <= config.max_depth_m)) continue;
      truth.returns_W.push_back(point_W);
      if (options.camera_view_only && !camera.sees(cam0_from_world * point_W)) continue;
      truth.rays.push_back({origin_W, offset / depth, depth});
    }
  }
  if (truth.world_from_sensor.empty()) {
    throw InputError((sequence_directory / "velodyne").string(), "",
                     "no scan for frames " + std::to_string(options.first_frame) + " to " +
                         std::to_string(options.last_frame));
  }
  return truth;
}

bool LidarTruth::covers(const Eigen::Vector3d& p_W, double max_depth_m, const PinholeCamera* camera) const {
  constexpr double kDegrees = 180.0 / 3.14159265358979323846;
  for (std::size_t i = 0; i < world_from_sensor.size(); ++i) {
    const Eigen::Vector3d p_S = world_from_sensor[i].inverse() * p_W;
    const double range = p_S.norm();
    if (!(range > 0 && range <= max_depth_m)) continue;
    const double elevation_deg = std::atan2(p_S.z(), p_S.head<2>().norm()) * kDegrees;
    if (elevation_deg > max_elevation_deg || elevation_deg < min_elevation_deg) continue;
    if (camera && !camera->sees(world_from_camera[i].inverse() * p_W)) continue;
    return true;
  }
  return false;
}

}  // namespace terramesh::evaluation

#include "datasets/kitti_odometry_reader.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "binary_input.h"
#include "camera_pose.h"
#include "common/input_error.h"
#include "datasets/tum_trajectory.h"
#include "text_lines.h"

namespace terramesh::datasets {
namespace {

using internal::TextLineReader;

constexpr std::size_t kVelodyneRecordBytes = 16;

/// `directory` as an absolute path without a trailing separator, so that filename() is its last
/// component and parent_path() goes up.
std::filesystem::path directoryName(const std::filesystem::path& directory) {
  std::filesystem::path normal = std::filesystem::absolute(directory).lexically_normal();
  return normal.filename().empty() ? normal.parent_path() : normal;
}

/// A 3x4 rigid transform written by rows in tokens[first .. first + 11].
Eigen::Isometry3d parseMatrix3x4(const TextLineReader& lines,
                                 const std::vector<std::string_view>& tokens, std::size_t first) {
  Eigen::Matrix<double, 3, 4> matrix;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      matrix(r, c) =
          lines.real(tokens[first + static_cast<std::size_t>(4 * r + c)],
                     "matrix entry (" + std::to_string(r) + "," + std::to_string(c) + ")");
    }
  }
  if (!internal::isRotationMatrix(matrix.leftCols<3>())) {
    lines.fail("the left 3x3 block must be a rotation (orthonormal, determinant +1)");
  }
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = matrix.leftCols<3>();
  transform.translation() = matrix.col(3);
  return transform;
}

/// Uniform in [0, bound), the same on every platform (std distributions are not).
std::uint64_t uniformBelow(std::mt19937_64& generator, std::uint64_t bound) {
  const std::uint64_t limit = std::mt19937_64::max() - std::mt19937_64::max() % bound;
  std::uint64_t value = generator();
  while (value >= limit) value = generator();
  return value % bound;
}

/// `count` of `indices` chosen uniformly without replacement, in their original order.
void keepRandomSubset(std::vector<std::uint32_t>& indices, std::size_t count, std::uint64_t seed) {
  if (indices.size() <= count) return;
  std::mt19937_64 generator(seed);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t pick = i + uniformBelow(generator, indices.size() - i);
    std::swap(indices[i], indices[pick]);
  }
  indices.resize(count);
  std::sort(indices.begin(), indices.end());
}

/// Scans velodyne/NNNNNN.bin of the selected frames, in frame order.
std::vector<std::pair<std::size_t, std::filesystem::path>> selectScans(
    const std::filesystem::path& velodyne, const KittiOdometryOptions& options) {
  std::vector<std::pair<std::size_t, std::filesystem::path>> scans;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(velodyne, error)) {
    const std::filesystem::path& path = entry.path();
    const std::string stem = path.stem().string();
    if (path.extension() != ".bin" || stem.empty() || stem.size() > 9 ||
        !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      continue;
    }
    const std::size_t frame = std::stoul(stem);
    if (frame < options.first_frame || frame > options.last_frame ||
        (frame - options.first_frame) % options.frame_step != 0) {
      continue;
    }
    scans.emplace_back(frame, path);
  }
  if (error)
    throw InputError(velodyne.string(), "", "cannot list the directory: " + error.message());
  std::sort(scans.begin(), scans.end());
  return scans;
}

/// cam0-to-world of each selected frame, from a KITTI or TUM poses file.
std::vector<Eigen::Isometry3d> posesOfFrames(
    const std::filesystem::path& directory,
    const std::vector<std::pair<std::size_t, std::filesystem::path>>& scans,
    const KittiOdometryOptions& options) {
  std::filesystem::path poses_path = options.poses_path;
  if (poses_path.empty()) {
    const auto found = findKittiPoses(directory);
    if (!found) {
      throw InputError(directory.string(), "",
                       "no poses: expected poses.txt in the directory or ../../poses/" +
                           directoryName(directory).filename().string() +
                           ".txt (KITTI's layout), or give the poses file explicitly");
    }
    poses_path = *found;
  }
  PoseFileFormat format = options.poses_format;
  if (format == PoseFileFormat::kAuto) format = detectPoseFileFormat(poses_path);

  std::vector<Eigen::Isometry3d> result;
  result.reserve(scans.size());
  if (format == PoseFileFormat::kKitti) {
    const std::vector<Eigen::Isometry3d> poses = readKittiPoses(poses_path);
    for (const auto& [frame, path] : scans) {
      if (frame >= poses.size()) {
        throw InputError(poses_path.string(), "",
                         "has " + std::to_string(poses.size()) + " poses (frames 0-" +
                             std::to_string(poses.size() - 1) + "), but scan " + path.string() +
                             " is frame " + std::to_string(frame));
      }
      result.push_back(poses[frame]);
    }
    return result;
  }
  const std::filesystem::path times_path = directory / "times.txt";
  const std::vector<StampedPose> poses = readTumTrajectory(poses_path);
  std::error_code error;
  if (!std::filesystem::exists(times_path, error)) {
    // KITTI's Velodyne download has no times.txt: a trajectory with one pose per scan, in frame
    // order, still says which pose is which scan's.
    const auto all_scans = selectScans(directory / "velodyne", KittiOdometryOptions());
    if (poses.size() != all_scans.size()) {
      throw InputError(times_path.string(), "",
                       "missing: TUM poses are matched to scans by time (times.txt), or by order "
                       "when there is one pose per scan, but " + poses_path.string() + " has " +
                           std::to_string(poses.size()) + " poses for " +
                           std::to_string(all_scans.size()) + " scans");
    }
    for (const auto& scan : scans) {
      const auto at = std::lower_bound(all_scans.begin(), all_scans.end(), scan);
      result.push_back(poses[static_cast<std::size_t>(at - all_scans.begin())].pose_W_C);
    }
    return result;
  }
  const std::vector<double> times = readKittiTimes(times_path);
  for (const auto& [frame, path] : scans) {
    if (frame >= times.size()) {
      throw InputError(times_path.string(), "",
                       "has " + std::to_string(times.size()) + " times, but scan " + path.string() +
                           " is frame " + std::to_string(frame));
    }
    const StampedPose* pose = nearestPose(poses, times[frame], options.pose_time_tolerance_s);
    if (pose == nullptr) {
      throw InputError(poses_path.string(), "",
                       "no pose within " + std::to_string(options.pose_time_tolerance_s) +
                           " s of frame " + std::to_string(frame) + " (time " +
                           std::to_string(times[frame]) + " s in times.txt)");
    }
    result.push_back(pose->pose_W_C);
  }
  return result;
}

}  // namespace

std::vector<std::string> KittiOdometryOptions::problems() const {
  std::vector<std::string> found;
  if (frame_step == 0) found.push_back("frame_step must be at least 1");
  if (first_frame > last_frame) found.push_back("first_frame must not exceed last_frame");
  for (const std::string& problem : lidar.problems()) found.push_back("lidar." + problem);
  if (!(pose_time_tolerance_s >= 0)) found.push_back("pose_time_tolerance_s must be >= 0");
  return found;
}

bool isKittiSequenceDirectory(const std::filesystem::path& directory) {
  return std::filesystem::is_directory(directory / "velodyne") &&
         std::filesystem::is_regular_file(directory / "calib.txt");
}

std::optional<std::filesystem::path> findKittiPoses(
    const std::filesystem::path& sequence_directory) {
  const std::filesystem::path directory = directoryName(sequence_directory);
  for (const std::filesystem::path& candidate :
       {directory / "poses.txt", directory.parent_path().parent_path() / "poses" /
                                     (directory.filename().string() + ".txt")}) {
    if (std::filesystem::is_regular_file(candidate)) return candidate;
  }
  return std::nullopt;
}

PoseFileFormat detectPoseFileFormat(const std::filesystem::path& path) {
  TextLineReader lines(path);
  std::vector<std::string_view> tokens;
  if (!lines.nextTokens(tokens)) lines.fail("empty poses file");
  if (tokens.size() == 12) return PoseFileFormat::kKitti;
  if (tokens.size() == 8) return PoseFileFormat::kTum;
  lines.fail(
      "expected a KITTI pose (12 numbers) or a TUM pose (timestamp tx ty tz qx qy qz qw), "
      "got " +
      std::to_string(tokens.size()) + " fields");
}

std::vector<Eigen::Isometry3d> readKittiPoses(const std::filesystem::path& path) {
  TextLineReader lines(path);
  std::vector<Eigen::Isometry3d> poses;
  std::vector<std::string_view> tokens;
  while (lines.nextTokens(tokens)) {
    lines.expectCount(tokens, 12, "r11 r12 r13 tx r21 r22 r23 ty r31 r32 r33 tz");
    poses.push_back(parseMatrix3x4(lines, tokens, 0));
  }
  if (poses.empty()) throw InputError(path.string(), "", "no poses (expected 12 numbers a line)");
  return poses;
}

Eigen::Isometry3d readKittiVelodyneToCam0(const std::filesystem::path& calib_path) {
  TextLineReader lines(calib_path);
  std::vector<std::string_view> tokens;
  while (lines.nextTokens(tokens)) {
    if (tokens[0] != "Tr:") continue;
    lines.expectCount(tokens, 13, "Tr: followed by 12 numbers (Velodyne to cam0, 3x4 by rows)");
    return parseMatrix3x4(lines, tokens, 1);
  }
  throw InputError(calib_path.string(), "",
                   "no \"Tr:\" line (expected the Velodyne-to-cam0 transform, 12 numbers)");
}

std::vector<double> readKittiTimes(const std::filesystem::path& path) {
  TextLineReader lines(path);
  std::vector<double> times;
  std::vector<std::string_view> tokens;
  while (lines.nextTokens(tokens)) {
    lines.expectCount(tokens, 1, "time in seconds");
    times.push_back(lines.real(tokens[0], "time"));
  }
  return times;
}

std::vector<VelodyneReturn> readVelodyneScan(const std::filesystem::path& path) {
  const std::string bytes = internal::readWholeFile(path);
  if (bytes.size() % kVelodyneRecordBytes != 0) {
    throw InputError(path.string(), "size " + std::to_string(bytes.size()) + " bytes",
                     "not a multiple of 16 (expected float32 x y z reflectance records): "
                     "truncated or corrupt scan");
  }
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  std::vector<VelodyneReturn> returns(bytes.size() / kVelodyneRecordBytes);
  for (std::size_t i = 0; i < returns.size(); ++i) {
    for (int k = 0; k < 4; ++k) {
      const std::size_t offset = kVelodyneRecordBytes * i + 4 * static_cast<std::size_t>(k);
      const float value = internal::loadLittleEndian<float>(data + offset);
      if (!std::isfinite(value)) {
        throw InputError(path.string(),
                         "byte " + std::to_string(offset) + " (return " + std::to_string(i) + ")",
                         "expected a finite number");
      }
      if (k < 3) {
        returns[i].position_S[k] = value;
      } else {
        returns[i].reflectance = value;
      }
    }
  }
  return returns;
}

SlamStream readKittiOdometry(const std::filesystem::path& sequence_directory,
                             const KittiOdometryOptions& options) {
  if (const std::vector<std::string> problems = options.problems(); !problems.empty()) {
    std::string message = "readKittiOdometry: invalid options:";
    for (const std::string& problem : problems) message += " " + problem + ";";
    message.pop_back();
    throw std::invalid_argument(message);
  }
  const std::filesystem::path velodyne = sequence_directory / "velodyne";
  const auto scans = selectScans(velodyne, options);
  if (scans.empty()) {
    throw InputError(velodyne.string(), "",
                     "no scan NNNNNN.bin among the selected frames (expected KITTI's velodyne "
                     "folder)");
  }
  const Eigen::Isometry3d cam0_from_velodyne =
      readKittiVelodyneToCam0(sequence_directory / "calib.txt");
  const std::vector<Eigen::Isometry3d> poses_W_cam0 =
      posesOfFrames(sequence_directory, scans, options);

  SlamStream stream;
  stream.metres_per_unit = 1.0;
  stream.scale_known = true;
  stream.recommended_min_views = 1;
  stream.recommended_steiner_step_m = kLidarSteinerStepM;
  stream.sensor_up_S = Eigen::Vector3d::UnitZ();  // Velodyne: x forward, y left, z up
  stream.description = sequence_directory.string() + " (KITTI odometry Velodyne, " +
                       std::to_string(scans.size()) + " scans)";
  LidarScanFilter filter(options.lidar);
  std::vector<std::uint32_t> kept;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    const auto& [frame, path] = scans[s];
    const std::vector<VelodyneReturn> returns = readVelodyneScan(path);
    kept.clear();
    for (std::size_t i = 0; i < returns.size(); ++i) {
      if (options.lidar.inRange(returns[i].position_S.cast<double>().squaredNorm())) {
        kept.push_back(static_cast<std::uint32_t>(i));
      }
    }
    filter.countDroppedOutOfRange(returns.size() - kept.size());
    if (options.max_returns_per_scan > 0) {
      keepRandomSubset(kept, options.max_returns_per_scan,
                       options.seed ^ (0x9E3779B97F4A7C15ull * (frame + 1)));
    }
    const Eigen::Isometry3d pose_W_S = poses_W_cam0[s] * cam0_from_velodyne;
    mesher::Keyframe keyframe;
    keyframe.id.value = frame;
    keyframe.position_W_C = pose_W_S.translation();
    keyframe.rotation_W_C = Eigen::Quaterniond(pose_W_S.linear()).normalized();
    keyframe.observations.reserve(kept.size());
    for (const std::uint32_t i : kept) {
      keyframe.observations.push_back({{(static_cast<std::uint64_t>(frame) << 32) | i},
                                       pose_W_S * returns[i].position_S.cast<double>()});
    }
    try {
      filter.filter(keyframe);
    } catch (const std::out_of_range& error) {
      throw InputError(path.string(), "", error.what());
    }
    stream.keyframe_names[keyframe.id] = path.filename().string();
    stream.events.emplace_back(std::move(keyframe));
  }
  stream.reader_notes.push_back(filter.describe());
  return stream;
}

}  // namespace terramesh::datasets

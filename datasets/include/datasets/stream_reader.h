#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "datasets/kitti_odometry_reader.h"
#include "datasets/rosbag_reader.h"
#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// The input formats readAnyStream knows.
enum class StreamFormat {
  kAuto,           ///< detectStreamFormat decides
  kSlamJson,       ///< the authors' JSON (slam_data_version)
  kTmStream,       ///< terramesh's .tmstream
  kOpenMvg,        ///< OpenMVG sfm_data.json (sfm_data_version)
  kColmap,         ///< a COLMAP model directory, binary if present, else text
  kColmapText,     ///< a COLMAP model directory, the .txt files
  kColmapBinary,   ///< a COLMAP model directory, the .bin files
  kBundler,        ///< a Bundler .out file (image list found by findBundlerList)
  kKittiOdometry,  ///< a KITTI odometry sequence directory (velodyne/, calib.txt, poses)
  kRosbag,         ///< a ROS 1 bag (.bag): PointCloud2 plus Odometry, PoseStamped or tf
};

/// The name of a format as `--input-format` spells it: auto, slam-json, tmstream, openmvg,
/// colmap, colmap-text, colmap-bin, bundler, kitti, rosbag.
std::string_view toString(StreamFormat format);

/// The format named `name` (as toString spells it), or nullopt.
std::optional<StreamFormat> parseStreamFormat(std::string_view name);

/// Every format name, comma separated, for help texts.
std::string streamFormatNames();

/// How readAnyStream reads its input.
struct StreamReadOptions {
  StreamFormat format = StreamFormat::kAuto;
  /// Options of the KITTI reader (poses file, frames, thinning).
  KittiOdometryOptions kitti;
  /// Bundler input: the image list (empty: found by findBundlerList, or none). Other formats
  /// refuse a non-empty one.
  std::filesystem::path bundler_image_list;
  /// Options of the ROS bag reader (topics, frames, pose matching).
  RosbagOptions rosbag;
};

/// The format of `path`: a directory is a COLMAP model (cameras, images, points3D all .bin or
/// all .txt; binary wins) or else a KITTI sequence (velodyne/ and calib.txt); a file is chosen
/// by extension: `.tmstream`, `.out` (Bundler), `.bag` (ROS 1 bag), `.json` — OpenMVG if its first version key is
/// "sfm_data_version", the authors' format if it is "slam_data_version". Never returns kAuto.
/// @throw terramesh::InputError naming the path if it does not exist or matches no format.
StreamFormat detectStreamFormat(const std::filesystem::path& path);

/// Reads any supported input as a stream, in `options.format` or the detected one.
/// @throw terramesh::InputError naming the file and line or field for unreadable or bad input.
/// @throw std::invalid_argument if `options.kitti` is invalid (KITTI input only), `options.rosbag`
///        is invalid (ROS bags only), or if
///        `options.bundler_image_list` is set for input that is not Bundler.
SlamStream readAnyStream(const std::filesystem::path& path, const StreamReadOptions& options = {});

}  // namespace terramesh::datasets

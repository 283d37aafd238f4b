#include "datasets/stream_reader.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <stdexcept>
#include <utility>

#include "common/input_error.h"
#include "datasets/bundler_reader.h"
#include "datasets/colmap_reader.h"
#include "datasets/openmvg_reader.h"
#include "datasets/slam_json.h"
#include "datasets/stream_format.h"

namespace terramesh::datasets {
namespace {

constexpr std::array<std::pair<StreamFormat, std::string_view>, 10> kFormatNames = {{
    {StreamFormat::kAuto, "auto"},
    {StreamFormat::kSlamJson, "slam-json"},
    {StreamFormat::kTmStream, "tmstream"},
    {StreamFormat::kOpenMvg, "openmvg"},
    {StreamFormat::kColmap, "colmap"},
    {StreamFormat::kColmapText, "colmap-text"},
    {StreamFormat::kColmapBinary, "colmap-bin"},
    {StreamFormat::kBundler, "bundler"},
    {StreamFormat::kKittiOdometry, "kitti"},
    {StreamFormat::kRosbag, "rosbag"},
}};

/// Which version key comes first in a JSON file, read in chunks so that a large file is not
/// read whole just to pick its reader.
StreamFormat detectJsonFormat(const std::filesystem::path& path) {
  constexpr std::string_view kOpenMvgKey = "\"sfm_data_version\"";
  constexpr std::string_view kAuthorsKey = "\"slam_data_version\"";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  std::string window;
  std::array<char, 1 << 16> chunk{};
  while (in.read(chunk.data(), chunk.size()) || in.gcount() > 0) {
    window.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    const std::size_t openmvg = window.find(kOpenMvgKey);
    const std::size_t authors = window.find(kAuthorsKey);
    if (openmvg != std::string::npos || authors != std::string::npos) {
      return openmvg < authors ? StreamFormat::kOpenMvg : StreamFormat::kSlamJson;
    }
    // Keep a tail as long as a key, in case one straddles two chunks.
    window.erase(0, window.size() - std::min(window.size(), kAuthorsKey.size()));
  }
  throw InputError(path.string(), "",
                   "a .json input needs \"slam_data_version\" (the authors' format) or "
                   "\"sfm_data_version\" (OpenMVG)");
}

}  // namespace

std::string_view toString(StreamFormat format) {
  for (const auto& [value, name] : kFormatNames) {
    if (value == format) return name;
  }
  return "unknown";
}

std::optional<StreamFormat> parseStreamFormat(std::string_view name) {
  for (const auto& [value, known] : kFormatNames) {
    if (known == name) return value;
  }
  return std::nullopt;
}

std::string streamFormatNames() {
  std::string names;
  for (const auto& entry : kFormatNames) {
    if (!names.empty()) names += ", ";
    names += entry.second;
  }
  return names;
}

StreamFormat detectStreamFormat(const std::filesystem::path& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) {
    throw InputError(path.string(), "", "cannot open: no such file or directory");
  }
  if (std::filesystem::is_directory(status)) {
    if (findColmapModelDirectory(path)) return StreamFormat::kColmap;
    if (isKittiSequenceDirectory(path)) return StreamFormat::kKittiOdometry;
    throw InputError(path.string(), "",
                     "unknown input directory (expected a COLMAP model: cameras, images and "
                     "points3D, all .bin or all .txt, here or in 0/, sparse/0/ or sparse/; or a "
                     "KITTI odometry sequence: velodyne/ and calib.txt)");
  }
  const std::string extension = path.extension().string();
  if (extension == ".json") return detectJsonFormat(path);
  if (extension == ".tmstream") return StreamFormat::kTmStream;
  if (extension == ".out") return StreamFormat::kBundler;
  if (extension == ".bag") return StreamFormat::kRosbag;
  throw InputError(path.string(), "",
                   "unknown stream format \"" + extension +
                       "\" (expected .json: the authors' format or OpenMVG; .tmstream; .out: "
                       "Bundler; .bag: a ROS 1 bag; or a COLMAP or KITTI directory)");
}

SlamStream readAnyStream(const std::filesystem::path& path, const StreamReadOptions& options) {
  const StreamFormat format =
      options.format == StreamFormat::kAuto ? detectStreamFormat(path) : options.format;
  if (!options.bundler_image_list.empty() && format != StreamFormat::kBundler) {
    throw std::invalid_argument("an image list applies to Bundler input only, not to " +
                                std::string(toString(format)) + " input " + path.string());
  }
  switch (format) {
    case StreamFormat::kSlamJson:
      return readSlamJson(path);
    case StreamFormat::kTmStream:
      return readStreamFile(path);
    case StreamFormat::kOpenMvg:
      return readOpenMvgSfmData(path);
    case StreamFormat::kColmap:
      return readColmapStream(path);
    case StreamFormat::kColmapText:
      return readColmapStream(path, ColmapFileType::kText);
    case StreamFormat::kColmapBinary:
      return readColmapStream(path, ColmapFileType::kBinary);
    case StreamFormat::kBundler:
      return readBundler(path, options.bundler_image_list);
    case StreamFormat::kKittiOdometry:
      return readKittiOdometry(path, options.kitti);
    case StreamFormat::kRosbag:
      return readRosbag(path, options.rosbag);
    case StreamFormat::kAuto:
      break;
  }
  throw std::logic_error("readAnyStream: unhandled format");
}

}  // namespace terramesh::datasets

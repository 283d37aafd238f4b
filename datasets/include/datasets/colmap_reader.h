#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "datasets/slam_stream.h"

namespace terramesh::datasets {

/// The two encodings of a COLMAP sparse model.
enum class ColmapFileType {
  kText,    ///< cameras.txt, images.txt, points3D.txt
  kBinary,  ///< cameras.bin, images.bin, points3D.bin (little-endian)
};

/// A COLMAP camera (intrinsics), as stored.
struct ColmapCamera {
  std::uint32_t id = 0;
  /// Model name, e.g. "SIMPLE_RADIAL" (the binary files store its number).
  std::string model;
  std::uint64_t width_px = 0;
  std::uint64_t height_px = 0;
  /// The model's parameters, in COLMAP's order; as many as the model has.
  std::vector<double> params;
};

/// A registered COLMAP image, as stored.
struct ColmapImage {
  std::uint32_t id = 0;
  /// qvec: rotates world vectors into the camera frame (x right, y down, z forward).
  Eigen::Quaterniond rotation_C_W = Eigen::Quaterniond::Identity();
  /// tvec: x_C = R_C_W x_W + t_C_W, in model units.
  Eigen::Vector3d translation_C_W = Eigen::Vector3d::Zero();
  std::uint32_t camera_id = 0;
  std::string name;
  /// 2D keypoints in pixels, and the 3D point each one is a projection of (-1: none).
  std::vector<Eigen::Vector2d> points2D_px;
  std::vector<std::int64_t> point3D_ids;
};

/// One element of a 3D point's track: the image and the index of the 2D point in it.
struct ColmapTrackElement {
  std::uint32_t image_id = 0;
  std::uint32_t point2D_index = 0;

  friend bool operator==(const ColmapTrackElement& a, const ColmapTrackElement& b) {
    return a.image_id == b.image_id && a.point2D_index == b.point2D_index;
  }
};

/// A COLMAP 3D point, as stored.
struct ColmapPoint3D {
  std::uint64_t id = 0;
  /// Position in the model's world frame, in model units.
  Eigen::Vector3d position_W = Eigen::Vector3d::Zero();
  std::array<std::uint8_t, 3> rgb{};
  /// Mean reprojection error in pixels.
  double error_px = 0.0;
  std::vector<ColmapTrackElement> track;
};

/// A whole COLMAP sparse model; each list is in file order.
struct ColmapModel {
  std::vector<ColmapCamera> cameras;
  std::vector<ColmapImage> images;
  std::vector<ColmapPoint3D> points;
};

/// COLMAP's number for a camera model (e.g. 2 for "SIMPLE_RADIAL"), as the binary files store it;
/// nullopt for a model this reader does not know.
std::optional<int> colmapCameraModelId(std::string_view model);

/// Which encoding of a COLMAP model `directory` holds: binary when cameras.bin, images.bin and
/// points3D.bin are all there (COLMAP's own preference), else text when the three .txt files are,
/// else none.
std::optional<ColmapFileType> findColmapModel(const std::filesystem::path& directory);

/// The folder that holds the COLMAP model meant by `path`: `path` itself when it has the three
/// model files, else the first of `path/0`, `path/sparse/0` and `path/sparse` that has them
/// (COLMAP's mapper writes `sparse/0`, `sparse/1`...: model 0 is the first); nullopt if none.
/// Other files in the folder (project.ini, database.db, rigs and frames of COLMAP 3.12...) are
/// ignored. With `type`, only that encoding counts; without, either.
std::optional<std::filesystem::path> findColmapModelDirectory(
    const std::filesystem::path& path, std::optional<ColmapFileType> type = std::nullopt);

/// Reads the three files of a COLMAP sparse model in `directory`. Checks that numbers are
/// finite, quaternions have unit norm (within 1e-3), ids are unique, and that every image's
/// camera and every 3D point id an image refers to exist. Tracks are read but not cross-checked
/// with the images' 2D points. Camera models 0-11 (SIMPLE_PINHOLE ... RAD_TAN_THIN_PRISM_FISHEYE)
/// are known.
/// @throw terramesh::InputError naming the file and the line (text) or byte offset and record
///        (binary): missing file, truncated file, wrong count, unknown camera model, NaN, ...
ColmapModel readColmapModel(const std::filesystem::path& directory, ColmapFileType type);

/// One keyframe event per image, in increasing image id: centre -R^T t, rotation R^T (camera to
/// world), observations the image's 2D points that have a 3D point, in 2D point order, with the
/// 3D point's position. A 3D point seen twice in one image (COLMAP allows it) is listed once.
/// Keyframe ids are image ids, point ids are point3D ids; keyframe_names holds image names.
/// Units are the model's (scale unknown).
/// @throw std::invalid_argument if an image refers to a 3D point the model does not have.
SlamStream colmapModelToStream(const ColmapModel& model, const std::string& description);

/// Reads the COLMAP model in `directory` (or in the folder findColmapModelDirectory finds from it)
/// as a stream (colmapModelToStream), in the given encoding or, by default, the one
/// findColmapModel finds.
/// @throw terramesh::InputError if the directory holds no complete model, or as readColmapModel.
SlamStream readColmapStream(const std::filesystem::path& directory,
                            std::optional<ColmapFileType> type = std::nullopt);

}  // namespace terramesh::datasets

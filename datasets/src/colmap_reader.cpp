#include "datasets/colmap_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "binary_input.h"
#include "camera_pose.h"
#include "common/input_error.h"
#include "text_lines.h"

namespace terramesh::datasets {
namespace {

using internal::BinaryCursor;
using internal::TextLineReader;

struct CameraModelInfo {
  int id;
  const char* name;
  std::size_t param_count;
};

// COLMAP's camera models (src/colmap/sensor/models.h): id, name, number of parameters.
constexpr std::array<CameraModelInfo, 12> kCameraModels = {{
    {0, "SIMPLE_PINHOLE", 3},
    {1, "PINHOLE", 4},
    {2, "SIMPLE_RADIAL", 4},
    {3, "RADIAL", 5},
    {4, "OPENCV", 8},
    {5, "OPENCV_FISHEYE", 8},
    {6, "FULL_OPENCV", 12},
    {7, "FOV", 5},
    {8, "SIMPLE_RADIAL_FISHEYE", 4},
    {9, "RADIAL_FISHEYE", 5},
    {10, "THIN_PRISM_FISHEYE", 12},
    {11, "RAD_TAN_THIN_PRISM_FISHEYE", 16},
}};

const CameraModelInfo* cameraModelById(std::int64_t id) {
  for (const CameraModelInfo& model : kCameraModels) {
    if (model.id == id) return &model;
  }
  return nullptr;
}

const CameraModelInfo* cameraModelByName(std::string_view name) {
  for (const CameraModelInfo& model : kCameraModels) {
    if (name == model.name) return &model;
  }
  return nullptr;
}

/// Sizes of the fixed parts of binary records, to check counts against the file size.
constexpr std::size_t kBinaryCameraMinBytes = 4 + 4 + 8 + 8;
constexpr std::size_t kBinaryImageMinBytes = 4 + 7 * 8 + 4 + 1 + 8;
constexpr std::size_t kBinaryPoint2DBytes = 8 + 8 + 8;
constexpr std::size_t kBinaryPointMinBytes = 8 + 3 * 8 + 3 + 8 + 8;
constexpr std::size_t kBinaryTrackElementBytes = 4 + 4;

/// The checks text and binary models share; each returns the problem, or "" when there is none.
/// The parsers report it at their own location (line, or byte offset).
class ModelChecker {
 public:
  std::string addCamera(const ColmapCamera& camera) {
    if (!cameras_.insert(camera.id).second) {
      return "camera id " + std::to_string(camera.id) + " appears twice";
    }
    return {};
  }

  std::string addPoint(const ColmapPoint3D& point) {
    if (!points_.insert(point.id).second) {
      return "point3D id " + std::to_string(point.id) + " appears twice";
    }
    return {};
  }

  std::string addImage(const ColmapImage& image) {
    const std::string what = "image " + std::to_string(image.id);
    if (!images_.insert(image.id).second) return what + ": image id appears twice";
    if (std::abs(image.rotation_C_W.norm() - 1.0) > 1e-3) {
      return what + ": qvec must have unit norm";
    }
    if (cameras_.count(image.camera_id) == 0) {
      return what + ": camera id " + std::to_string(image.camera_id) + " is not in cameras";
    }
    return {};
  }

  std::string checkImagePoints(const ColmapImage& image) const {
    for (std::size_t i = 0; i < image.point3D_ids.size(); ++i) {
      const std::int64_t id = image.point3D_ids[i];
      if (id == -1) continue;
      if (id < 0 || points_.count(static_cast<std::uint64_t>(id)) == 0) {
        return "image " + std::to_string(image.id) + ", POINTS2D[" + std::to_string(i) +
               "]: point3D id " + std::to_string(id) +
               " is not in points3D (expected -1 or an id "
               "there)";
      }
    }
    return {};
  }

 private:
  std::unordered_set<std::uint32_t> cameras_;
  std::unordered_set<std::uint64_t> points_;
  std::unordered_set<std::uint32_t> images_;
};

class TextModelParser {
 public:
  explicit TextModelParser(const std::filesystem::path& directory) : directory_(directory) {}

  ColmapModel parse() {
    ColmapModel model;
    readCameras(model);
    readPoints(model);
    readImages(model);
    return model;
  }

 private:
  static std::uint32_t id32(const TextLineReader& lines, std::string_view token,
                            const std::string& what) {
    const std::uint64_t value = lines.integer(token, what);
    if (value > std::numeric_limits<std::uint32_t>::max()) lines.fail(what + ": out of range");
    return static_cast<std::uint32_t>(value);
  }

  void readCameras(ColmapModel& model) {
    TextLineReader lines(directory_ / "cameras.txt");
    std::vector<std::string_view> tokens;
    while (lines.nextTokens(tokens)) {
      if (tokens.size() < 4) lines.fail("expected \"CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]\"");
      ColmapCamera camera;
      camera.id = id32(lines, tokens[0], "CAMERA_ID");
      const CameraModelInfo* info = cameraModelByName(tokens[1]);
      if (info == nullptr) {
        lines.fail("unknown camera model \"" + std::string(tokens[1]) + "\"");
      }
      camera.model = info->name;
      camera.width_px = lines.integer(tokens[2], "WIDTH");
      camera.height_px = lines.integer(tokens[3], "HEIGHT");
      if (tokens.size() != 4 + info->param_count) {
        lines.fail(camera.model + " has " + std::to_string(info->param_count) +
                   " parameters, got " + std::to_string(tokens.size() - 4));
      }
      for (std::size_t p = 4; p < tokens.size(); ++p) {
        camera.params.push_back(lines.real(tokens[p], "PARAMS[" + std::to_string(p - 4) + "]"));
      }
      if (auto problem = checker_.addCamera(camera); !problem.empty()) lines.fail(problem);
      model.cameras.push_back(std::move(camera));
    }
  }

  void readPoints(ColmapModel& model) {
    TextLineReader lines(directory_ / "points3D.txt");
    std::vector<std::string_view> tokens;
    while (lines.nextTokens(tokens)) {
      if (tokens.size() < 8 || (tokens.size() - 8) % 2 != 0) {
        lines.fail("expected \"POINT3D_ID X Y Z R G B ERROR (IMAGE_ID POINT2D_IDX)...\"");
      }
      ColmapPoint3D point;
      point.id = lines.integer(tokens[0], "POINT3D_ID");
      for (int k = 0; k < 3; ++k) point.position_W[k] = lines.real(tokens[1 + k], "X Y Z");
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t channel = lines.integer(tokens[4 + k], "R G B");
        if (channel > 255) lines.fail("R G B: expected 0-255");
        point.rgb[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(channel);
      }
      point.error_px = lines.real(tokens[7], "ERROR");
      for (std::size_t t = 8; t < tokens.size(); t += 2) {
        point.track.push_back({id32(lines, tokens[t], "TRACK IMAGE_ID"),
                               id32(lines, tokens[t + 1], "TRACK POINT2D_IDX")});
      }
      if (auto problem = checker_.addPoint(point); !problem.empty()) lines.fail(problem);
      model.points.push_back(std::move(point));
    }
  }

  void readImages(ColmapModel& model) {
    TextLineReader lines(directory_ / "images.txt");
    std::vector<std::string_view> tokens;
    while (lines.nextTokens(tokens)) {
      lines.expectCount(tokens, 10, "IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
      ColmapImage image;
      image.id = id32(lines, tokens[0], "IMAGE_ID");
      image.rotation_C_W =
          Eigen::Quaterniond(lines.real(tokens[1], "QW"), lines.real(tokens[2], "QX"),
                             lines.real(tokens[3], "QY"), lines.real(tokens[4], "QZ"));
      for (int k = 0; k < 3; ++k) image.translation_C_W[k] = lines.real(tokens[5 + k], "TX TY TZ");
      image.camera_id = id32(lines, tokens[8], "CAMERA_ID");
      image.name = std::string(tokens[9]);
      if (auto problem = checker_.addImage(image); !problem.empty()) lines.fail(problem);
      const std::size_t header_line = lines.lineNumber();
      // The POINTS2D line follows its header directly, and is blank for an image without points.
      if (!lines.nextLine(tokens)) {
        lines.fail("file ends after the image of line " + std::to_string(header_line) +
                   ": expected its POINTS2D line (X Y POINT3D_ID)...");
      }
      if (tokens.size() % 3 != 0) {
        lines.fail("expected POINTS2D as (X Y POINT3D_ID) triples, got " +
                   std::to_string(tokens.size()) + " fields");
      }
      image.points2D_px.reserve(tokens.size() / 3);
      image.point3D_ids.reserve(tokens.size() / 3);
      for (std::size_t t = 0; t < tokens.size(); t += 3) {
        image.points2D_px.emplace_back(lines.real(tokens[t], "POINTS2D X"),
                                       lines.real(tokens[t + 1], "POINTS2D Y"));
        image.point3D_ids.push_back(lines.signedInteger(tokens[t + 2], "POINTS2D POINT3D_ID"));
      }
      if (auto problem = checker_.checkImagePoints(image); !problem.empty()) lines.fail(problem);
      model.images.push_back(std::move(image));
    }
  }

  std::filesystem::path directory_;
  ModelChecker checker_;
};

class BinaryModelParser {
 public:
  explicit BinaryModelParser(const std::filesystem::path& directory) : directory_(directory) {}

  ColmapModel parse() {
    ColmapModel model;
    model.cameras = readRecords<ColmapCamera>(
        "cameras.bin", "camera", kBinaryCameraMinBytes, &BinaryModelParser::readCamera,
        [this](const ColmapCamera& camera) { return checker_.addCamera(camera); });
    model.points = readRecords<ColmapPoint3D>(
        "points3D.bin", "point", kBinaryPointMinBytes, &BinaryModelParser::readPoint,
        [this](const ColmapPoint3D& point) { return checker_.addPoint(point); });
    model.images = readRecords<ColmapImage>(
        "images.bin", "image", kBinaryImageMinBytes, &BinaryModelParser::readImage,
        [this](const ColmapImage& image) {
          std::string problem = checker_.addImage(image);
          return problem.empty() ? checker_.checkImagePoints(image) : problem;
        });
    return model;
  }

 private:
  /// A file holding a count then that many records; a record's problem is reported at its start.
  template <class Record, class Check>
  std::vector<Record> readRecords(const char* file, const std::string& kind,
                                  std::size_t min_record_bytes, Record (*read)(BinaryCursor&),
                                  Check check) const {
    BinaryCursor in(directory_ / file);
    const std::uint64_t count = in.readCount((kind + " count").c_str(), min_record_bytes);
    std::vector<Record> records;
    records.reserve(count);
    for (std::uint64_t r = 0; r < count; ++r) {
      in.setRecord(kind + " " + std::to_string(r + 1) + " of " + std::to_string(count));
      const std::size_t start = in.offset();
      records.push_back(read(in));
      if (const std::string problem = check(records.back()); !problem.empty()) {
        in.fail(start, problem);
      }
    }
    in.setRecord("");
    in.expectEnd(std::to_string(count) + " " + kind + "s");
    return records;
  }

  static ColmapCamera readCamera(BinaryCursor& in) {
    ColmapCamera camera;
    camera.id = in.read<std::uint32_t>("camera_id");
    const std::size_t model_offset = in.offset();
    const auto model_id = in.read<std::int32_t>("model_id");
    const CameraModelInfo* info = cameraModelById(model_id);
    if (info == nullptr) {
      in.fail(model_offset, "unknown camera model id " + std::to_string(model_id) +
                                " (expected 0-" + std::to_string(kCameraModels.size() - 1) + ")");
    }
    camera.model = info->name;
    camera.width_px = in.read<std::uint64_t>("width");
    camera.height_px = in.read<std::uint64_t>("height");
    in.require(8 * info->param_count, std::to_string(info->param_count) + " params");
    for (std::size_t p = 0; p < info->param_count; ++p) {
      camera.params.push_back(in.readFinite("params"));
    }
    return camera;
  }

  static ColmapPoint3D readPoint(BinaryCursor& in) {
    ColmapPoint3D point;
    point.id = in.read<std::uint64_t>("point3D_id");
    for (int k = 0; k < 3; ++k) point.position_W[k] = in.readFinite("xyz");
    for (auto& channel : point.rgb) channel = in.read<std::uint8_t>("rgb");
    point.error_px = in.readFinite("error");
    point.track.resize(in.readCount("track_length", kBinaryTrackElementBytes));
    for (ColmapTrackElement& element : point.track) {
      element.image_id = in.read<std::uint32_t>("track image_id");
      element.point2D_index = in.read<std::uint32_t>("track point2D_idx");
    }
    return point;
  }

  static ColmapImage readImage(BinaryCursor& in) {
    ColmapImage image;
    image.id = in.read<std::uint32_t>("image_id");
    double q[4];
    for (double& value : q) value = in.readFinite("qvec");
    image.rotation_C_W = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    for (int k = 0; k < 3; ++k) image.translation_C_W[k] = in.readFinite("tvec");
    image.camera_id = in.read<std::uint32_t>("camera_id");
    image.name = in.readCString("name");
    const std::uint64_t points = in.readCount("num_points2D", kBinaryPoint2DBytes);
    image.points2D_px.resize(points);
    image.point3D_ids.resize(points);
    for (std::uint64_t k = 0; k < points; ++k) {
      image.points2D_px[k].x() = in.readFinite("point2D x");
      image.points2D_px[k].y() = in.readFinite("point2D y");
      image.point3D_ids[k] = in.read<std::int64_t>("point3D_id");
    }
    return image;
  }

  std::filesystem::path directory_;
  ModelChecker checker_;
};

const char* extensionOf(ColmapFileType type) {
  return type == ColmapFileType::kText ? ".txt" : ".bin";
}

bool hasModelFiles(const std::filesystem::path& directory, ColmapFileType type) {
  for (const char* stem : {"cameras", "images", "points3D"}) {
    if (!std::filesystem::is_regular_file(directory / (std::string(stem) + extensionOf(type)))) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::optional<int> colmapCameraModelId(std::string_view model) {
  const CameraModelInfo* info = cameraModelByName(model);
  if (info == nullptr) return std::nullopt;
  return info->id;
}

std::optional<ColmapFileType> findColmapModel(const std::filesystem::path& directory) {
  for (ColmapFileType type : {ColmapFileType::kBinary, ColmapFileType::kText}) {
    if (hasModelFiles(directory, type)) return type;
  }
  return std::nullopt;
}

std::optional<std::filesystem::path> findColmapModelDirectory(const std::filesystem::path& path,
                                                              std::optional<ColmapFileType> type) {
  for (const std::filesystem::path& candidate :
       {path, path / "0", path / "sparse" / "0", path / "sparse"}) {
    const bool found = type ? hasModelFiles(candidate, *type) : findColmapModel(candidate).has_value();
    if (found) return candidate;
  }
  return std::nullopt;
}

ColmapModel readColmapModel(const std::filesystem::path& directory, ColmapFileType type) {
  if (type == ColmapFileType::kText) return TextModelParser(directory).parse();
  return BinaryModelParser(directory).parse();
}

SlamStream colmapModelToStream(const ColmapModel& model, const std::string& description) {
  std::unordered_map<std::uint64_t, const ColmapPoint3D*> points;
  points.reserve(model.points.size());
  for (const ColmapPoint3D& point : model.points) points.emplace(point.id, &point);
  std::vector<const ColmapImage*> images;
  for (const ColmapImage& image : model.images) images.push_back(&image);
  std::sort(images.begin(), images.end(),
            [](const ColmapImage* a, const ColmapImage* b) { return a->id < b->id; });

  SlamStream stream;
  stream.description = description;
  stream.recommend_auto_max_distance = true;
  for (const ColmapImage* image : images) {
    mesher::Keyframe keyframe =
        internal::keyframeFromWorldToCamera(image->id, image->rotation_C_W, image->translation_C_W);
    std::unordered_set<std::int64_t> listed;
    for (const std::int64_t id : image->point3D_ids) {
      if (id == -1 || !listed.insert(id).second) continue;
      const auto point = points.find(static_cast<std::uint64_t>(id));
      if (id < 0 || point == points.end()) {
        throw std::invalid_argument("colmapModelToStream: image " + std::to_string(image->id) +
                                    " refers to point3D " + std::to_string(id) +
                                    ", which the model does not have");
      }
      keyframe.observations.push_back({{point->first}, point->second->position_W});
    }
    stream.keyframe_names[keyframe.id] = image->name;
    stream.events.emplace_back(std::move(keyframe));
  }
  return stream;
}

SlamStream readColmapStream(const std::filesystem::path& path,
                            std::optional<ColmapFileType> type) {
  const std::filesystem::path directory = findColmapModelDirectory(path, type).value_or(path);
  if (!type) type = findColmapModel(directory);
  if (!type) {
    throw InputError(directory.string(), "",
                     "not a COLMAP model: expected cameras, images and points3D, all .bin or all "
                     ".txt");
  }
  const char* encoding = *type == ColmapFileType::kText ? "text" : "binary";
  return colmapModelToStream(readColmapModel(directory, *type),
                             directory.string() + " (COLMAP " + encoding + " model)");
}

}  // namespace terramesh::datasets

#include "datasets/bundler_reader.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <unordered_set>
#include <vector>

#include "camera_pose.h"
#include "common/input_error.h"
#include "text_lines.h"

namespace terramesh::datasets {
namespace {

using internal::TextLineReader;

constexpr std::string_view kHeader = "# Bundle file v0.3";

/// The whitespace-separated tokens of a file, across lines; errors name the current line and the
/// record being read.
class TokenStream {
 public:
  explicit TokenStream(TextLineReader& lines) : lines_(lines) {}

  void setRecord(std::string record) { record_ = std::move(record); }

  std::uint64_t integer(const char* field) { return lines_.integer(next(field), label(field)); }
  double real(const char* field) { return lines_.real(next(field), label(field)); }
  /// Whether any token is left.
  bool atEnd() {
    fill();
    return next_ >= tokens_.size();
  }
  [[noreturn]] void fail(const std::string& problem) const {
    lines_.fail(record_.empty() ? problem : record_ + ": " + problem);
  }

 private:
  /// "record: field", for the reader's error messages.
  std::string label(const char* field) const {
    return record_.empty() ? std::string(field) : record_ + ": " + field;
  }

  void fill() {
    while (next_ >= tokens_.size() && lines_.nextTokens(tokens_)) next_ = 0;
  }

  std::string_view next(const char* field) {
    fill();
    if (next_ >= tokens_.size()) fail(std::string(field) + ": file ends (truncated file?)");
    return tokens_[next_++];
  }

  TextLineReader& lines_;
  std::vector<std::string_view> tokens_;
  std::size_t next_ = 0;
  std::string record_;
};

/// The first field of every non-blank line of a Bundler image list.
std::vector<std::string> readImageList(const std::filesystem::path& path) {
  TextLineReader lines(path);
  std::vector<std::string> names;
  std::vector<std::string_view> tokens;
  while (lines.nextTokens(tokens)) names.emplace_back(tokens[0]);
  return names;
}

}  // namespace

std::vector<std::filesystem::path> bundlerListCandidates(const std::filesystem::path& bundle_path) {
  const std::filesystem::path directory = bundle_path.parent_path();
  std::vector<std::filesystem::path> candidates;
  auto add = [&candidates](const std::filesystem::path& candidate) {
    if (std::find(candidates.begin(), candidates.end(), candidate) == candidates.end()) {
      candidates.push_back(candidate);
    }
  };
  std::string name = bundle_path.filename().string();
  const std::size_t bundle = name.find("bundle");
  if (bundle != std::string::npos) {
    name.replace(bundle, 6, "list");
    std::filesystem::path renamed = directory / name;
    if (renamed != bundle_path) add(renamed);
    add(renamed.replace_extension(".txt"));
  }
  add(directory / "list.txt");
  add(directory.parent_path() / "list.txt");
  return candidates;
}

std::optional<std::filesystem::path> findBundlerList(const std::filesystem::path& bundle_path) {
  for (const std::filesystem::path& candidate : bundlerListCandidates(bundle_path)) {
    std::error_code error;
    if (std::filesystem::is_regular_file(candidate, error)) return candidate;
  }
  return std::nullopt;
}

SlamStream readBundler(const std::filesystem::path& bundle_path,
                       const std::filesystem::path& list_path) {
  TextLineReader lines(bundle_path);
  std::filesystem::path list = list_path;
  if (list.empty()) list = findBundlerList(bundle_path).value_or(std::filesystem::path());

  std::vector<std::string_view> tokens;
  if (!lines.nextLine(tokens) || lines.line().rfind(kHeader, 0) != 0) {
    lines.fail("expected the header \"" + std::string(kHeader) + "\"");
  }
  TokenStream in(lines);
  in.setRecord("header");
  const std::uint64_t camera_count = in.integer("number of cameras");
  const std::uint64_t point_count = in.integer("number of points");
  // Refuse counts the file cannot hold before allocating for them: a camera is 15 numbers and a
  // point at least 7, each one character and a separator at the least.
  std::error_code size_error;
  const std::uintmax_t file_bytes = std::filesystem::file_size(bundle_path, size_error);
  if (!size_error && (camera_count > file_bytes / 30 || point_count > file_bytes / 14)) {
    in.fail(std::to_string(camera_count) + " cameras and " + std::to_string(point_count) +
            " points cannot fit in the file's " + std::to_string(file_bytes) +
            " bytes: wrong count or truncated file");
  }
  const std::vector<std::string> names =
      list.empty() ? std::vector<std::string>() : readImageList(list);
  if (!list.empty() && names.size() != camera_count) {
    throw InputError(list.string(), "",
                     "lists " + std::to_string(names.size()) + " images but " +
                         bundle_path.string() + " has " + std::to_string(camera_count) +
                         " cameras (expected one image a line, in camera order)");
  }

  // Bundler's camera frame has y up and looks down -z; ours has y down and looks down +z.
  const Eigen::Matrix3d flip_yz = Eigen::Vector3d(1, -1, -1).asDiagonal();
  std::vector<mesher::Keyframe> keyframes(camera_count);
  std::vector<bool> reconstructed(camera_count, false);
  for (std::uint64_t c = 0; c < camera_count; ++c) {
    in.setRecord("camera " + std::to_string(c));
    const double focal_px = in.real("f");
    in.real("k1");
    in.real("k2");
    Eigen::Matrix3d rotation;
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) rotation(r, k) = in.real("R");
    }
    Eigen::Vector3d translation;
    for (int k = 0; k < 3; ++k) translation[k] = in.real("t");
    if (focal_px == 0.0) continue;
    if (!internal::isRotationMatrix(rotation)) {
      in.fail("R: expected a rotation matrix (orthonormal, determinant +1)");
    }
    keyframes[c] = internal::keyframeFromWorldToCamera(c, Eigen::Quaterniond(flip_yz * rotation),
                                                       flip_yz * translation);
    reconstructed[c] = true;
  }

  std::unordered_set<std::uint64_t> listed;
  for (std::uint64_t p = 0; p < point_count; ++p) {
    in.setRecord("point " + std::to_string(p));
    Eigen::Vector3d position_W;
    for (int k = 0; k < 3; ++k) position_W[k] = in.real("position");
    for (int k = 0; k < 3; ++k) {
      if (in.integer("colour") > 255) in.fail("colour: expected 0-255");
    }
    const std::uint64_t views = in.integer("view list length");
    listed.clear();
    for (std::uint64_t v = 0; v < views; ++v) {
      const std::uint64_t camera = in.integer("view list camera");
      if (camera >= camera_count) {
        in.fail("view list: camera " + std::to_string(camera) + " out of range (" +
                std::to_string(camera_count) + " cameras)");
      }
      if (!reconstructed[camera]) {
        in.fail("view list: camera " + std::to_string(camera) + " is not reconstructed");
      }
      in.integer("view list key");
      in.real("view list x");
      in.real("view list y");
      if (listed.insert(camera).second) keyframes[camera].observations.push_back({{p}, position_W});
    }
  }
  in.setRecord("");
  if (!in.atEnd()) {
    in.fail("unexpected data after the last of " + std::to_string(point_count) + " points");
  }

  SlamStream stream;
  stream.description = bundle_path.string() + " (Bundler v0.3, " +
                       (list.empty() ? std::string("no image list") : "images of " + list.string()) +
                       ")";
  stream.recommend_auto_max_distance = true;
  for (std::uint64_t c = 0; c < camera_count; ++c) {
    if (!reconstructed[c]) continue;
    if (!names.empty()) stream.keyframe_names[keyframes[c].id] = names[c];
    stream.events.emplace_back(std::move(keyframes[c]));
  }
  return stream;
}

}  // namespace terramesh::datasets

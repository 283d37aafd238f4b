#include "datasets/openmvg_reader.h"

#include <map>
#include <unordered_map>
#include <unordered_set>

#include "json_fields.h"

namespace terramesh::datasets {
namespace {

using internal::JsonFieldReader;
using nlohmann::json;

struct ViewInfo {
  std::uint64_t pose_id = 0;
  std::string filename;
};

class SfmDataParser {
 public:
  explicit SfmDataParser(std::string file) : fields_(std::move(file)) {}

  SlamStream parse(const json& root) const {
    if (!root.is_object()) fields_.fail("", "the top level must be a JSON object");
    const std::string version =
        fields_.string(fields_.member(root, "sfm_data_version", ""), "sfm_data_version");
    const std::map<std::uint64_t, ViewInfo> views = parseViews(root);
    const std::unordered_map<std::uint64_t, mesher::Keyframe> poses = parsePoses(root);

    // Keyframes of the posed views, in increasing view key.
    std::map<std::uint64_t, mesher::Keyframe> keyframes;
    SlamStream stream;
    for (const auto& [key, view] : views) {
      const auto pose = poses.find(view.pose_id);
      if (pose == poses.end()) continue;
      mesher::Keyframe keyframe = pose->second;
      keyframe.id.value = key;
      keyframes.emplace(key, std::move(keyframe));
      stream.keyframe_names[mesher::KeyframeId{key}] = view.filename;
    }
    addObservations(root, views, keyframes);
    stream.description = fields_.file() + " (OpenMVG sfm_data_version " + version + ")";
    stream.recommend_auto_max_distance = true;
    for (auto& entry : keyframes) stream.events.emplace_back(std::move(entry.second));
    return stream;
  }

 private:
  /// The data of a cereal pointer wrapper: `value.ptr_wrapper.data`.
  const json& pointee(const json& value, const std::string& path) const {
    const std::string wrapper_path = JsonFieldReader::join(path, "ptr_wrapper");
    return fields_.member(fields_.member(value, "ptr_wrapper", path), "data", wrapper_path);
  }

  std::map<std::uint64_t, ViewInfo> parseViews(const json& root) const {
    std::map<std::uint64_t, ViewInfo> views;
    const json& array = fields_.array(fields_.member(root, "views", ""), "views");
    for (std::size_t v = 0; v < array.size(); ++v) {
      const std::string path = JsonFieldReader::at("views", v);
      const std::uint64_t key =
          fields_.id(fields_.member(array[v], "key", path), JsonFieldReader::join(path, "key"));
      const std::string data_path = JsonFieldReader::join(path, "value.ptr_wrapper.data");
      const json& data =
          pointee(fields_.member(array[v], "value", path), JsonFieldReader::join(path, "value"));
      ViewInfo view;
      view.pose_id = fields_.id(fields_.member(data, "id_pose", data_path),
                                JsonFieldReader::join(data_path, "id_pose"));
      view.filename = fields_.string(fields_.member(data, "filename", data_path),
                                     JsonFieldReader::join(data_path, "filename"));
      if (!views.emplace(key, std::move(view)).second) {
        fields_.fail(JsonFieldReader::join(path, "key"),
                     "view key " + std::to_string(key) + " appears twice");
      }
    }
    return views;
  }

  std::unordered_map<std::uint64_t, mesher::Keyframe> parsePoses(const json& root) const {
    std::unordered_map<std::uint64_t, mesher::Keyframe> poses;
    const json& array = fields_.array(fields_.member(root, "extrinsics", ""), "extrinsics");
    for (std::size_t e = 0; e < array.size(); ++e) {
      const std::string path = JsonFieldReader::at("extrinsics", e);
      const std::uint64_t key =
          fields_.id(fields_.member(array[e], "key", path), JsonFieldReader::join(path, "key"));
      const std::string value_path = JsonFieldReader::join(path, "value");
      const json& value = fields_.member(array[e], "value", path);
      // OpenMVG's Pose3: x_C = R (x_W - C), so R is world to camera.
      const Eigen::Matrix3d rotation_C_W =
          fields_.rotationRows(fields_.member(value, "rotation", value_path),
                               JsonFieldReader::join(value_path, "rotation"));
      mesher::Keyframe pose;
      pose.position_W_C = fields_.vector3(fields_.member(value, "center", value_path),
                                          JsonFieldReader::join(value_path, "center"));
      pose.rotation_W_C = Eigen::Quaterniond(rotation_C_W.transpose()).normalized();
      if (!poses.emplace(key, std::move(pose)).second) {
        fields_.fail(JsonFieldReader::join(path, "key"),
                     "pose key " + std::to_string(key) + " appears twice");
      }
    }
    return poses;
  }

  void addObservations(const json& root, const std::map<std::uint64_t, ViewInfo>& views,
                       std::map<std::uint64_t, mesher::Keyframe>& keyframes) const {
    const json& structure = fields_.array(fields_.member(root, "structure", ""), "structure");
    std::unordered_set<std::uint64_t> point_keys;
    point_keys.reserve(structure.size());
    std::unordered_set<std::uint64_t> seen_by;
    for (std::size_t s = 0; s < structure.size(); ++s) {
      const std::string path = JsonFieldReader::at("structure", s);
      const std::string key_path = JsonFieldReader::join(path, "key");
      const std::uint64_t point_key =
          fields_.id(fields_.member(structure[s], "key", path), key_path);
      if (!point_keys.insert(point_key).second) {
        fields_.fail(key_path, "point key " + std::to_string(point_key) + " appears twice");
      }
      const std::string value_path = JsonFieldReader::join(path, "value");
      const json& value = fields_.member(structure[s], "value", path);
      const Eigen::Vector3d position_W = fields_.vector3(fields_.member(value, "X", value_path),
                                                         JsonFieldReader::join(value_path, "X"));
      const std::string observations_path = JsonFieldReader::join(value_path, "observations");
      const json& observations =
          fields_.array(fields_.member(value, "observations", value_path), observations_path);
      seen_by.clear();
      for (std::size_t o = 0; o < observations.size(); ++o) {
        const std::string observation_path = JsonFieldReader::at(observations_path, o);
        const std::string view_path = JsonFieldReader::join(observation_path, "key");
        const std::uint64_t view_key =
            fields_.id(fields_.member(observations[o], "key", observation_path), view_path);
        if (!seen_by.insert(view_key).second) {
          fields_.fail(view_path,
                       "view " + std::to_string(view_key) + " observes this point twice");
        }
        const auto keyframe = keyframes.find(view_key);
        if (keyframe == keyframes.end()) {
          fields_.fail(view_path,
                       views.count(view_key) == 0
                           ? "view " + std::to_string(view_key) + " is not in views"
                           : "view " + std::to_string(view_key) + " has no pose in extrinsics");
        }
        keyframe->second.observations.push_back({{point_key}, position_W});
      }
    }
  }

  JsonFieldReader fields_;
};

}  // namespace

SlamStream readOpenMvgSfmData(const std::filesystem::path& path) {
  return SfmDataParser(path.string()).parse(terramesh::json::readJsonFile(path, "OpenMVG sfm_data JSON"));
}

}  // namespace terramesh::datasets

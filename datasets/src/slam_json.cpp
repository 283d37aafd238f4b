#include "datasets/slam_json.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <unordered_map>

#include "common/atomic_file.h"
#include "json_fields.h"

namespace terramesh::datasets {
namespace {

using internal::JsonFieldReader;
using nlohmann::json;

/// The field names that differ between the versions of the authors' format.
struct JsonVersionKeys {
  const char* view_id;
  const char* point_id;
};

class JsonStreamParser {
 public:
  explicit JsonStreamParser(std::string file) : fields_(std::move(file)) {}

  SlamStream parse(const json& root) const {
    if (!root.is_object()) fields_.fail("", "the top level must be a JSON object");
    const json& version = fields_.member(root, "slam_data_version", "");
    if (!version.is_string()) {
      fields_.fail("slam_data_version", "expected a string such as \"0.1\"");
    }
    const std::string name = version.get<std::string>();
    JsonVersionKeys keys{};
    if (name == "0.1") {
      keys = {"key", "key"};
    } else if (name == "0.2" || name == "0.3") {
      keys = {"viewId", "pointId"};
    } else {
      fields_.fail("slam_data_version",
                   "unsupported version \"" + name + "\" (expected 0.1, 0.2 or 0.3)");
    }
    const json& views = fields_.member(root, "views", "");
    if (!views.is_array()) fields_.fail("views", "expected an array of views");

    SlamStream stream;
    stream.description = fields_.file() + " (slam_data_version " + name + ")";
    for (std::size_t v = 0; v < views.size(); ++v) {
      stream.events.emplace_back(parseView(views[v], JsonFieldReader::at("views", v), keys));
    }
    return stream;
  }

 private:
  mesher::Keyframe parseView(const json& view, const std::string& path,
                             const JsonVersionKeys& keys) const {
    using Fields = JsonFieldReader;
    mesher::Keyframe keyframe;
    keyframe.id.value =
        fields_.id(fields_.member(view, keys.view_id, path), Fields::join(path, keys.view_id));
    const std::string extrinsic_path = Fields::join(path, "extrinsic");
    const json& extrinsic = fields_.member(view, "extrinsic", path);
    keyframe.position_W_C = fields_.vector3(fields_.member(extrinsic, "center", extrinsic_path),
                                            Fields::join(extrinsic_path, "center"));
    keyframe.rotation_W_C =
        Eigen::Quaterniond(
            fields_.rotationRows(fields_.member(extrinsic, "rotation", extrinsic_path),
                                 Fields::join(extrinsic_path, "rotation")))
            .normalized();
    const std::string observations_path = Fields::join(path, "observations");
    const json& observations =
        fields_.array(fields_.member(view, "observations", path), observations_path);
    keyframe.observations.reserve(observations.size());
    // The mesher rejects a point listed twice; each listing carries its own position, so there
    // is no right one to keep.
    std::unordered_map<mesher::PointId, std::size_t> first_listing;
    for (std::size_t o = 0; o < observations.size(); ++o) {
      const std::string observation_path = Fields::at(observations_path, o);
      const json& observation = observations[o];
      mesher::PointObservation parsed;
      const std::string id_path = Fields::join(observation_path, keys.point_id);
      parsed.point.value =
          fields_.id(fields_.member(observation, keys.point_id, observation_path), id_path);
      const auto [first, inserted] = first_listing.emplace(parsed.point, o);
      if (!inserted) {
        fields_.fail(id_path, "point " + std::to_string(parsed.point.value) +
                                  " is listed twice in this view (first at " +
                                  Fields::at(observations_path, first->second) + ")");
      }
      parsed.position_W = fields_.vector3(fields_.member(observation, "X", observation_path),
                                          Fields::join(observation_path, "X"));
      keyframe.observations.push_back(parsed);
    }
    return keyframe;
  }

  JsonFieldReader fields_;
};

json viewToJson(const mesher::Keyframe& keyframe, bool version01) {
  json view;
  const Eigen::Matrix3d rotation = keyframe.rotation_W_C.normalized().toRotationMatrix();
  json rows = json::array();
  for (int r = 0; r < 3; ++r) rows.push_back({rotation(r, 0), rotation(r, 1), rotation(r, 2)});
  const auto& c = keyframe.position_W_C;
  if (version01) {
    view["key"] = keyframe.id.value;
    view["id_view"] = keyframe.id.value;
    view["id_pose"] = keyframe.id.value;
  } else {
    view["viewId"] = keyframe.id.value;
  }
  view["local_path"] = "/";
  view["filename"] = "";
  view["width"] = 0;
  view["height"] = 0;
  view["id_intrinsic"] = 0;
  view["extrinsic"] = {{"rotation", rows}, {"center", {c.x(), c.y(), c.z()}}};
  json observations = json::array();
  for (const auto& observation : keyframe.observations) {
    const auto& x = observation.position_W;
    json entry;
    entry[version01 ? "key" : "pointId"] = observation.point.value;
    entry["X"] = {x.x(), x.y(), x.z()};
    entry["x"] = {0.0, 0.0};
    observations.push_back(std::move(entry));
  }
  view["observations"] = std::move(observations);
  return view;
}

}  // namespace

SlamStream readSlamJson(const std::filesystem::path& path) {
  return JsonStreamParser(path.string())
      .parse(terramesh::json::readJsonFile(path, "the authors' slam_data JSON"));
}

void writeSlamJson(const std::filesystem::path& path, const SlamStream& stream,
                   const std::string& version) {
  if (version != "0.1" && version != "0.3") {
    throw std::invalid_argument("writeSlamJson: version must be \"0.1\" or \"0.3\"");
  }
  const bool version01 = version == "0.1";
  json root;
  root["slam_data_version"] = version;
  root["root_path"] = "";
  json intrinsic = {{"polymorphic_id", 0},
                    {"polymorphic_name", "pinhole"},
                    {"ptr_wrapper",
                     {{"data",
                       {{"width", 0},
                        {"height", 0},
                        {"focal_length", 0.0},
                        {"principal_point", {0.0, 0.0}}}}}}};
  json intrinsic_entry = {{version01 ? "key" : "intrinsicId", 0}, {"value", intrinsic}};
  root["intrinsics"] = json::array({intrinsic_entry});
  json views = json::array();
  for (const StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      views.push_back(viewToJson(*keyframe, version01));
    }
  }
  root["views"] = std::move(views);
  writeFileAtomically(path, root.dump(1));
}

}  // namespace terramesh::datasets

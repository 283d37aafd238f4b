#include "datasets/slam_json.h"

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/input_error.h"

namespace terramesh::datasets {
namespace {

using nlohmann::json;

/// The field names that differ between the versions of the authors' format.
struct JsonVersionKeys {
  const char* view_id;
  const char* point_id;
};

class JsonStreamParser {
 public:
  explicit JsonStreamParser(std::string file) : file_(std::move(file)) {}

  SlamStream parse(const json& root) const {
    if (!root.is_object()) fail("", "the top level must be a JSON object");
    const json& version = member(root, "slam_data_version", "");
    if (!version.is_string()) fail("slam_data_version", "expected a string such as \"0.1\"");
    const std::string name = version.get<std::string>();
    JsonVersionKeys keys{};
    if (name == "0.1") {
      keys = {"key", "key"};
    } else if (name == "0.2" || name == "0.3") {
      keys = {"viewId", "pointId"};
    } else {
      fail("slam_data_version", "unsupported version \"" + name + "\" (expected 0.1, 0.2 or 0.3)");
    }
    const json& views = member(root, "views", "");
    if (!views.is_array()) fail("views", "expected an array of views");

    SlamStream stream;
    stream.description = file_ + " (slam_data_version " + name + ")";
    for (std::size_t v = 0; v < views.size(); ++v) {
      stream.events.emplace_back(parseView(views[v], "views[" + std::to_string(v) + "]", keys));
    }
    return stream;
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw InputError(file_, where, problem);
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  const json& member(const json& object, const char* key, const std::string& path) const {
    if (!object.is_object()) fail(path, "expected a JSON object");
    const auto it = object.find(key);
    if (it == object.end()) fail(join(path, key), "missing field");
    return *it;
  }

  std::uint64_t parseId(const json& value, const std::string& path) const {
    if (value.is_number_unsigned()) return value.get<std::uint64_t>();
    if (value.is_number_integer() && value.get<std::int64_t>() >= 0) {
      return static_cast<std::uint64_t>(value.get<std::int64_t>());
    }
    fail(path, "expected a non-negative integer id");
  }

  Eigen::Vector3d parseVector3(const json& value, const std::string& path) const {
    if (!value.is_array() || value.size() != 3) fail(path, "expected an array of 3 numbers");
    Eigen::Vector3d result;
    for (int i = 0; i < 3; ++i) {
      const json& element = value[static_cast<std::size_t>(i)];
      if (!element.is_number()) fail(path + "[" + std::to_string(i) + "]", "expected a number");
      result[i] = element.get<double>();
      if (!std::isfinite(result[i])) {
        fail(path + "[" + std::to_string(i) + "]", "expected a finite number");
      }
    }
    return result;
  }

  Eigen::Quaterniond parseRotation(const json& value, const std::string& path) const {
    if (!value.is_array() || value.size() != 3) fail(path, "expected a 3x3 array of numbers");
    Eigen::Matrix3d rotation;
    for (int r = 0; r < 3; ++r) {
      rotation.row(r) = parseVector3(value[static_cast<std::size_t>(r)],
                                     path + "[" + std::to_string(r) + "]")
                            .transpose();
    }
    const double error = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm();
    if (error > 1e-2 || rotation.determinant() < 0) {
      fail(path, "expected a rotation matrix (orthonormal, determinant +1)");
    }
    return Eigen::Quaterniond(rotation).normalized();
  }

  mesher::Keyframe parseView(const json& view, const std::string& path,
                             const JsonVersionKeys& keys) const {
    mesher::Keyframe keyframe;
    keyframe.id.value = parseId(member(view, keys.view_id, path), join(path, keys.view_id));
    const std::string extrinsic_path = join(path, "extrinsic");
    const json& extrinsic = member(view, "extrinsic", path);
    keyframe.position_W_C =
        parseVector3(member(extrinsic, "center", extrinsic_path), join(extrinsic_path, "center"));
    keyframe.rotation_W_C = parseRotation(member(extrinsic, "rotation", extrinsic_path),
                                          join(extrinsic_path, "rotation"));
    const json& observations = member(view, "observations", path);
    const std::string observations_path = join(path, "observations");
    if (!observations.is_array()) fail(observations_path, "expected an array");
    keyframe.observations.reserve(observations.size());
    for (std::size_t o = 0; o < observations.size(); ++o) {
      const std::string observation_path = observations_path + "[" + std::to_string(o) + "]";
      const json& observation = observations[o];
      mesher::PointObservation parsed;
      parsed.point.value = parseId(member(observation, keys.point_id, observation_path),
                                   join(observation_path, keys.point_id));
      parsed.position_W =
          parseVector3(member(observation, "X", observation_path), join(observation_path, "X"));
      keyframe.observations.push_back(parsed);
    }
    return keyframe;
  }

  std::string file_;
};

std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw InputError(path.string(), "", "read error");
  return content.str();
}

std::string lineAndColumn(const std::string& text, std::size_t byte) {
  byte = std::min(byte, text.size());
  std::size_t line = 1;
  std::size_t column = 1;
  for (std::size_t i = 0; i + 1 < byte; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

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
  const std::string text = readWholeFile(path);
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& error) {
    throw InputError(path.string(), lineAndColumn(text, error.byte),
                     "malformed JSON (expected the authors' slam_data JSON)");
  }
  return JsonStreamParser(path.string()).parse(root);
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

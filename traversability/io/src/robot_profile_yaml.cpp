// robot.yaml: robot profiles read from and written to YAML (yaml-cpp), with the schema of
// robot_profile_schema.h.
#include "traversability/robot_profile_yaml.h"

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/input_error.h"
#include "robot_profile_schema.h"

namespace terramesh::traversability {
namespace {

using internal::formatNumber;
using internal::kHeadingsRange;
using internal::kMinRaysRange;
using internal::kSensorHeightRange;
using internal::NumericKey;
using internal::numericKeys;
using internal::problemsOf;
using internal::Range;

/// Reads a YAML profile, throwing InputError at the first problem.
class ProfileReader {
 public:
  explicit ProfileReader(const std::filesystem::path& path) : file_(path.string()) {}

  RobotProfile read() {
    YAML::Node root;
    try {
      root = YAML::LoadFile(file_);
    } catch (const YAML::BadFile&) {
      throw InputError(file_, "file", "cannot be opened");
    } catch (const YAML::ParserException& e) {
      throw InputError(file_, lineLocation(static_cast<std::size_t>(e.mark.line) + 1), "not valid YAML: " + e.msg);
    }
    if (!root.IsMap()) throw InputError(file_, "top level", "expected a mapping of profile keys");
    RobotProfile profile;
    bool has_name = false;
    for (const auto& entry : root) {
      const std::string key = keyText(entry.first, "");
      const YAML::Node& value = entry.second;
      if (key == "name") {
        if (!value.IsScalar() || value.Scalar().empty()) fail(value, key, describe(value), "a non-empty string");
        profile.name = value.Scalar();
        has_name = true;
      } else if (key == "footprint") {
        readFootprint(value, profile);
      } else if (key == "weights") {
        readSection(value, key, {"slope", "step", "roughness", "contact", "inflation"}, profile);
      } else if (key == "contact_headings") {
        profile.contact_headings = readInteger(value, key, kHeadingsRange);
      } else if (key == "motion_model") {
        profile.motion_model = readMotionModel(value);
      } else if (key == "min_rays") {
        profile.min_rays = readInteger(value, key, kMinRaysRange);
      } else if (key == "gravity") {
        profile.gravity_W = readGravity(value);
      } else if (key == "evidence") {
        readSection(value, key,
                    {"point_noise_m", "relief_per_m_observed", "relief_per_m_unobserved", "driven_uncertainty_m",
                     "obstacle_extension", "max_obstacle_extension_m", "obstacle_support_m",
                     "unconfirmed_point_extension_m", "proud_point_rise_m", "uncertain_cost"},
                    profile);
      } else if (key == "sensor_height_m") {
        profile.sensor_height_m = readNumber(value, key, kSensorHeightRange);
      } else if (key == "sensor_pose_in_base") {
        profile.T_B_S = readSensorPose(value);
      } else if (const NumericKey* numeric = find(key)) {
        numeric->field(profile) = readNumber(value, key, numeric->range);
      } else {
        fail(entry.first, key, "an unknown key",
             "one of name, footprint, max_slope_deg, max_step_m, max_roughness_m, min_clearance_m, "
             "contact_tolerance_m, min_support, contact_headings, motion_model, inscribed_radius_m, "
             "inflation_radius_m, cost_scaling_factor, weights, min_rays, gravity, evidence, sensor_height_m, "
             "sensor_pose_in_base");
      }
    }
    if (!has_name) throw InputError(file_, "name", "missing: every profile needs a name");
    const std::vector<std::string> problems = problemsOf(profile);
    if (!problems.empty()) throw InputError(file_, "profile", problems.front());
    return profile;
  }

 private:
  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& value,
                         const std::string& expected) const {
    const YAML::Mark mark = node.Mark();
    const std::string where =
        (mark.line >= 0 ? lineLocation(static_cast<std::size_t>(mark.line) + 1) + ", " : std::string()) + "key " + key;
    throw InputError(file_, where, value + ": expected " + expected);
  }

  /// A mapping key as text; YAML also allows sequences and mappings as keys, which no profile has.
  std::string keyText(const YAML::Node& key, const std::string& section) const {
    if (!key.IsScalar()) fail(key, section + "?", describe(key), "a key name");
    return key.Scalar();
  }

  static std::string describe(const YAML::Node& node) {
    if (node.IsScalar()) return "value \"" + node.Scalar() + "\"";
    if (node.IsSequence()) return "a sequence";
    if (node.IsMap()) return "a mapping";
    return "no value";
  }

  static const NumericKey* find(const std::string& key) {
    for (const NumericKey& k : numericKeys()) {
      if (key == k.key) return &k;
    }
    return nullptr;
  }

  double readNumber(const YAML::Node& node, const std::string& key, const Range& range) const {
    double value = 0;
    bool ok = node.IsScalar();
    if (ok) {
      try {
        value = node.as<double>();
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
    if (!ok || !range.contains(value)) fail(node, key, describe(node), "a number in " + range.text());
    return value;
  }

  MotionModel readMotionModel(const YAML::Node& node) const {
    for (MotionModel model : {MotionModel::kDiffDrive, MotionModel::kOmni}) {
      if (node.IsScalar() && node.Scalar() == toString(model)) return model;
    }
    fail(node, "motion_model", describe(node), "diff_drive or omni");
  }

  int readInteger(const YAML::Node& node, const std::string& key, const Range& range) const {
    const double value = readNumber(node, key, range);
    if (value != std::floor(value)) fail(node, key, describe(node), "an integer in " + range.text());
    return static_cast<int>(value);
  }

  void readSection(const YAML::Node& node, const std::string& section, const std::set<std::string>& allowed,
                   RobotProfile& profile) const {
    if (!node.IsMap()) fail(node, section, describe(node), "a mapping");
    for (const auto& entry : node) {
      const std::string name = keyText(entry.first, section + ".");
      const std::string key = section + "." + name;
      const NumericKey* numeric = find(key);
      if (!allowed.count(name) || !numeric) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(entry.first, key, "an unknown key", "one of " + list);
      }
      numeric->field(profile) = readNumber(entry.second, key, numeric->range);
    }
  }

  void readFootprint(const YAML::Node& node, RobotProfile& profile) const {
    if (!node.IsMap()) fail(node, "footprint", describe(node), "{radius_m: R} or {length_m: L, width_m: W}");
    readSection(node, "footprint", {"radius_m", "length_m", "width_m"}, profile);
    const bool disc = static_cast<bool>(node["radius_m"]);
    const bool length = static_cast<bool>(node["length_m"]);
    const bool width = static_cast<bool>(node["width_m"]);
    if (disc && !length && !width) {
      profile.footprint = FootprintShape::kDisc;
    } else if (!disc && length && width) {
      profile.footprint = FootprintShape::kRectangle;
    } else {
      fail(node, "footprint", "a mapping with keys that do not describe one shape",
           "either radius_m alone (disc) or both length_m and width_m (rectangle)");
    }
  }

  std::optional<Eigen::Vector3d> readGravity(const YAML::Node& node) const {
    if (node.IsScalar() && node.Scalar() == "auto") return std::nullopt;
    if (node.IsSequence() && node.size() == 3) {
      Eigen::Vector3d g;
      for (int i = 0; i < 3; ++i) {
        g[i] = readNumber(node[static_cast<std::size_t>(i)], "gravity[" + std::to_string(i) + "]",
                          Range{-1e9, 1e9, false, false});
      }
      if (g.norm() > 1e-12) return g;
    }
    fail(node, "gravity", describe(node), "auto or a non-zero [x, y, z] pointing down in the map frame");
  }

  std::vector<double> readVector(const YAML::Node& node, const std::string& key, std::size_t size) const {
    if (!node.IsSequence() || node.size() != size) {
      fail(node, key, describe(node), "a sequence of " + std::to_string(size) + " numbers");
    }
    std::vector<double> values;
    for (std::size_t i = 0; i < size; ++i) {
      values.push_back(readNumber(node[i], key + "[" + std::to_string(i) + "]", Range{-1e9, 1e9, false, false}));
    }
    return values;
  }

  /// sensor_pose_in_base: {translation_m: [x, y, z], rotation_xyzw: [x, y, z, w]}, both required.
  Eigen::Isometry3d readSensorPose(const YAML::Node& node) const {
    const std::string key = "sensor_pose_in_base";
    const char* expected = "{translation_m: [x, y, z], rotation_xyzw: [x, y, z, w]}";
    if (!node.IsMap()) fail(node, key, describe(node), expected);
    for (const auto& entry : node) {
      const std::string name = keyText(entry.first, key + ".");
      if (name != "translation_m" && name != "rotation_xyzw") {
        fail(entry.first, key + "." + name, "an unknown key", "one of translation_m, rotation_xyzw");
      }
    }
    if (!node["translation_m"] || !node["rotation_xyzw"]) fail(node, key, "a mapping missing a key", expected);
    const std::vector<double> t = readVector(node["translation_m"], key + ".translation_m", 3);
    const std::vector<double> q = readVector(node["rotation_xyzw"], key + ".rotation_xyzw", 4);
    const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
    if (rotation.norm() < 1e-9) fail(node["rotation_xyzw"], key + ".rotation_xyzw", "a zero quaternion", "a non-zero quaternion");
    Eigen::Isometry3d T_B_S = Eigen::Isometry3d::Identity();
    T_B_S.linear() = rotation.normalized().toRotationMatrix();
    T_B_S.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
    return T_B_S;
  }

  std::string file_;
};

void writeMounting(YAML::Emitter& out, const RobotProfile& profile) {
  if (profile.sensor_height_m) out << YAML::Key << "sensor_height_m" << YAML::Value << *profile.sensor_height_m;
  if (!profile.T_B_S) return;
  const Eigen::Vector3d t = profile.T_B_S->translation();
  const Eigen::Quaterniond q(profile.T_B_S->linear());
  out << YAML::Key << "sensor_pose_in_base" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "translation_m" << YAML::Value << YAML::Flow << YAML::BeginSeq << t.x() << t.y() << t.z()
      << YAML::EndSeq;
  out << YAML::Key << "rotation_xyzw" << YAML::Value << YAML::Flow << YAML::BeginSeq << q.x() << q.y() << q.z()
      << q.w() << YAML::EndSeq;
  out << YAML::EndMap;
}

}  // namespace

RobotProfile loadRobotProfile(const std::filesystem::path& path) { return ProfileReader(path).read(); }

void writeRobotProfile(const std::filesystem::path& path, const RobotProfile& profile) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << profile.name;
  out << YAML::Key << "footprint" << YAML::Value << YAML::BeginMap;
  if (profile.footprint == FootprintShape::kDisc) {
    out << YAML::Key << "radius_m" << YAML::Value << profile.footprint_radius_m;
  } else {
    out << YAML::Key << "length_m" << YAML::Value << profile.footprint_length_m;
    out << YAML::Key << "width_m" << YAML::Value << profile.footprint_width_m;
  }
  out << YAML::EndMap;
  RobotProfile copy = profile;
  for (const NumericKey& key : numericKeys()) {
    const std::string k = key.key;
    if (k.find('.') != std::string::npos) continue;
    out << YAML::Key << k << YAML::Value << key.field(copy);
  }
  out << YAML::Key << "contact_headings" << YAML::Value << profile.contact_headings;
  out << YAML::Key << "motion_model" << YAML::Value << toString(profile.motion_model);
  out << YAML::Key << "min_rays" << YAML::Value << profile.min_rays;
  out << YAML::Key << "weights" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "slope" << YAML::Value << profile.weights.slope;
  out << YAML::Key << "step" << YAML::Value << profile.weights.step;
  out << YAML::Key << "roughness" << YAML::Value << profile.weights.roughness;
  out << YAML::Key << "contact" << YAML::Value << profile.weights.contact;
  out << YAML::Key << "inflation" << YAML::Value << profile.weights.inflation;
  out << YAML::EndMap;
  out << YAML::Key << "evidence" << YAML::Value << YAML::BeginMap;
  for (const NumericKey& key : numericKeys()) {
    const std::string k = key.key;
    if (k.rfind("evidence.", 0) != 0) continue;
    out << YAML::Key << k.substr(9) << YAML::Value << key.field(copy);
  }
  out << YAML::EndMap;
  out << YAML::Key << "gravity" << YAML::Value;
  if (profile.gravity_W) {
    out << YAML::Flow << YAML::BeginSeq << profile.gravity_W->x() << profile.gravity_W->y() << profile.gravity_W->z()
        << YAML::EndSeq;
  } else {
    out << "auto";
  }
  writeMounting(out, profile);
  out << YAML::EndMap;
  writeFileAtomically(path, std::string(out.c_str()) + "\n");
}

}  // namespace terramesh::traversability

// writeMapDirectory / readMapDirectory: every export of a map into one directory, and back.
#include "traversability/map_directory.h"
#include "traversability/robot_profile_yaml.h"

#include <yaml-cpp/yaml.h>

#include <regex>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/input_error.h"
#include "export_writers.h"

namespace terramesh::traversability {
namespace internal {

void writeMapFrame(const std::filesystem::path& path, const MapPlane& plane, const Eigen::Vector3d& up_W) {
  std::ostringstream out;
  out.precision(17);
  const auto vec = [&](const Eigen::Vector3d& v) {
    std::ostringstream s;
    s.precision(17);
    s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
    return s.str();
  };
  out << "# terramesh map frame: how the mesh frame (map units) relates to the metric map plane of\n"
      << "# the 2D exports. A mesh point p maps to x = plan_x . p * s, y = plan_y . p * s,\n"
      << "# height = up . p * s (metres), s = metres_per_unit. plan_x is the mesh x axis projected\n"
      << "# onto the plane perpendicular to up (the y axis if x is within 30 degrees of up).\n"
      << "up: " << vec(up_W.normalized()) << "\nmetres_per_unit: " << plane.metres_per_unit
      << "\nplan_x: " << vec(plane.x_W) << "\nplan_y: " << vec(plane.y_W) << '\n';
  writeFileAtomically(path, out.str());
}

void readMapFrame(const std::filesystem::path& path, LayeredMesh& map) {
  const std::string file = path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw InputError(file, "", "cannot open file for reading");
  } catch (const YAML::Exception& error) {
    throw InputError(file, lineLocation(static_cast<std::size_t>(error.mark.line + 1)), error.msg);
  }
  if (!root.IsMap()) throw InputError(file, "", "expected a YAML mapping");
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    if (key != "up" && key != "metres_per_unit" && key != "plan_x" && key != "plan_y") {
      throw InputError(file, "key " + key, "unknown key (expected up, metres_per_unit, plan_x, plan_y)");
    }
  }
  const auto where = [](const YAML::Node& node, const std::string& key) {
    return "key " + key + " (" + lineLocation(static_cast<std::size_t>(node.Mark().line + 1)) + ")";
  };
  const YAML::Node up = root["up"];
  if (!up || !up.IsSequence() || up.size() != 3) throw InputError(file, "key up", "expected [x, y, z]");
  Eigen::Vector3d up_W;
  try {
    for (std::size_t k = 0; k < 3; ++k) up_W[static_cast<Eigen::Index>(k)] = up[k].as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(file, where(up, "up"), "expected three numbers");
  }
  if (!up_W.allFinite() || up_W.norm() < 1e-12) throw InputError(file, where(up, "up"), "expected a finite non-zero vector");
  const YAML::Node scale = root["metres_per_unit"];
  if (!scale) throw InputError(file, "key metres_per_unit", "missing");
  double metres_per_unit = 0;
  try {
    metres_per_unit = scale.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(file, where(scale, "metres_per_unit"), "expected a number");
  }
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit)) {
    throw InputError(file, where(scale, "metres_per_unit"), "expected a positive number");
  }
  map.up_W = up_W.normalized();
  map.metres_per_unit = metres_per_unit;
}

}  // namespace internal

namespace {

constexpr const char* kPlyName = "traversability.ply";
constexpr const char* kMeshMapName = "traversability.h5";
constexpr const char* kRobotName = "robot.yaml";
constexpr const char* kFrameName = "map_frame.yaml";
constexpr const char* kSummaryName = "traversability_summary.txt";

/// Removes the level files of an earlier export with more levels than this one.
void removeStaleLevels(const std::filesystem::path& dir, std::size_t levels) {
  static const std::regex kLevelFile(R"((?:layers_)?level_(\d+)(?:_cost)?\.(?:pgm|png|yaml|tif))");
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::smatch match;
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, match, kLevelFile) && std::stoul(match[1].str()) >= levels) {
      std::error_code ignored;
      std::filesystem::remove(entry.path(), ignored);
    }
  }
}

}  // namespace

void ExportConfig::validate() const {
  std::string problems;
  if (!(grid_resolution_m > 0) || !std::isfinite(grid_resolution_m)) {
    problems = "grid_resolution_m: " + std::to_string(grid_resolution_m) + " (expected > 0)";
  }
  try {
    levels.validate();
  } catch (const std::invalid_argument& error) {
    problems += (problems.empty() ? "" : "; ") + std::string(error.what());
  }
  if (!problems.empty()) throw std::invalid_argument("ExportConfig: " + problems);
}

ExportReport writeMapDirectory(const std::filesystem::path& dir, const LayeredMesh& map,
                               const RobotProfile& profile, const ExportConfig& config) {
  config.validate();
  if (map.layers.size() != map.mesh.faces.size()) {
    throw std::invalid_argument("writeMapDirectory: " + std::to_string(map.layers.size()) + " layer records for " +
                                std::to_string(map.mesh.faces.size()) + " faces");
  }
  std::filesystem::create_directories(dir);
  const MapPlane plane = MapPlane::fromUp(map.up_W, map.metres_per_unit);
  ExportReport report;
  if (config.write_layered_ply) {
    internal::writeLayeredPly(dir / kPlyName, map);
    report.files.push_back(kPlyName);
  } else {
    std::error_code ignored;
    std::filesystem::remove(dir / kPlyName, ignored);
  }
  if (config.write_mesh_map_h5) {
    internal::writeMeshMapH5(dir / kMeshMapName, map, profile);
    report.files.push_back(kMeshMapName);
  } else {
    std::error_code ignored;
    std::filesystem::remove(dir / kMeshMapName, ignored);
  }

  const Levels levels = segmentLevels(map, plane, config.levels);
  std::vector<LevelGrid> grids;
  for (std::size_t l = 0; l < levels.count(); ++l) {
    grids.push_back(rasterizeLevel(map, plane, levels, l, config.grid_resolution_m));
    const std::string base = "level_" + std::to_string(l);
    internal::writeNav2Maps(dir, base, grids.back(), map, plane, levels.mean_height_m[l], report.files);
    if (config.write_geotiff) {
      const std::string name = "layers_" + base + ".tif";
      internal::writeLayerGeoTiff(dir / name, grids.back(), map, plane);
      report.files.push_back(name);
    }
    report.level_heights_m.push_back(levels.mean_height_m[l]);
  }
  report.levels = levels.count();
  removeStaleLevels(dir, levels.count());
  if (!config.write_geotiff) {
    for (std::size_t l = 0; l < levels.count(); ++l) {
      std::error_code ignored;
      std::filesystem::remove(dir / ("layers_level_" + std::to_string(l) + ".tif"), ignored);
    }
  }
  writeRobotProfile(dir / kRobotName, profile);
  internal::writeMapFrame(dir / kFrameName, plane, map.up_W);
  report.summary = internal::mapSummary(map, levels, grids);
  writeFileAtomically(dir / kSummaryName, report.summary);
  report.files.insert(report.files.end(), {kRobotName, kFrameName, kSummaryName});
  return report;
}

MapDirectory readMapDirectory(const std::filesystem::path& dir) {
  if (std::filesystem::exists(dir) && !std::filesystem::is_directory(dir)) {
    throw InputError(dir.string(), "", std::string("a file: expected the map's directory (") + kPlyName + ", " +
                                           kRobotName + ", " + kFrameName + "), written by terramesh");
  }
  for (const char* name : {kPlyName, kRobotName, kFrameName}) {
    if (!std::filesystem::exists(dir / name)) {
      throw InputError((dir / name).string(), "", "missing: not a map directory written by terramesh");
    }
  }
  MapDirectory result;
  result.map = internal::readLayeredPly(dir / kPlyName);
  internal::readMapFrame(dir / kFrameName, result.map);
  result.profile = loadRobotProfile(dir / kRobotName);
  return result;
}

}  // namespace terramesh::traversability

#include "mesh_frame_hints.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "common/input_error.h"

namespace terramesh::cli {
namespace {

constexpr const char* kScaleKey = "frame.metres_per_unit";
constexpr const char* kUpKey = "frame.up";
constexpr const char* kUpSourceKey = "frame.up_source";
constexpr const char* kHeightKey = "frame.sensor_height_m";
constexpr const char* kHeightSourceKey = "frame.sensor_height_source";

std::string fullPrecision(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

/// The rest of the line after `key` and one space, if the line starts with it.
std::optional<std::string> valueOf(const std::string& line, const std::string& key) {
  if (line.size() <= key.size() + 1 || line.compare(0, key.size(), key) != 0 || line[key.size()] != ' ') {
    return std::nullopt;
  }
  return line.substr(key.size() + 1);
}

}  // namespace

std::vector<std::string> meshFrameComments(const MeshFrameHints& hints) {
  std::vector<std::string> lines;
  if (hints.metres_per_unit) lines.push_back(std::string(kScaleKey) + " " + fullPrecision(*hints.metres_per_unit));
  if (hints.up_W) {
    const Eigen::Vector3d& up = *hints.up_W;
    lines.push_back(std::string(kUpKey) + " " + fullPrecision(up.x()) + " " + fullPrecision(up.y()) + " " +
                    fullPrecision(up.z()));
    if (!hints.up_source.empty()) lines.push_back(std::string(kUpSourceKey) + " " + hints.up_source);
  }
  if (hints.sensor_height_m) {
    lines.push_back(std::string(kHeightKey) + " " + fullPrecision(*hints.sensor_height_m));
    if (!hints.sensor_height_source.empty()) lines.push_back(std::string(kHeightSourceKey) + " " + hints.sensor_height_source);
  }
  return lines;
}

MeshFrameHints readMeshFrameHints(const std::filesystem::path& path) {
  MeshFrameHints hints;
  if (path.extension() != ".ply") return hints;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!in || !std::getline(in, line) || line.rfind("ply", 0) != 0) return hints;  // readMesh reports it
  const std::string file = path.string();
  for (int number = 2; std::getline(in, line) && line.rfind("end_header", 0) != 0; ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("comment ", 0) != 0) continue;
    const std::string text = line.substr(8);
    const std::string where = "line " + std::to_string(number);
    const auto number_from = [&](const std::string& value, const char* key, double& out) {
      std::istringstream words(value);
      if (!(words >> out) || !std::isfinite(out)) {
        throw InputError(file, where, std::string(key) + ": expected a number, got \"" + value + "\"");
      }
    };
    if (const auto value = valueOf(text, kScaleKey)) {
      double scale = 0;
      number_from(*value, kScaleKey, scale);
      if (!(scale > 0)) throw InputError(file, where, std::string(kScaleKey) + ": expected a positive number");
      hints.metres_per_unit = scale;
    } else if (const auto up_value = valueOf(text, kUpKey)) {
      std::istringstream words(*up_value);
      Eigen::Vector3d up;
      if (!(words >> up.x() >> up.y() >> up.z()) || !up.allFinite() || !(up.norm() > 0)) {
        throw InputError(file, where, std::string(kUpKey) + ": expected three numbers, not all zero, got \"" +
                                          *up_value + "\"");
      }
      hints.up_W = up.normalized();
    } else if (const auto source = valueOf(text, kUpSourceKey)) {
      hints.up_source = *source;
    } else if (const auto height = valueOf(text, kHeightKey)) {
      double h = 0;
      number_from(*height, kHeightKey, h);
      if (!(h > 0)) throw InputError(file, where, std::string(kHeightKey) + ": expected a positive number");
      hints.sensor_height_m = h;
    } else if (const auto height_source = valueOf(text, kHeightSourceKey)) {
      hints.sensor_height_source = *height_source;
    }
  }
  return hints;
}

}  // namespace terramesh::cli

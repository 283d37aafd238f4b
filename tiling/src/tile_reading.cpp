#include "tile_reading.h"

#include <fstream>
#include <sstream>

#include "common/input_error.h"

namespace terramesh::tiling::internal {
namespace {

std::string fileText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

PlanRect readBounds(const json::FieldReader& json, const nlohmann::json& object,
                    const std::string& path) {
  const nlohmann::json& rect = json.member(object, "bounds_m", path);
  const std::string where = json::FieldReader::join(path, "bounds_m");
  PlanRect result{json.number(rect, "min_x", where), json.number(rect, "min_y", where),
                  json.number(rect, "max_x", where), json.number(rect, "max_y", where)};
  if (result.empty()) json.fail(where, "expected min_x < max_x and min_y < max_y");
  return result;
}

Eigen::Vector3d readDirection(const json::FieldReader& json, const nlohmann::json& object,
                              const std::string& key, const std::string& path) {
  const nlohmann::json& v = json.array(object, key, path);
  const std::string where = json::FieldReader::join(path, key);
  if (v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    json.fail(where, "expected [x, y, z]");
  const Eigen::Vector3d result(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  if (!result.allFinite() || result.norm() < 1e-12)
    json.fail(where, "expected a finite non-zero vector");
  return result;
}

traversability::MapDirectory OwnedMapReader::read(const std::filesystem::path& map_dir,
                                                  const std::string& tile_name) {
  const std::filesystem::path robot = map_dir / "robot.yaml";
  const std::string text = fileText(robot);
  if (first_tile_.empty()) {
    first_tile_ = tile_name;
    first_robot_text_ = text;
  } else if (text != first_robot_text_) {
    throw InputError(
        robot.string(), "",
        "another robot profile than " + first_tile_ + "'s: mesh every tile with the same --robot");
  }
  return traversability::readMapDirectory(map_dir);
}

}  // namespace terramesh::tiling::internal

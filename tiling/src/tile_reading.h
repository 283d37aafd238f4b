#pragma once

// What the readers of a plan, a tile index and the tiles' maps share (internal to tiling): the
// bounds and vectors of their JSON, and the owned maps read one by one with a check that every
// tile was computed for the first one's robot.
#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "common/json_fields.h"
#include "tiling/tile_plan.h"
#include "traversability/map_directory.h"

namespace terramesh::tiling::internal {

/// Member "bounds_m" of `object` ({min_x, min_y, max_x, max_y}, metres) at JSON path `path`.
/// @throw terramesh::InputError naming the field if missing, not numbers, or empty.
PlanRect readBounds(const json::FieldReader& json, const nlohmann::json& object,
                    const std::string& path);

/// Member `key` of `object`: [x, y, z], finite and non-zero.
/// @throw terramesh::InputError naming the field otherwise.
Eigen::Vector3d readDirection(const json::FieldReader& json, const nlohmann::json& object,
                              const std::string& key, const std::string& path);

/// Reads tiles' owned maps (readMapDirectory) and checks that each one's robot.yaml is the first's.
class OwnedMapReader {
 public:
  /// The map in `map_dir`, the owned map of tile `tile_name`.
  /// @throw terramesh::InputError naming robot.yaml if it differs from the first tile's, or as
  ///        readMapDirectory does.
  traversability::MapDirectory read(const std::filesystem::path& map_dir,
                                    const std::string& tile_name);

 private:
  std::string first_robot_text_;
  std::string first_tile_;
};

}  // namespace terramesh::tiling::internal

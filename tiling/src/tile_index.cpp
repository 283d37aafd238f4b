// The tile index as a consumer reads it, and tiles joined for planning across their borders.
#include "tiling/tile_index.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include "common/input_error.h"
#include "common/json_fields.h"
#include "tile_reading.h"
#include "tiling/tile_map.h"
#include "traversability/map_directory.h"

namespace terramesh::tiling {
namespace {

constexpr const char* kIndexFormat = "terramesh tile index";
constexpr const char* kLayeredPly = "traversability.ply";

IndexedTile readIndexedTile(const json::FieldReader& json, const nlohmann::json& item,
                            std::size_t i, const std::filesystem::path& folder) {
  const std::string path = json::FieldReader::at("tiles", i);
  IndexedTile tile;
  tile.index = json.count(item, "index", path);
  tile.name = json.string(item, "name", path);
  tile.bounds = internal::readBounds(json, item, path);
  tile.faces = json.count(item, "faces", path);
  const nlohmann::json& files = json.array(item, "files", path);
  for (std::size_t k = 0; k < files.size(); ++k) {
    const std::filesystem::path file =
        json.string(files[k], json::FieldReader::at(json::FieldReader::join(path, "files"), k));
    if (file.filename() == kLayeredPly) tile.map_dir = (folder / file).parent_path();
  }
  if (tile.map_dir.empty())
    json.fail(json::FieldReader::join(path, "files"), std::string("expected a ") + kLayeredPly);
  return tile;
}

/// Welds the vertices of `map` at bitwise-equal positions; returns how many positions two or more
/// vertices shared.
std::size_t weldEqualPositions(traversability::LayeredMesh& map) {
  using Key = std::array<std::uint64_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return static_cast<std::size_t>(k[0] * 0x9E3779B97F4A7C15ull ^
                                      (k[1] + 0x632BE59BD9B4E019ull) * 31 ^ k[2]);
    }
  };
  const auto keyOf = [](const Eigen::Vector3d& p) {
    Key key;
    for (int i = 0; i < 3; ++i) {
      const double v = p[i] == 0.0 ? 0.0 : p[i];  // -0 and +0 are one position
      std::memcpy(&key[static_cast<std::size_t>(i)], &v, sizeof(v));
    }
    return key;
  };
  mesher::TriangleMesh& mesh = map.mesh;
  const std::size_t n = mesh.vertices.size();
  std::unordered_map<Key, std::uint32_t, KeyHash> first;
  first.reserve(n);
  std::vector<std::uint32_t> remap(n);
  std::vector<std::uint32_t> kept;
  std::size_t shared = 0;
  std::vector<std::uint8_t> counted;
  for (std::size_t v = 0; v < n; ++v) {
    const auto [it, inserted] =
        first.emplace(keyOf(mesh.vertices[v]), static_cast<std::uint32_t>(kept.size()));
    if (inserted) {
      kept.push_back(static_cast<std::uint32_t>(v));
      counted.push_back(0);
    } else if (!counted[it->second]) {
      counted[it->second] = 1;
      ++shared;
    }
    remap[v] = it->second;
  }
  const auto compact = [&](auto& values) {
    if (values.size() != n) return;
    std::remove_reference_t<decltype(values)> out;
    out.reserve(kept.size());
    for (const std::uint32_t v : kept) out.push_back(values[v]);
    values = std::move(out);
  };
  compact(mesh.vertices);
  compact(mesh.is_steiner);
  compact(mesh.driven_kind);
  compact(mesh.vertex_keys);
  for (auto& face : mesh.faces) {
    for (auto& v : face) v = remap[v];
  }
  return shared;
}

/// Edges shared by exactly two faces that come from different tiles (`tile_of_face`).
std::size_t countBorderEdges(const mesher::TriangleMesh& mesh,
                             const std::vector<std::size_t>& tile_of_face) {
  struct EdgeUse {
    std::size_t first_face = 0;
    std::uint32_t faces = 0;
    bool across = false;  ///< its second face is another tile's
  };
  std::unordered_map<std::uint64_t, EdgeUse> uses;
  uses.reserve(mesh.faces.size() * 2);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = mesh.faces[f][e], b = mesh.faces[f][(e + 1) % 3];
      EdgeUse& use = uses[(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b)];
      if (use.faces++ == 0) {
        use.first_face = f;
      } else {
        use.across = tile_of_face[use.first_face] != tile_of_face[f];
      }
    }
  }
  std::size_t border = 0;
  for (const auto& entry : uses) border += entry.second.faces == 2 && entry.second.across ? 1 : 0;
  return border;
}

}  // namespace

PlanRect TileIndex::extentOfFaces() const {
  PlanRect extent{0, 0, 0, 0};
  bool any = false;
  for (const IndexedTile& tile : tiles) {
    if (tile.faces == 0) continue;
    extent = any ? PlanRect{std::min(extent.min_x_m, tile.bounds.min_x_m),
                            std::min(extent.min_y_m, tile.bounds.min_y_m),
                            std::max(extent.max_x_m, tile.bounds.max_x_m),
                            std::max(extent.max_y_m, tile.bounds.max_y_m)}
                 : tile.bounds;
    any = true;
  }
  return extent;
}

TileIndex readTileIndex(const std::filesystem::path& path) {
  const nlohmann::json root =
      json::readJsonFile(path, "a tile index written by terramesh tiles merge");
  const json::FieldReader json(path.string());
  json.header(root, kIndexFormat, 1);
  TileIndex index;
  index.path = path;
  const nlohmann::json& frame = json.member(root, "frame", "");
  const double metres_per_unit = json.number(frame, "metres_per_unit", "frame");
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit))
    json.fail("frame.metres_per_unit", "expected > 0");
  index.plane.x_W = internal::readDirection(json, frame, "plan_x", "frame");
  index.plane.y_W = internal::readDirection(json, frame, "plan_y", "frame");
  index.plane.z_W = internal::readDirection(json, frame, "up", "frame");
  index.plane.metres_per_unit = metres_per_unit;
  index.tile_m = json.number(root, "tile_m", "");
  if (!(index.tile_m > 0) || !std::isfinite(index.tile_m)) json.fail("tile_m", "expected > 0");
  const nlohmann::json& tiles = json.array(root, "tiles", "");
  if (tiles.empty()) json.fail("tiles", "expected at least one tile");
  std::set<std::string> names;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    index.tiles.push_back(readIndexedTile(json, tiles[i], i, path.parent_path()));
    if (!names.insert(index.tiles.back().name).second) {
      json.fail(json::FieldReader::join(json::FieldReader::at("tiles", i), "name"),
                "names another tile too");
    }
  }
  return index;
}

std::vector<std::size_t> tilesMeeting(const TileIndex& index, const PlanRect& region) {
  std::vector<std::size_t> result;
  for (std::size_t i = 0; i < index.tiles.size(); ++i) {
    const PlanRect& b = index.tiles[i].bounds;
    const bool meets = b.min_x_m <= region.max_x_m && region.min_x_m <= b.max_x_m &&
                       b.min_y_m <= region.max_y_m && region.min_y_m <= b.max_y_m;
    if (meets && index.tiles[i].faces > 0) result.push_back(i);
  }
  return result;
}

JoinedTiles joinTiles(const TileIndex& index, const std::vector<std::size_t>& tiles) {
  if (tiles.empty()) throw std::invalid_argument("joinTiles: no tile to join");
  JoinedTiles joined;
  joined.tiles = tiles;
  std::vector<std::size_t> tile_of_face;
  internal::OwnedMapReader reader;
  for (const std::size_t t : tiles) {
    if (t >= index.tiles.size())
      throw std::invalid_argument("joinTiles: tile " + std::to_string(t) + " out of range");
    const IndexedTile& tile = index.tiles[t];
    traversability::MapDirectory part = reader.read(tile.map_dir, tile.name);
    if (t == tiles.front()) joined.profile = part.profile;
    const bool same_frame =
        (part.map.up_W.normalized() - index.plane.z_W.normalized()).norm() < 1e-9 &&
        std::abs(part.map.metres_per_unit - index.plane.metres_per_unit) <=
            1e-12 * index.plane.metres_per_unit;
    if (!same_frame) {
      throw InputError((tile.map_dir / "map_frame.yaml").string(), "up, metres_per_unit",
                       "differ from the tile index's frame (" + index.path.string() + ")");
    }
    if (!joined.map.mesh.vertices.empty()) {  // one frame, to the last bit, for appendMap
      part.map.up_W = joined.map.up_W;
      part.map.metres_per_unit = joined.map.metres_per_unit;
    }
    tile_of_face.insert(tile_of_face.end(), part.map.mesh.faces.size(), t);
    appendMap(joined.map, part.map);
  }
  joined.welded_vertices = weldEqualPositions(joined.map);
  joined.border_edges = countBorderEdges(joined.map.mesh, tile_of_face);
  return joined;
}

}  // namespace terramesh::tiling

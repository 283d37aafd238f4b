// Owned parts of tile maps, joined maps and class agreement across a border.
#include "tiling/tile_map.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace terramesh::tiling {
namespace {

using traversability::LayeredMesh;
using traversability::LevelGrid;

/// Adds the area of `grid_a`'s cells in `region` that `grid_b` also covers, and of those agreeing.
void compareGrids(const LevelGrid& grid_a, const LevelGrid& grid_b, const PlanRect& region, ClassAgreement& result) {
  const double r = grid_a.resolution_m;
  for (std::size_t row = 0; row < grid_a.height; ++row) {
    for (std::size_t col = 0; col < grid_a.width; ++col) {
      const std::size_t cell = grid_a.index(col, row);
      if (grid_a.face[cell] < 0) continue;
      const Eigen::Vector2d centre(grid_a.origin_x_m + (static_cast<double>(col) + 0.5) * r,
                                   grid_a.origin_y_m + (static_cast<double>(row) + 0.5) * r);
      if (!region.contains(centre)) continue;
      const double col_b = std::floor((centre.x() - grid_b.origin_x_m) / r);
      const double row_b = std::floor((centre.y() - grid_b.origin_y_m) / r);
      if (col_b < 0 || row_b < 0 || col_b >= static_cast<double>(grid_b.width) ||
          row_b >= static_cast<double>(grid_b.height)) {
        result.only_a_m2 += r * r;
        continue;
      }
      const std::size_t cell_b = grid_b.index(static_cast<std::size_t>(col_b), static_cast<std::size_t>(row_b));
      if (grid_b.face[cell_b] < 0) {
        result.only_a_m2 += r * r;
        continue;
      }
      result.compared_m2 += r * r;
      const traversability::FaceClass a = grid_a.cell_class[cell], b = grid_b.cell_class[cell_b];
      if (a == b) result.agreeing_m2 += r * r;
      if ((a == traversability::FaceClass::kFree) == (b == traversability::FaceClass::kFree)) result.same_free_m2 += r * r;
    }
  }
}

}  // namespace

LayeredMesh ownedPart(const LayeredMesh& map, const TilePlan& plan, std::size_t tile) {
  if (tile >= plan.tiles.size()) {
    throw std::out_of_range("ownedPart: tile " + std::to_string(tile) + " of a plan of " +
                            std::to_string(plan.tiles.size()) + " tiles");
  }
  if (map.layers.size() != map.mesh.faces.size()) {
    throw std::invalid_argument("ownedPart: " + std::to_string(map.layers.size()) + " layer records for " +
                                std::to_string(map.mesh.faces.size()) + " faces");
  }
  const traversability::MapPlane plane = plan.plane();
  std::vector<std::uint8_t> keep(map.mesh.faces.size());
  LayeredMesh owned;
  const bool keyed = map.face_keys.size() == map.mesh.faces.size();
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    const auto& face = map.mesh.faces[f];
    const Eigen::Vector3d centroid =
        (map.mesh.vertices[face[0]] + map.mesh.vertices[face[1]] + map.mesh.vertices[face[2]]) / 3.0;
    keep[f] = plan.ownerOf(plane.planM(centroid)) == tile;
    if (!keep[f]) continue;
    owned.layers.push_back(map.layers[f]);
    if (keyed) owned.face_keys.push_back(map.face_keys[f]);
  }
  owned.mesh = mesher::selectFaces(map.mesh, keep);
  owned.up_W = map.up_W;
  owned.metres_per_unit = map.metres_per_unit;
  return owned;
}

void appendMap(LayeredMesh& into, const LayeredMesh& part) {
  if (into.mesh.faces.empty() && into.mesh.vertices.empty()) {
    into.up_W = part.up_W;
    into.metres_per_unit = part.metres_per_unit;
  } else if (!(into.up_W - part.up_W).isZero(1e-12) || into.metres_per_unit != part.metres_per_unit) {
    throw std::invalid_argument("appendMap: the maps have different frames (up or metres_per_unit)");
  }
  const auto offset = static_cast<std::uint32_t>(into.mesh.vertices.size());
  const std::size_t faces_before = into.mesh.faces.size();
  // A per-vertex or per-face array is kept only while every part has it for all its elements.
  const auto appendAligned = [](auto& target, const auto& source, std::size_t before, std::size_t count) {
    if (target.size() == before && source.size() == count) {
      target.insert(target.end(), source.begin(), source.end());
    } else {
      target.clear();
    }
  };
  const std::size_t part_vertices = part.mesh.vertices.size(), part_faces = part.mesh.faces.size();
  appendAligned(into.mesh.is_steiner, part.mesh.is_steiner, offset, part_vertices);
  appendAligned(into.mesh.driven_kind, part.mesh.driven_kind, offset, part_vertices);
  appendAligned(into.mesh.vertex_keys, part.mesh.vertex_keys, offset, part_vertices);
  appendAligned(into.mesh.face_rays, part.mesh.face_rays, faces_before, part_faces);
  appendAligned(into.mesh.face_front_crossings, part.mesh.face_front_crossings, faces_before, part_faces);
  appendAligned(into.mesh.face_view_sides, part.mesh.face_view_sides, faces_before, part_faces);
  appendAligned(into.mesh.face_back_crossings, part.mesh.face_back_crossings, faces_before, part_faces);
  appendAligned(into.mesh.face_back_depth, part.mesh.face_back_depth, faces_before, part_faces);
  appendAligned(into.face_keys, part.face_keys, faces_before, part_faces);
  into.mesh.vertices.insert(into.mesh.vertices.end(), part.mesh.vertices.begin(), part.mesh.vertices.end());
  for (const auto& face : part.mesh.faces) into.mesh.faces.push_back({face[0] + offset, face[1] + offset, face[2] + offset});
  into.layers.insert(into.layers.end(), part.layers.begin(), part.layers.end());
}

ClassAgreement classAgreement(const LayeredMesh& a, const LayeredMesh& b, const PlanRect& region,
                              const traversability::LevelConfig& levels, double cell_m) {
  if (!(cell_m > 0) || !std::isfinite(cell_m)) throw std::invalid_argument("classAgreement: cell_m must be > 0");
  const traversability::MapPlane plane = traversability::MapPlane::fromUp(a.up_W, a.metres_per_unit);
  const traversability::Levels levels_a = traversability::segmentLevels(a, plane, levels);
  const traversability::Levels levels_b = traversability::segmentLevels(b, plane, levels);
  ClassAgreement result;
  for (std::size_t la = 0; la < levels_a.count(); ++la) {
    std::size_t best = levels_b.count();
    double best_gap = levels.level_separation_m;
    for (std::size_t lb = 0; lb < levels_b.count(); ++lb) {
      const double gap = std::abs(levels_a.mean_height_m[la] - levels_b.mean_height_m[lb]);
      if (gap <= best_gap) {
        best_gap = gap;
        best = lb;
      }
    }
    if (best == levels_b.count()) {
      // A level `b` does not have: all of it is a's alone.
      const LevelGrid alone = traversability::rasterizeLevel(a, plane, levels_a, la, cell_m);
      compareGrids(alone, LevelGrid{}, region, result);
      continue;
    }
    compareGrids(traversability::rasterizeLevel(a, plane, levels_a, la, cell_m),
                 traversability::rasterizeLevel(b, plane, levels_b, best, cell_m), region, result);
  }
  return result;
}

}  // namespace terramesh::tiling

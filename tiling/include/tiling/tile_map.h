#pragma once

// Traversability maps and tiles: the part of a tile's map that it owns, maps joined for the
// overview, and how far two tiles agree where they overlap.
#include <cstddef>

#include "tiling/tile_plan.h"
#include "traversability/layered_mesh.h"
#include "traversability/map_levels.h"

namespace terramesh::tiling {

/// The faces of `map` (a tile's map meshed with its overlap) that tile `tile` owns: those whose
/// centroid's plan position has the tile as TilePlan::ownerOf; with their layers and keys, unused
/// vertices dropped (mesher::selectFaces). Owned parts of all tiles hold every face once.
/// O(V + F).
/// @throw std::out_of_range if `tile` is not a tile of the plan; std::invalid_argument if layers
///        and faces differ in number.
traversability::LayeredMesh ownedPart(const traversability::LayeredMesh& map, const TilePlan& plan, std::size_t tile);

/// Appends `part`'s faces, vertices and layers to `into` (vertices are not welded; the frame is
/// taken from the first part). For the overview of the merged map. O(size of part).
/// @throw std::invalid_argument if `part` has a different up or scale than a non-empty `into`.
void appendMap(traversability::LayeredMesh& into, const traversability::LayeredMesh& part);

/// Plan area over which two maps of one frame were compared, and the part of it where their
/// classes agree.
struct ClassAgreement {
  double compared_m2 = 0;
  double agreeing_m2 = 0;
  /// The part where both are free or both are not: the drivable decision agrees (a lethal and an
  /// unknown cell agree here, not in agreeing_m2).
  double same_free_m2 = 0;
  /// Area in the region where `a` has a face and `b` none (on a's levels), not in compared_m2.
  double only_a_m2 = 0;
  /// agreeing / compared; 1 when nothing was compared.
  double fraction() const { return compared_m2 > 0 ? agreeing_m2 / compared_m2 : 1.0; }
  /// same_free / compared; 1 when nothing was compared.
  double freeFraction() const { return compared_m2 > 0 ? same_free_m2 / compared_m2 : 1.0; }
};

/// Compares the face classes of two maps in the same frame over `region`: both are split into
/// levels (segmentLevels with `levels`) and each level of `a` is paired with the level of `b`
/// nearest in mean height (if within levels.level_separation_m); both are rasterised at `cell_m`
/// (rasterizeLevel, grids aligned to multiples of the cell size), and every cell whose centre
/// lies in `region` and that has a face in both grids counts its area, agreeing if the classes
/// are equal. O(F log F + cells).
/// @throw std::invalid_argument for a bad level config or cell size.
ClassAgreement classAgreement(const traversability::LayeredMesh& a, const traversability::LayeredMesh& b,
                              const PlanRect& region, const traversability::LevelConfig& levels, double cell_m);

}  // namespace terramesh::tiling

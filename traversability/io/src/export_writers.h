#pragma once

// The single-file writers and readers behind writeMapDirectory / readMapDirectory (internal).
#include <filesystem>
#include <string>
#include <vector>

#include "traversability/layered_mesh.h"
#include "traversability/map_levels.h"
#include "traversability/robot_profile.h"

namespace terramesh::traversability::internal {

/// `traversability.ply`: binary little-endian; per vertex x y z (double), steiner (uchar), cost
/// (float); per face vertex_indices, cost, lethal, unknown, slope_deg, step_m, roughness_m,
/// contact, contact_best, clearance_m, lethal_distance_m, rays, steiner. Atomic.
void writeLayeredPly(const std::filesystem::path& path, const LayeredMesh& map);

/// Reads a file written by writeLayeredPly (any PLY encoding). Sets mesh, layers and
/// mesh.is_steiner; face_keys stay empty; up_W and metres_per_unit are left at their defaults.
/// @throw terramesh::InputError naming the file, the element/property missing or the face whose
///        values are invalid.
LayeredMesh readLayeredPly(const std::filesystem::path& path);

/// The mesh group of `traversability.h5` (mesh_map's `mesh_part` / `mesh_working_part`).
inline constexpr const char* kMeshMapPart = "mesh";

/// One per-vertex layer of `traversability.h5` (`vertex_attributes/<name>`, float32 N x 1).
struct VertexLayer {
  std::string name;
  std::vector<float> values;
};

/// The per-vertex layers of `traversability.h5`, in file order: mesh_map's names (height_diff,
/// roughness, steepness, border, clearance, inflation, cost, cost_allow_uncertain), then
/// terramesh's own (lethal, uncertain, unknown, contact, evidence, height_uncertainty_m). Every
/// value follows LayeredMesh::vertexWorst, vertexCost and vertexClass; docs/mesh_navigation.md has
/// the table. mesh_map's layers are never NaN (no data is the worst value: +inf, 0 for clearance).
std::vector<VertexLayer> meshMapVertexLayers(const LayeredMesh& map, const RobotProfile& profile);

/// `traversability.h5`: lvr2's HDF5 MeshIO layout (group `/mesh` with IO = "MeshIO", CLASS =
/// "MeshBuffer"; geometry/vertices float32 N x 3 in the metric plan frame, geometry/face_indices
/// uint32 F x 3, normals, vertex_attributes/<layer> float32 N x 1). Atomic.
/// @throw std::runtime_error naming the file if HDF5 or the write fails.
void writeMeshMapH5(const std::filesystem::path& path, const LayeredMesh& map, const RobotProfile& profile);

/// `map_frame.yaml`: up, metres_per_unit and the plan axes. Atomic.
void writeMapFrame(const std::filesystem::path& path, const MapPlane& plane, const Eigen::Vector3d& up_W);

/// Reads up (normalised) and metres_per_unit back into `map`.
/// @throw terramesh::InputError naming the file and the key.
void readMapFrame(const std::filesystem::path& path, LayeredMesh& map);

/// `<base>.pgm` + `<base>.yaml` (trinary) and `<base>_cost.png` + `<base>_cost.yaml` (scale, grey +
/// alpha, alpha 0 = unknown). Appends the file names to `files`. Atomic.
void writeNav2Maps(const std::filesystem::path& dir, const std::string& base, const LevelGrid& grid,
                   const LayeredMesh& map, const MapPlane& plane, double level_height_m,
                   std::vector<std::string>& files);

/// Names of the GeoTIFF bands, in order.
const std::vector<std::string>& geotiffBandNames();

/// `layers_level_N.tif`: one Float32 band per name of geotiffBandNames(), NaN nodata. Atomic.
void writeLayerGeoTiff(const std::filesystem::path& path, const LevelGrid& grid, const LayeredMesh& map,
                       const MapPlane& plane);

/// The text of `traversability_summary.txt`.
std::string mapSummary(const LayeredMesh& map, const Levels& levels, const std::vector<LevelGrid>& grids);

}  // namespace terramesh::traversability::internal

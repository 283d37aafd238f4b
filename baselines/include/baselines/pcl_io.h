#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "baselines/slam_points.h"
#include "mesher/triangle_mesh.h"
#include "traversability/layered_mesh.h"

namespace terramesh::baselines {

/// Writes `mesh` through a pcl::PolygonMesh with PCL's writers, chosen by extension: `.ply`
/// (binary, pcl::io::savePLYFileBinary), `.obj` (pcl::io::saveOBJFile), `.vtk` (legacy ASCII,
/// pcl::io::saveVTKFile, which needs no VTK library). Vertices are float32 x y z, plus a uchar
/// `steiner` field when the mesh has flags. Written to a temporary file, then renamed.
/// @throw std::invalid_argument for another extension; std::runtime_error if PCL fails to write.
void writeMeshWithPcl(const std::filesystem::path& path, const mesher::TriangleMesh& mesh);

/// Reads a mesh with PCL's readers into a pcl::PolygonMesh and from there into a TriangleMesh:
/// `.ply` (pcl::io::loadPLYFile) and `.obj` (pcl::io::loadOBJFile). Polygons with more than three
/// corners are fanned into triangles. A `steiner` vertex field, when present, fills is_steiner.
/// (`.vtk` cannot be read without the VTK libraries.)
/// @throw terramesh::InputError if the file cannot be read or a polygon indexes a missing vertex;
///        std::invalid_argument for another extension.
mesher::TriangleMesh readMeshWithPcl(const std::filesystem::path& path);

/// Writes SLAM points as a binary PCD of pcl::PointWithViewpoint (x y z vp_x vp_y vp_z, float32):
/// each point's viewpoint is the centre of the camera that observed it (SlamPoints::viewpoints_W),
/// all in the map frame, multiplied by `scale` (1: map units). Temporary file, then rename.
/// @throw std::runtime_error if the file cannot be written.
void writeSlamPointsPcd(const std::filesystem::path& path, const SlamPoints& points, double scale = 1.0);

/// Writes a traversability map as a binary PCD: one point per face at its centroid (map units),
/// fields x y z cost class slope_deg step_m roughness_m contact contact_best clearance_m
/// lethal_distance_m rays steiner (float32, class as in FaceClass: 0 free, 1 lethal, 2 unknown).
/// @throw std::invalid_argument if the map has not one layer per face; std::runtime_error if the
///        file cannot be written.
void writeTraversabilityPcd(const std::filesystem::path& path, const traversability::LayeredMesh& map);

/// A PCD file as PCL's own reader (pcl::PCDReader) sees it: field names and every value as double.
struct PcdContents {
  std::vector<std::string> fields;
  std::size_t width = 0;
  std::size_t height = 0;
  /// values[i][f]: point i, field f.
  std::vector<std::vector<double>> values;
  /// Index of a field, or -1.
  int field(const std::string& name) const;
};

/// Reads a PCD with pcl::PCDReader (fields of any numeric type, count 1).
/// @throw terramesh::InputError if PCL cannot read it.
PcdContents readPcdWithPcl(const std::filesystem::path& path);

}  // namespace terramesh::baselines

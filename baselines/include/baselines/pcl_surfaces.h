#pragma once

#include <string>

#include "baselines/slam_points.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::baselines {

/// PCL's surface reconstructions compared with the mesher.
enum class PclMethod {
  kGreedyProjection,    ///< pcl::GreedyProjectionTriangulation (vertices are the input points)
  kPoisson,             ///< pcl::Poisson (screened Poisson, watertight, with invented parts)
  kMarchingCubesHoppe,  ///< pcl::MarchingCubesHoppe (signed distance to the nearest tangent plane)
};

/// Lower-case name: "greedy", "poisson", "marching-cubes".
const char* toString(PclMethod method);

/// Parameters, all lengths as multiples of the point spacing s (the median distance from a point
/// to its nearest neighbour), so the same config fits metric and unit-less maps.
struct PclSurfaceConfig {
  /// Neighbours of the normal estimate (pcl::NormalEstimation, k nearest).
  int normal_neighbours = 16;
  /// Greedy projection: search radius (in s), mu (max edge length relative to the local spacing),
  /// max nearest neighbours, max surface angle and the min / max triangle angles (degrees).
  double greedy_radius_spacings = 6.0;
  double greedy_mu = 2.5;
  int greedy_max_neighbours = 100;
  double greedy_max_surface_angle_deg = 45.0;
  double greedy_min_angle_deg = 10.0;
  double greedy_max_angle_deg = 120.0;
  /// Poisson: octree depth and minimum samples per node.
  int poisson_depth = 9;
  double poisson_samples_per_node = 1.5;
  /// Marching cubes: cell edge (in s), the largest cell count along any axis (the cell grows to
  /// respect it), and the distance beyond which the field is ignored (in s).
  double mc_cell_spacings = 2.0;
  int mc_max_cells_per_axis = 256;
  double mc_ignore_spacings = 3.0;
  /// Output vertices farther than this (in s) from every input point are flagged unsupported
  /// (TriangleMesh::is_steiner = 1): the accuracy measures and the traversability layers treat
  /// them as the mesher treats its Steiner vertices (not measured).
  double support_spacings = 3.0;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// A reconstruction and what it took.
struct PclSurfaceResult {
  /// Map frame and units; is_steiner flags the unsupported vertices.
  mesher::TriangleMesh mesh;
  /// The point spacing s, map units.
  double spacing_units = 0;
  /// The parameters actually used, in map units, one "name value" pair per entry, for reports.
  std::string parameters;
  double normals_seconds = 0;
  double surface_seconds = 0;
};

/// Median distance from each point to its nearest other point (map units); 0 for fewer than two
/// points. O(N log N).
double medianPointSpacing(const std::vector<Eigen::Vector3d>& points_W);

/// Reconstructs a surface from `points` with PCL. Normals are estimated from the k nearest
/// neighbours and each is flipped towards that point's own viewpoint
/// (pcl::flipNormalTowardsViewpoint with points.viewpoints_W[i]), not one global viewpoint.
/// Faces are wound counter-clockwise seen from the side the normals point to.
/// @throw std::invalid_argument if the config does not validate or there are fewer than
///        normal_neighbours + 1 points.
PclSurfaceResult reconstructWithPcl(const SlamPoints& points, PclMethod method, const PclSurfaceConfig& config);

}  // namespace terramesh::baselines

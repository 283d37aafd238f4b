#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "datasets/lidar_truth.h"
#include "datasets/mesh_evaluation.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::baselines {

/// Manifoldness of a triangle mesh.
struct Manifoldness {
  std::size_t vertices = 0;  ///< referenced by a face
  std::size_t faces = 0;
  std::size_t non_manifold_edges = 0;     ///< edges with more than two faces
  std::size_t non_manifold_vertices = 0;  ///< vertices whose faces form more than one fan
  std::size_t boundary_edges = 0;         ///< edges with exactly one face
  /// Connected pieces of the graph of boundary edges (one per hole or border on a manifold mesh).
  std::size_t boundary_loops = 0;
  std::size_t components = 0;  ///< connected through shared vertices
  /// Sum over components of (2 - chi - b) / 2, chi = V - E + F and b the boundary loops of the
  /// component: the genus of each surface when it is a manifold (a formal value otherwise).
  long genus = 0;
  std::size_t orientation_errors = 0;  ///< directed edges used by more than one face
};

/// Counts the above (mesher::analyzeTopology plus boundary loops and the genus of open
/// components). O(F log F).
Manifoldness measureManifoldness(const mesher::TriangleMesh& mesh);

/// How a surface is compared with the geometric ground truth: the measures of `terramesh eval`.
struct GeometryTruthConfig {
  /// Points sampled on the surface's measured faces (accuracy) and truth ray ends kept
  /// (completeness).
  std::size_t samples = 100000;
  std::uint64_t seed = 1;
  /// LiDAR: a surface sample with no return within this is unmatched.
  double match_radius_m = 2.0;
  datasets::DepthComparisonConfig depth{8, 40.0, 0.5, 20.0};
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// The scores of one surface (see docs/accuracy.md).
struct GeometryScores {
  std::size_t faces = 0;
  std::size_t measured_faces = 0;  ///< not touching a Steiner / unsupported vertex
  datasets::DepthErrors depth;
  datasets::DistanceStats accuracy;      ///< measured-face samples to the truth
  datasets::DistanceStats completeness;  ///< truth ray ends to the measured faces
};

/// The geometric ground truth, prepared once: a surface mesh rendered from views, or KITTI LiDAR.
/// Not thread-safe.
class GeometryTruth {
 public:
  /// @throw std::invalid_argument if the config does not validate or no truth ray is within the
  ///        depth limit of a view.
  static GeometryTruth fromMesh(const mesher::TriangleMesh& truth, const std::vector<datasets::EvaluationView>& views,
                                const GeometryTruthConfig& config);
  /// @throw terramesh::InputError for unreadable scans (datasets::readLidarTruth);
  ///        std::invalid_argument as fromMesh.
  static GeometryTruth fromLidar(const std::filesystem::path& sequence, const datasets::LidarTruthOptions& options,
                                 const GeometryTruthConfig& config);
  ~GeometryTruth();
  GeometryTruth(GeometryTruth&&) noexcept;
  GeometryTruth& operator=(GeometryTruth&&) noexcept;

  std::size_t truthRays() const;

  /// Scores `mesh` (in the truth's frame, metres; its is_steiner flags mark unmeasured vertices).
  /// A mesh with no measured face scores zero samples (NaN-free zeros).
  GeometryScores score(const mesher::TriangleMesh& mesh) const;

 private:
  struct Impl;
  explicit GeometryTruth(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Merges vertices whose coordinates round to the same multiple of `tolerance` (0: identical
/// coordinates only), so a triangle soup becomes an indexed mesh; faces keep their order, faces
/// that collapse (two corners merged) are dropped; is_steiner is kept (a merged vertex is Steiner
/// if any copy was). O(V + F) expected.
/// @throw std::invalid_argument if tolerance is negative or not finite.
mesher::TriangleMesh weldVertices(const mesher::TriangleMesh& mesh, double tolerance = 0);

}  // namespace terramesh::baselines

#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "evaluation/lidar_truth.h"
#include "evaluation/mesh_evaluation.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::evaluation {

/// How a surface is compared with the geometric ground truth: the measures of `terramesh eval`.
struct GeometryTruthConfig {
  /// Points sampled on the surface's measured faces (accuracy) and truth ray ends kept
  /// (completeness).
  std::size_t samples = 100000;
  std::uint64_t seed = 1;
  /// LiDAR: a surface sample with no return within this is unmatched.
  double match_radius_m = 2.0;
  DepthComparisonConfig depth{8, 40.0, 0.5, 20.0};
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// The scores of one surface (see docs/accuracy.md).
struct GeometryScores {
  std::size_t faces = 0;
  std::size_t measured_faces = 0;  ///< not touching a Steiner / unsupported vertex
  DepthErrors depth;
  DistanceStats accuracy;      ///< measured-face samples to the truth
  DistanceStats completeness;  ///< truth ray ends to the measured faces
};

/// The geometric ground truth, prepared once: a surface mesh rendered from views, or KITTI LiDAR.
/// Not thread-safe.
class GeometryTruth {
 public:
  /// @throw std::invalid_argument if the config does not validate or no truth ray is within the
  ///        depth limit of a view.
  static GeometryTruth fromMesh(const mesher::TriangleMesh& truth, const std::vector<EvaluationView>& views,
                                const GeometryTruthConfig& config);
  /// @throw terramesh::InputError for unreadable scans (readLidarTruth);
  ///        std::invalid_argument as fromMesh.
  static GeometryTruth fromLidar(const std::filesystem::path& sequence, const LidarTruthOptions& options,
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

}  // namespace terramesh::evaluation

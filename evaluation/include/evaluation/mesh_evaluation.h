#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "datasets/point_cloud_index.h"
#include "datasets/triangle_bvh.h"
#include "mesher/triangle_mesh.h"

namespace terramesh::evaluation {

/// A pinhole camera (pixels), for rendering depth images. Defaults: KITTI's P0.
struct PinholeCamera {
  int width_px = 1241;
  int height_px = 376;
  double fx_px = 718.856;
  double fy_px = 718.856;
  double cx_px = 607.1928;
  double cy_px = 185.2157;

  /// Unit ray direction through pixel (u, v), in the camera frame (x right, y down, z forward).
  Eigen::Vector3d rayDirection_C(double u, double v) const;
  /// Whether camera-frame point `p_C` projects inside the image (in front of the camera).
  bool sees(const Eigen::Vector3d& p_C) const;
};

/// A viewpoint: camera centre and camera-to-world rotation, in the evaluation frame.
struct EvaluationView {
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation_W_C = Eigen::Quaterniond::Identity();
};

/// A ground-truth depth sample: a ray and how far along it the true surface is.
struct DepthRay {
  Eigen::Vector3d origin_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction_W = Eigen::Vector3d::UnitZ();  ///< unit
  double truth_depth_m = 0.0;                             ///< range along the ray
};

/// Settings of the depth comparison.
struct DepthComparisonConfig {
  int stride_px = 4;                  ///< render every stride-th pixel in each direction
  double max_depth_m = 40.0;          ///< ground-truth samples beyond this are not used
  double coverage_threshold_m = 0.5;  ///< a ray is covered when the error is at most this
  /// Mesh hits farther than the truth by more than this count as misses (the mesh has a hole).
  double max_overshoot_m = 20.0;
};

/// How the reconstruction's depths compare with the truth's, over the ground-truth rays.
struct DepthErrors {
  std::size_t truth_rays = 0;    ///< ground-truth rays used
  std::size_t compared = 0;      ///< ... where the mesh was hit too (errors are over these)
  std::size_t covered = 0;       ///< ... with |error| <= coverage threshold
  std::size_t steiner_hits = 0;  ///< compared rays whose mesh hit is a face touching a Steiner vertex
  double mean_abs_m = 0.0;
  double median_abs_m = 0.0;
  double rmse_m = 0.0;
  double mean_signed_m = 0.0;  ///< mesh depth minus truth: negative = mesh in front of the truth

  /// Fraction of the ground-truth rays the mesh covers within the threshold.
  double coverage() const { return truth_rays ? static_cast<double>(covered) / truth_rays : 0.0; }
};

/// Ground-truth rays from rendering `truth` at each view (every stride-th pixel with a hit within
/// max_depth_m).
std::vector<DepthRay> renderTruthRays(const datasets::TriangleBvh& truth, const std::vector<EvaluationView>& views,
                                      const PinholeCamera& camera, const DepthComparisonConfig& config);

/// Ground-truth rays from an origin to measured points (e.g. LiDAR returns from the sensor),
/// keeping those within max_depth_m.
std::vector<DepthRay> raysToPoints(const Eigen::Vector3d& origin_W, const std::vector<Eigen::Vector3d>& points_W,
                                   const DepthComparisonConfig& config);

/// Casts every ground-truth ray into the reconstruction and compares depths. `is_steiner` flags
/// the reconstruction's vertices (may be empty); faces touching one are counted in steiner_hits.
DepthErrors compareDepths(const datasets::TriangleBvh& reconstruction, const mesher::TriangleMesh& reconstruction_mesh,
                          const std::vector<DepthRay>& truth, const DepthComparisonConfig& config);

/// Distances from sample points to a surface or a point cloud, summarised.
struct DistanceStats {
  std::size_t samples = 0;    ///< points measured
  std::size_t matched = 0;    ///< ... with a neighbour within the search radius (point clouds)
  double mean_m = 0.0;
  double median_m = 0.0;
  double p90_m = 0.0;
  /// Fractions of the samples within 0.1, 0.2, 0.25 and 0.5 m (kThresholdsM; index with kWithin*).
  std::array<double, 4> within{};
  static constexpr std::array<double, 4> kThresholdsM = {0.1, 0.2, 0.25, 0.5};
  static constexpr std::size_t kWithin10cm = 0, kWithin20cm = 1, kWithin25cm = 2, kWithin50cm = 3;
};

/// `count` points spread uniformly by area over the faces of `mesh` (fixed `seed`); with
/// `skip_steiner`, faces touching a Steiner vertex are left out.
std::vector<Eigen::Vector3d> sampleSurface(const mesher::TriangleMesh& mesh, std::size_t count,
                                           std::uint64_t seed, bool skip_steiner);

/// Distance from each sample to the nearest point of the surface in `surface`.
DistanceStats distancesToSurface(const std::vector<Eigen::Vector3d>& samples, const datasets::TriangleBvh& surface);

/// Distance from each sample to the nearest cloud point within `max_distance_m` (samples with
/// none are unmatched and count as beyond every threshold).
DistanceStats distancesToPoints(const std::vector<Eigen::Vector3d>& samples, const datasets::PointCloudIndex& cloud,
                                double max_distance_m);

}  // namespace terramesh::evaluation

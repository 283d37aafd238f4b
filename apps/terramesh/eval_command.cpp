// terramesh eval MESH: the accuracy of a mesh against ground truth (a mesh or KITTI LiDAR scans).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "common/input_error.h"
#include "datasets/kitti_odometry_reader.h"
#include "evaluation/lidar_truth.h"
#include "evaluation/mesh_evaluation.h"
#include "datasets/similarity_transform.h"
#include "datasets/triangle_bvh.h"
#include "mesher/mesh_io.h"
#include "run_extras.h"

namespace terramesh::cli {
namespace {

using evaluation::DepthComparisonConfig;
using evaluation::DepthErrors;
using evaluation::DistanceStats;

/// The parsed command line.
struct EvalOptions {
  std::string mesh;
  std::optional<std::string> gt_mesh, views, gt_lidar, poses, sim3, report;
  /// Without --views or a trajectory.txt beside the truth: the run's own trajectory.csv beside MESH.
  std::optional<std::string> run_trajectory;
  std::string frames = "0:10";
  std::optional<double> steiner_grid_step;
  std::size_t stride_px = 8;
  std::size_t view_step = 1;
  double max_depth_m = 40;
  double coverage_m = 0.5;
  std::size_t samples = 200000;
  double match_radius_m = 2;
  std::uint64_t seed = 1;
  bool quiet = false;
};

void declareOptions(CLI::App& app, EvalOptions& o) {
  const auto positive = positiveNumber();
  app.add_option("MESH", o.mesh, "the mesh to evaluate (PLY, OBJ or OFF; its `steiner` flags are used when present)")
      ->required();
  app.add_option("--gt-mesh", o.gt_mesh, "ground truth: a surface mesh (e.g. ground_truth.ply of terramesh generate)")
      ->option_text("FILE");
  app.add_option("--views", o.views,
                 "with --gt-mesh: camera poses to render depth from (KITTI format; default: trajectory.txt beside "
                 "the truth, as terramesh generate writes it, else the keyframes of trajectory.csv beside MESH, "
                 "as terramesh mesh writes it)")
      ->option_text("FILE");
  app.add_option("--gt-lidar", o.gt_lidar, "ground truth: a KITTI odometry sequence (velodyne/*.bin, calib.txt)")
      ->option_text("DIR");
  app.add_option("--poses", o.poses, "with --gt-lidar: its KITTI poses (cam0-to-world)")->option_text("FILE");
  app.add_option("--frames", o.frames, "with --gt-lidar: scans of frames A to B (inclusive)")->option_text("A:B");
  app.add_option("--steiner-grid-step", o.steiner_grid_step,
                 "mark as Steiner the vertices whose coordinates are all multiples of S (mesh units, before "
                 "--sim3): for meshes without `steiner` flags, such as the authors' reference .off files")
      ->option_text("S")
      ->check(positive);
  app.add_option("--sim3", o.sim3, "map MESH into the ground truth's frame by x' = s R x + t (s, R, t lines)")
      ->option_text("FILE");
  app.add_option("--stride-px", o.stride_px, "with --gt-mesh: render every N-th pixel in each direction")->check(positive);
  app.add_option("--view-step", o.view_step, "with --gt-mesh: use every N-th view")->check(positive);
  app.add_option("--max-depth-m", o.max_depth_m, "ground truth beyond D metres from the sensor is not used")
      ->check(positive);
  app.add_option("--coverage-m", o.coverage_m, "a ground-truth ray is covered when the mesh depth is within E")
      ->check(positive);
  app.add_option("--samples", o.samples, "surface samples each way for accuracy and completeness")->check(positive);
  app.add_option("--match-radius-m", o.match_radius_m,
                 "with --gt-lidar: a mesh sample with no return within R is unmatched")
      ->check(positive);
  app.add_option("--seed", o.seed, "seed of the surface sampling")->check(nonNegativeNumber());
  app.add_option("--report", o.report, "also write the report to FILE (atomically)")->option_text("FILE");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
}

/// "A:B" -> {A, B}, inclusive.
std::pair<std::size_t, std::size_t> parseInclusiveRange(const std::string& text) {
  const auto fields = parseColonIntegers(text, "eval: --frames", "A:B", 2);
  if (fields.size() != 2 || !fields[0] || !fields[1]) {
    throw UsageError("eval: --frames expects A:B with non-negative integers, got \"" + text + "\"");
  }
  if (*fields[1] < *fields[0]) throw UsageError("eval: --frames A:B needs A <= B, got \"" + text + "\"");
  return {*fields[0], *fields[1]};
}

/// Every `step`-th element of `points`, at most about `count` of them.
std::vector<Eigen::Vector3d> thin(const std::vector<Eigen::Vector3d>& points, std::size_t count) {
  const std::size_t step = std::max<std::size_t>(1, (points.size() + count - 1) / std::max<std::size_t>(1, count));
  std::vector<Eigen::Vector3d> kept;
  for (std::size_t i = 0; i < points.size(); i += step) kept.push_back(points[i]);
  return kept;
}

std::vector<Eigen::Vector3d> rayEnds(const std::vector<evaluation::DepthRay>& rays) {
  std::vector<Eigen::Vector3d> ends;
  ends.reserve(rays.size());
  for (const auto& ray : rays) ends.push_back(ray.origin_W + ray.truth_depth_m * ray.direction_W);
  return ends;
}

std::string fixed(double value, int digits = 3) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

void reportDistances(std::ostream& out, const std::string& prefix, const DistanceStats& stats) {
  out << prefix << "_samples " << stats.samples << '\n'
      << prefix << "_matched " << stats.matched << '\n'
      << prefix << "_mean_m " << fixed(stats.mean_m) << '\n'
      << prefix << "_median_m " << fixed(stats.median_m) << '\n'
      << prefix << "_p90_m " << fixed(stats.p90_m) << '\n';
  for (std::size_t t = 0; t < DistanceStats::kThresholdsM.size(); ++t) {
    out << prefix << "_within_" << fixed(DistanceStats::kThresholdsM[t], 2) << "m " << fixed(stats.within[t]) << '\n';
  }
}

/// Flags the vertices lying on the grid of step `step` (all three coordinates multiples of it).
void markGridVertices(mesher::TriangleMesh& mesh, double step) {
  mesh.is_steiner.assign(mesh.vertices.size(), 0);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Eigen::Vector3d cells = mesh.vertices[v] / step;
    const double off_grid = (cells - cells.array().round().matrix()).cwiseAbs().maxCoeff();
    mesh.is_steiner[v] = off_grid < 1e-6;
  }
}

std::vector<evaluation::EvaluationView> readViews(const std::filesystem::path& path, std::size_t step) {
  std::vector<evaluation::EvaluationView> views;
  const std::vector<Eigen::Isometry3d> poses = datasets::readKittiPoses(path);
  for (std::size_t i = 0; i < poses.size(); i += step) {
    views.push_back({poses[i].translation(), Eigen::Quaterniond(poses[i].linear())});
  }
  return views;
}

/// The keyframes of a run's trajectory.csv as views, mapped like the mesh (--sim3), every step-th.
std::vector<evaluation::EvaluationView> readRunViews(const EvalOptions& options, std::size_t step) {
  const std::vector<TrajectoryRow> rows = readTrajectoryCsv(*options.run_trajectory);
  std::optional<datasets::SimilarityTransform> sim3;
  if (options.sim3) sim3 = datasets::readSimilarityTransform(*options.sim3);
  std::vector<evaluation::EvaluationView> views;
  for (std::size_t i = 0; i < rows.size(); i += step) {
    const TrajectoryRow& row = rows[i];
    views.push_back({sim3 ? sim3->apply(row.position_W) : row.position_W,
                     sim3 ? sim3->apply(row.rotation_W_C) : row.rotation_W_C});
  }
  return views;
}

/// Checks the truth options; without --views, the views of --gt-mesh are the trajectory.txt that
/// `terramesh generate` writes beside it, else the keyframes of the trajectory.csv that `terramesh
/// mesh` writes beside MESH (said on stderr).
/// @throw UsageError for a missing or contradictory option.
void resolveTruthOptions(EvalOptions& options) {
  const bool lidar = options.gt_lidar.has_value();
  if (lidar == options.gt_mesh.has_value()) throw UsageError("eval: give exactly one of --gt-mesh and --gt-lidar");
  if (!lidar && !options.views) {
    const std::filesystem::path beside = std::filesystem::path(*options.gt_mesh).parent_path() / "trajectory.txt";
    const std::filesystem::path run = std::filesystem::path(options.mesh).parent_path() / "trajectory.csv";
    if (std::filesystem::is_regular_file(beside)) {
      options.views = beside.string();
      if (!options.quiet) std::cerr << "eval: views: " << beside.string() << ", beside the truth (--views overrides)\n";
    } else if (std::filesystem::is_regular_file(run)) {
      options.run_trajectory = run.string();
      if (!options.quiet) {
        std::cerr << "eval: views: the keyframes of " << run.string() << ", beside the mesh"
                  << (options.sim3 ? " (mapped by --sim3)" : "") << " (--views overrides)\n";
      }
    } else {
      throw UsageError("eval: --gt-mesh needs --views FILE (no trajectory.txt beside " + *options.gt_mesh +
                       ", no trajectory.csv beside " + options.mesh + ")");
    }
  }
  if (lidar && !options.poses) throw UsageError("eval: --gt-lidar needs --poses FILE");
  if (!lidar && options.poses) throw UsageError("eval: --poses goes with --gt-lidar (use --views)");
}

/// The mesh in the truth's frame, its measured part (no face touching a Steiner vertex) and samples
/// of that part.
struct EvalMesh {
  mesher::TriangleMesh mesh, measured;
  bool flagged = false;  ///< whether the mesh says which vertices are Steiner vertices
  std::vector<Eigen::Vector3d> samples;
};

/// @throw InputError naming the mesh file when it has no (measured) face.
EvalMesh loadMesh(const EvalOptions& options) {
  EvalMesh m;
  const std::string path = std::filesystem::path(options.mesh).string();
  m.mesh = mesher::readMesh(options.mesh);
  if (m.mesh.faces.empty()) throw InputError(path, "faces", "the mesh has no faces");
  if (options.steiner_grid_step) markGridVertices(m.mesh, *options.steiner_grid_step);
  if (options.sim3) m.mesh = datasets::readSimilarityTransform(*options.sim3).apply(m.mesh);
  m.flagged = m.mesh.is_steiner.size() == m.mesh.vertices.size();
  m.measured = m.flagged ? mesher::dropSteinerFaces(m.mesh) : m.mesh;
  if (m.measured.faces.empty()) throw InputError(path, "faces", "every face touches a Steiner vertex");
  m.samples = evaluation::sampleSurface(m.measured, options.samples, options.seed, false);
  return m;
}

/// The ground-truth rays (LiDAR returns seen by cam0, or pixels of the truth mesh rendered from the
/// views) and the distances from the mesh's samples to the truth; appends the truth's lines to
/// `report`.
std::vector<evaluation::DepthRay> readTruth(const EvalOptions& options, const DepthComparisonConfig& config,
                                            const evaluation::PinholeCamera& camera,
                                            const std::vector<Eigen::Vector3d>& samples, DistanceStats& accuracy,
                                            std::ostream& report) {
  if (options.gt_lidar) {
    evaluation::LidarTruthOptions lidar_options;
    lidar_options.poses_path = *options.poses;
    std::tie(lidar_options.first_frame, lidar_options.last_frame) = parseInclusiveRange(options.frames);
    evaluation::LidarTruth truth = evaluation::readLidarTruth(*options.gt_lidar, lidar_options, camera, config);
    std::vector<Eigen::Vector3d> covered_samples;
    for (const Eigen::Vector3d& p : samples) {
      if (truth.covers(p, config.max_depth_m, &camera)) covered_samples.push_back(p);
    }
    const datasets::PointCloudIndex cloud(truth.returns_W);
    accuracy = evaluation::distancesToPoints(covered_samples, cloud, options.match_radius_m);
    report << "truth lidar " << *options.gt_lidar << " frames " << options.frames << '\n'
           << "truth_scans " << truth.world_from_sensor.size() << '\n'
           << "truth_returns " << truth.returns_read << '\n'
           << "mesh_samples_in_lidar_coverage " << covered_samples.size() << " of " << samples.size() << '\n';
    return std::move(truth.rays);
  }
  const mesher::TriangleMesh truth_mesh = mesher::readMesh(*options.gt_mesh);
  const datasets::TriangleBvh truth_bvh(truth_mesh);
  const auto views =
      options.run_trajectory ? readRunViews(options, options.view_step) : readViews(*options.views, options.view_step);
  std::vector<evaluation::DepthRay> rays = evaluation::renderTruthRays(truth_bvh, views, camera, config);
  accuracy = evaluation::distancesToSurface(samples, truth_bvh);
  report << "truth mesh " << *options.gt_mesh << '\n' << "truth_views " << views.size() << '\n';
  return rays;
}

}  // namespace

int runEval(const std::vector<std::string>& args) {
  CLI::App app{"mesh accuracy against a ground-truth mesh or KITTI LiDAR", "terramesh eval"};
  app.option_defaults()->always_capture_default();
  app.footer(
      "Depth: every ground-truth ray (a rendered pixel of --gt-mesh from each view, or a LiDAR "
                 "return seen by cam0, from the sensor) is cast into MESH; errors are mesh depth minus true "
                 "depth over the rays that hit it, coverage the fraction of all rays within --coverage-m.\n"
                 "Accuracy: samples of MESH's measured faces (none touching a Steiner vertex) to the truth "
                 "(the surface, or the nearest LiDAR return; with LiDAR only samples a scan could have "
                 "measured). Completeness: ground-truth ray ends to MESH's measured faces.");
  EvalOptions options;
  declareOptions(app, options);
  if (!parseCommandLine(app, args)) return kExitOk;
  resolveTruthOptions(options);
  DepthComparisonConfig config;
  config.stride_px = static_cast<int>(options.stride_px);
  config.max_depth_m = options.max_depth_m;
  config.coverage_threshold_m = options.coverage_m;
  const evaluation::PinholeCamera camera;

  // The mesh, in the ground truth's frame.
  const EvalMesh m = loadMesh(options);
  const datasets::TriangleBvh mesh_bvh(m.mesh);
  const datasets::TriangleBvh measured_bvh(m.measured);
  std::ostringstream report;
  report << "mesh " << std::filesystem::path(options.mesh).string() << '\n'
         << "mesh_vertices " << m.mesh.vertices.size() << '\n'
         << "mesh_steiner_vertices "
         << (m.flagged ? std::to_string(std::count(m.mesh.is_steiner.begin(), m.mesh.is_steiner.end(), 1)) : "unknown")
         << '\n'
         << "mesh_faces " << m.mesh.faces.size() << '\n'
         << "mesh_measured_faces " << m.measured.faces.size() << '\n';
  DistanceStats accuracy;
  const std::vector<evaluation::DepthRay> truth_rays = readTruth(options, config, camera, m.samples, accuracy, report);
  if (truth_rays.empty()) throw UsageError("eval: no ground-truth ray within " + fixed(config.max_depth_m, 1) + " m of a view");
  const DepthErrors depth = evaluation::compareDepths(mesh_bvh, m.mesh, truth_rays, config);
  const DistanceStats completeness =
      evaluation::distancesToSurface(thin(rayEnds(truth_rays), options.samples), measured_bvh);

  report << "depth_truth_rays " << depth.truth_rays << '\n'
         << "depth_rays_hitting_mesh " << depth.compared << '\n'
         << "depth_hits_on_steiner_faces " << depth.steiner_hits << '\n'
         << "depth_mean_abs_error_m " << fixed(depth.mean_abs_m) << '\n'
         << "depth_median_abs_error_m " << fixed(depth.median_abs_m) << '\n'
         << "depth_rmse_m " << fixed(depth.rmse_m) << '\n'
         << "depth_mean_signed_error_m " << fixed(depth.mean_signed_m) << '\n'
         << "depth_coverage_within_" << fixed(config.coverage_threshold_m, 2) << "m " << fixed(depth.coverage())
         << '\n';
  reportDistances(report, "accuracy", accuracy);
  reportDistances(report, "completeness", completeness);

  if (options.report) writeFileAtomically(*options.report, report.str());
  if (!options.quiet) std::cout << report.str();
  return kExitOk;
}

}  // namespace terramesh::cli

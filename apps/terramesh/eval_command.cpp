// terramesh eval MESH: the accuracy of a mesh against ground truth (a mesh or KITTI LiDAR scans).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "common/input_error.h"
#include "datasets/kitti_odometry_reader.h"
#include "datasets/lidar_truth.h"
#include "datasets/mesh_evaluation.h"
#include "datasets/similarity_transform.h"
#include "datasets/triangle_bvh.h"
#include "mesher/mesh_io.h"

namespace terramesh::cli {
namespace {

using datasets::DepthComparisonConfig;
using datasets::DepthErrors;
using datasets::DistanceStats;

void declareOptions(ArgParser& parser) {
  parser.positional("MESH", "the mesh to evaluate (PLY, OBJ or OFF; its `steiner` flags are used when present)")
      .option("--gt-mesh", "FILE", "ground truth: a surface mesh (e.g. ground_truth.ply of terramesh generate)")
      .option("--views", "FILE", "with --gt-mesh: camera poses to render depth from (KITTI format, e.g. trajectory.txt)")
      .option("--gt-lidar", "DIR", "ground truth: a KITTI odometry sequence (velodyne/*.bin, calib.txt)")
      .option("--poses", "FILE", "with --gt-lidar: its KITTI poses (cam0-to-world)")
      .option("--frames", "A:B", "with --gt-lidar: scans of frames A to B (inclusive)", "0:10")
      .option("--steiner-grid-step", "S",
              "mark as Steiner the vertices whose coordinates are all multiples of S (mesh units, before "
              "--sim3): for meshes without `steiner` flags, such as the authors' reference .off files")
      .option("--sim3", "FILE", "map MESH into the ground truth's frame by x' = s R x + t (s, R, t lines)")
      .option("--stride-px", "N", "with --gt-mesh: render every N-th pixel in each direction", "8")
      .option("--view-step", "N", "with --gt-mesh: use every N-th view", "1")
      .option("--max-depth-m", "D", "ground truth beyond D metres from the sensor is not used", "40")
      .option("--coverage-m", "E", "a ground-truth ray is covered when the mesh depth is within E", "0.5")
      .option("--samples", "N", "surface samples each way for accuracy and completeness", "200000")
      .option("--match-radius-m", "R", "with --gt-lidar: a mesh sample with no return within R is unmatched", "2")
      .option("--seed", "N", "seed of the surface sampling", "1")
      .option("--report", "FILE", "also write the report to FILE (atomically)")
      .flag("--quiet", "print nothing but errors");
}

std::size_t positiveCount(const ArgParser& parser, const std::string& name) {
  const long value = parser.getInt(name);
  if (value < 1) throw UsageError("eval: " + name + " must be >= 1");
  return static_cast<std::size_t>(value);
}

double positiveReal(const ArgParser& parser, const std::string& name) {
  const double value = parser.getDouble(name);
  if (!(value > 0)) throw UsageError("eval: " + name + " must be > 0");
  return value;
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

std::vector<Eigen::Vector3d> rayEnds(const std::vector<datasets::DepthRay>& rays) {
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

std::vector<datasets::EvaluationView> readViews(const std::filesystem::path& path, std::size_t step) {
  std::vector<datasets::EvaluationView> views;
  const std::vector<Eigen::Isometry3d> poses = datasets::readKittiPoses(path);
  for (std::size_t i = 0; i < poses.size(); i += step) {
    views.push_back({poses[i].translation(), Eigen::Quaterniond(poses[i].linear())});
  }
  return views;
}

}  // namespace

int runEval(const std::vector<std::string>& args) {
  ArgParser parser("eval");
  declareOptions(parser);
  parser.parse(args);
  if (parser.helpRequested()) {
    std::cout << parser.usage()
              << "\nDepth: every ground-truth ray (a rendered pixel of --gt-mesh from each view, or a LiDAR "
                 "return seen by cam0, from the sensor) is cast into MESH; errors are mesh depth minus true "
                 "depth over the rays that hit it, coverage the fraction of all rays within --coverage-m.\n"
                 "Accuracy: samples of MESH's measured faces (none touching a Steiner vertex) to the truth "
                 "(the surface, or the nearest LiDAR return; with LiDAR only samples a scan could have "
                 "measured). Completeness: ground-truth ray ends to MESH's measured faces.\n";
    return kExitOk;
  }
  const bool lidar = parser.has("--gt-lidar");
  if (lidar == parser.has("--gt-mesh")) throw UsageError("eval: give exactly one of --gt-mesh and --gt-lidar");
  if (!lidar && !parser.has("--views")) throw UsageError("eval: --gt-mesh needs --views FILE");
  if (lidar && !parser.has("--poses")) throw UsageError("eval: --gt-lidar needs --poses FILE");
  if (!lidar && parser.has("--poses")) throw UsageError("eval: --poses goes with --gt-lidar (use --views)");

  DepthComparisonConfig config;
  config.stride_px = static_cast<int>(positiveCount(parser, "--stride-px"));
  config.max_depth_m = positiveReal(parser, "--max-depth-m");
  config.coverage_threshold_m = positiveReal(parser, "--coverage-m");
  const std::size_t sample_count = positiveCount(parser, "--samples");
  const double match_radius_m = positiveReal(parser, "--match-radius-m");
  const auto seed = static_cast<std::uint64_t>(parser.getInt("--seed"));
  const datasets::PinholeCamera camera;

  // The mesh, in the ground truth's frame.
  const std::filesystem::path mesh_path = parser.positionalValue("MESH");
  mesher::TriangleMesh mesh = mesher::readMesh(mesh_path);
  if (mesh.faces.empty()) throw InputError(mesh_path.string(), "faces", "the mesh has no faces");
  if (parser.has("--steiner-grid-step")) markGridVertices(mesh, positiveReal(parser, "--steiner-grid-step"));
  if (parser.has("--sim3")) mesh = datasets::readSimilarityTransform(parser.get("--sim3")).apply(mesh);
  const bool flagged = mesh.is_steiner.size() == mesh.vertices.size();
  const mesher::TriangleMesh measured = flagged ? mesher::dropSteinerFaces(mesh) : mesh;
  const datasets::TriangleBvh mesh_bvh(mesh);
  if (measured.faces.empty()) throw InputError(mesh_path.string(), "faces", "every face touches a Steiner vertex");
  const datasets::TriangleBvh measured_bvh(measured);
  const std::vector<Eigen::Vector3d> mesh_samples = datasets::sampleSurface(measured, sample_count, seed, false);

  std::ostringstream report;
  report << "mesh " << mesh_path.string() << '\n'
         << "mesh_vertices " << mesh.vertices.size() << '\n'
         << "mesh_steiner_vertices "
         << (flagged ? std::to_string(std::count(mesh.is_steiner.begin(), mesh.is_steiner.end(), 1)) : "unknown")
         << '\n'
         << "mesh_faces " << mesh.faces.size() << '\n'
         << "mesh_measured_faces " << measured.faces.size() << '\n';
  std::vector<datasets::DepthRay> truth_rays;
  DistanceStats accuracy;
  if (lidar) {
    datasets::LidarTruthOptions options;
    options.poses_path = parser.get("--poses");
    std::tie(options.first_frame, options.last_frame) = parseInclusiveRange(parser.get("--frames"));
    datasets::LidarTruth truth = datasets::readLidarTruth(parser.get("--gt-lidar"), options, camera, config);
    truth_rays = std::move(truth.rays);
    std::vector<Eigen::Vector3d> covered_samples;
    for (const Eigen::Vector3d& p : mesh_samples) {
      if (truth.covers(p, config.max_depth_m, &camera)) covered_samples.push_back(p);
    }
    const datasets::PointCloudIndex cloud(truth.returns_W, 0.5);
    accuracy = datasets::distancesToPoints(covered_samples, cloud, match_radius_m);
    report << "truth lidar " << parser.get("--gt-lidar") << " frames " << parser.get("--frames") << '\n'
           << "truth_scans " << truth.world_from_sensor.size() << '\n'
           << "truth_returns " << truth.returns_read << '\n'
           << "mesh_samples_in_lidar_coverage " << covered_samples.size() << " of " << mesh_samples.size() << '\n';
  } else {
    const mesher::TriangleMesh truth_mesh = mesher::readMesh(parser.get("--gt-mesh"));
    const datasets::TriangleBvh truth_bvh(truth_mesh);
    const auto views = readViews(parser.get("--views"), positiveCount(parser, "--view-step"));
    truth_rays = datasets::renderTruthRays(truth_bvh, views, camera, config);
    accuracy = datasets::distancesToSurface(mesh_samples, truth_bvh);
    report << "truth mesh " << parser.get("--gt-mesh") << '\n'
           << "truth_views " << views.size() << '\n';
  }
  if (truth_rays.empty()) throw UsageError("eval: no ground-truth ray within " + fixed(config.max_depth_m, 1) + " m of a view");
  const DepthErrors depth = datasets::compareDepths(mesh_bvh, mesh, truth_rays, config);
  const DistanceStats completeness =
      datasets::distancesToSurface(thin(rayEnds(truth_rays), sample_count), measured_bvh);

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

  if (parser.has("--report")) writeFileAtomically(parser.get("--report"), report.str());
  if (!parser.flagSet("--quiet")) std::cout << report.str();
  return kExitOk;
}

}  // namespace terramesh::cli

// terramesh traverse-eval MAP_DIR: a traversability map against per-robot ground truth (a
// labelled mesh of terramesh generate) or, on real data, against the road under the camera path.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <variant>

#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "common/input_error.h"
#include "common/plan_frame.h"
#include "datasets/kitti_odometry_reader.h"
#include "datasets/labeled_mesh.h"
#include "datasets/similarity_transform.h"
#include "datasets/stream_reader.h"
#include "datasets/tum_trajectory.h"
#include "evaluation/ground_truth_traversability.h"
#include "evaluation/mesh_refinement.h"
#include "evaluation/road_under_path.h"
#include "evaluation/robot_limits.h"
#include "evaluation/traversability_score.h"
#include "evaluation/truth_checker.h"
#include "mesh_frame_hints.h"
#include "mesher/mesh_io.h"
#include "run_extras.h"
#include "traversability/layer_registry.h"
#include "traversability/map_directory.h"

namespace terramesh::cli {
namespace {

/// The parsed command line.
struct TraverseEvalOptions {
  std::string map_dir;
  std::optional<std::string> gt_mesh, gt_up, sim3, road_under_path, lidar_ground, lidar_sim3, report;
  std::vector<std::string> paths;
  double max_distance_m = 0.5;
  double gt_max_edge_m = 0.25;
  double sample_edge_m = 0.25;
  std::optional<double> camera_height_m;
  double lateral_m = 1.5;
  double height_tolerance_m = 0.5;
  bool quiet = false;
};

void declareOptions(CLI::App& app, TraverseEvalOptions& o) {
  const auto non_negative = nonNegativeNumber();
  app.add_option("MAP_DIR", o.map_dir, "a map directory (traversability.ply, robot.yaml, map_frame.yaml)")->required();
  app.add_option("--gt-mesh", o.gt_mesh, "ground truth: a labelled mesh (ground_truth.ply of terramesh generate)")
      ->option_text("FILE");
  app.add_option("--gt-up", o.gt_up, "with --gt-mesh: the truth's up vector (default: from its level faces)")
      ->option_text("X,Y,Z");
  app.add_option("--sim3", o.sim3, "with --gt-mesh: map the map into the truth's frame by x' = s R x + t")
      ->option_text("FILE");
  app.add_option("--max-distance-m", o.max_distance_m,
                 "with --gt-mesh: map surface farther than D from the truth is not scored")
      ->check(non_negative);
  app.add_option("--gt-max-edge-m", o.gt_max_edge_m, "with --gt-mesh: truth faces are split to edges <= E and judged each")
      ->check(non_negative);
  app.add_option("--sample-edge-m", o.sample_edge_m, "map faces are split to edges <= E, each piece judged at its centroid")
      ->check(non_negative);
  app.add_option("--road-under-path", o.road_under_path,
                 "real data: the map's classes on the road under the keyframe centres of "
                 "STREAM (map units), of a run's trajectory.csv, or of every pose of a KITTI or "
                 "TUM pose file (.txt; frames.txt of terramesh generate: the camera's true path, "
                 "frame by frame); without a value (after MAP_DIR), MAP_DIR/trajectory.csv")
      ->option_text("[STREAM]")
      ->expected(0, 1);
  app.add_option("--camera-height-m", o.camera_height_m,
                 "with --road-under-path: the road lies H below the camera (default: the sensor height MAP_DIR/mesh.ply "
                 "records, else KITTI's 1.65)")
      ->check(non_negative);
  app.add_option("--lateral-m", o.lateral_m, "with --road-under-path: map surface within L of the path, horizontally")
      ->check(non_negative);
  app.add_option("--height-tolerance-m", o.height_tolerance_m, "with --road-under-path: ... and within H +- T below it")
      ->check(non_negative);
  app.add_option("--path", o.paths,
                 "with --gt-mesh: also check these planned paths (path.csv of terramesh plan, map frame) against "
                 "the truth with planner_demo's strict check")
      ->option_text("FILE ...");
  app.add_option("--lidar-ground", o.lidar_ground,
                 "with --road-under-path: measured points (a PLY of LiDAR returns) to check the map under the "
                 "path against")
      ->option_text("PLY");
  app.add_option("--lidar-sim3", o.lidar_sim3,
                 "with --lidar-ground: the similarity x_lidar = s R x_map + t between the map and the points' frame "
                 "(default: the same frame)")
      ->option_text("FILE");
  app.add_option("--report", o.report, "also write the report to FILE (atomically)")->option_text("FILE");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
}

std::string fixed(double value, int digits = 4) {
  if (std::isnan(value)) return "nan";
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

Eigen::Vector3d parseVector(const std::string& text, const std::string& option) {
  Eigen::Vector3d v;
  char a = 0, b = 0;
  std::istringstream in(text);
  if (!(in >> v.x() >> a >> v.y() >> b >> v.z()) || a != ',' || b != ',' || !v.allFinite() || v.norm() == 0) {
    throw UsageError("traverse-eval: " + option + " expects X,Y,Z (non-zero), got \"" + text + "\"");
  }
  return v.normalized();
}

std::string labelName(std::size_t label) {
  return std::string(datasets::toString(static_cast<datasets::SurfaceLabel>(label)));
}

void reportAreas(std::ostream& out, const std::string& prefix, const evaluation::ClassAreas& areas) {
  out << prefix << "_free_m2 " << fixed(areas.free_m2, 3) << '\n'
      << prefix << "_lethal_m2 " << fixed(areas.lethal_m2, 3) << '\n'
      << prefix << "_unknown_m2 " << fixed(areas.unknown_m2, 3) << '\n'
      << prefix << "_uncertain_m2 " << fixed(areas.uncertain_m2, 3) << '\n';
}

/// One line per reason bit (traversability/layer_registry.h): the share under the path whose map
/// face has it, e.g. "road_reason_possible_step_fraction 0.0123".
void reportReasons(std::ostream& out, const std::string& prefix,
                   const std::array<double, traversability::reason::kCount>& fractions) {
  const std::vector<const char*>& names = traversability::reason::names();
  for (std::size_t b = 0; b < fractions.size(); ++b) {
    out << prefix << "_reason_" << names[b] << "_fraction " << fixed(fractions[b]) << '\n';
  }
}

void reportRobot(std::ostream& out, const evaluation::RobotLimits& robot) {
  out << "robot " << robot.name << '\n'
      << "robot_footprint_radius_m " << fixed(robot.footprint_radius_m, 3) << '\n'
      << "robot_max_slope_deg " << fixed(robot.max_slope_deg, 2) << '\n'
      << "robot_max_step_m " << fixed(robot.max_step_m, 3) << '\n'
      << "robot_height_m " << fixed(robot.height_m, 3) << '\n';
}

/// Why the map calls a face what it does: free, unknown, or the first of the profile's limits a
/// lethal face exceeds (a diagnosis of false negatives; the map's own layers, not the truth).
const char* const kGroupNames[] = {"free",    "unknown",   "slope", "step",     "roughness",
                                   "contact", "clearance", "other", "uncertain"};

std::vector<std::uint8_t> lethalCauses(const traversability::LayeredMesh& map,
                                       const traversability::RobotProfile& profile) {
  std::vector<std::uint8_t> groups;
  groups.reserve(map.layers.size());
  for (const traversability::FaceLayers& l : map.layers) {
    std::uint8_t group = 7;
    if (l.face_class == traversability::FaceClass::kFree) group = 0;
    else if (l.face_class == traversability::FaceClass::kUnknown) group = 1;
    else if (l.face_class == traversability::FaceClass::kUncertain) group = 8;
    else if (l.slope_deg > profile.max_slope_deg) group = 2;
    else if (l.step_m > profile.max_step_m) group = 3;
    else if (l.roughness_m > profile.max_roughness_m) group = 4;
    else if (l.contact < profile.min_support) group = 5;
    else if (l.clearance_m < profile.min_clearance_m) group = 6;
    groups.push_back(group);
  }
  return groups;
}

/// The x, y, z (and yaw) columns of a path.csv of terramesh plan.
struct PathCsv {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> yaws;  ///< radians, when `with_yaw`
};

/// A path.csv: a header line naming x, y and z first (and yaw fourth, when `with_yaw`), then one
/// finite point per line.
/// @throw InputError naming the file and line.
PathCsv readPathCsv(const std::string& file, bool with_yaw) {
  std::ifstream in(file);
  if (!in) throw InputError(file, "file", "cannot open the path");
  std::string line;
  const std::string header = with_yaw ? "x,y,z,yaw" : "x,y,z";
  if (!std::getline(in, line) || line.rfind(header, 0) != 0) {
    const std::string why = with_yaw ? " (the robot keeps its own heading: motion_model omni)" : "";
    throw InputError(file, lineLocation(1),
                     "expected the header " + header + ",... of terramesh plan's path.csv" + why);
  }
  PathCsv path;
  for (std::size_t number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    Eigen::Vector3d p;
    double yaw = 0;
    char a = 0, b = 0, c = ',';
    std::istringstream fields(line);
    const bool read = (fields >> p.x() >> a >> p.y() >> b >> p.z()) && (!with_yaw || (fields >> c >> yaw));
    if (!read || a != ',' || b != ',' || c != ',' || !p.allFinite() || !std::isfinite(yaw)) {
      throw InputError(file, lineLocation(number), "expected " + header + " as " + (with_yaw ? "four" : "three") +
                                                       " finite numbers, got \"" + line + "\"");
    }
    path.points.push_back(p);
    if (with_yaw) path.yaws.push_back(yaw);
  }
  return path;
}

/// Planned paths against the truth (the map's robot, strict check), in the truth's frame: per path,
/// "path_valid FILE 0|1", "path_max_ground_offset_m FILE M" and "path_reason FILE TEXT". A
/// rectangle that keeps its own heading (motion_model omni) is checked at the path's yaw, about
/// the map's `map_up` in planning's heading frame (geometry::headingFrameRule).
void checkPaths(const std::vector<std::string>& files, const datasets::SimilarityTransform* sim3,
                const datasets::LabeledMesh& truth, const Eigen::Vector3d& up, const Eigen::Vector3d& map_up,
                const traversability::RobotProfile& profile, std::ostream& report) {
  const evaluation::TruthCheckConfig config = evaluation::truthCheckConfigFrom(profile);
  const datasets::TriangleBvh bvh(truth.mesh);
  const evaluation::TruthChecker checker(truth, bvh);
  std::size_t valid = 0;
  for (const std::string& file : files) {
    PathCsv path = readPathCsv(file, config.own_heading);
    std::vector<Eigen::Vector3d> body;
    for (const double yaw : path.yaws) {
      const Eigen::Vector3d heading = geometry::headingDirection(yaw, map_up.normalized());
      body.push_back(sim3 ? Eigen::Vector3d(sim3->rotation * heading) : heading);
    }
    if (sim3) {
      for (Eigen::Vector3d& p : path.points) p = sim3->apply(p);
    }
    const evaluation::TruthCheck check = checker.check(path.points, up, 1.0, config, body);
    valid += check.valid ? 1 : 0;
    report << "path_valid " << file << ' ' << (check.valid ? 1 : 0) << '\n'
           << "path_max_ground_offset_m " << file << ' ' << fixed(check.max_ground_offset_m, 3) << '\n'
           << "path_reason " << file << ' ' << (check.reason.empty() ? "-" : check.reason) << '\n';
  }
  report << "paths_checked " << files.size() << '\n' << "paths_valid " << valid << '\n';
}

/// The map against a labelled ground-truth mesh; returns the truth judged for the map's robot.
evaluation::GroundTruthTraversability evaluateAgainstMesh(const TraverseEvalOptions& options,
                                                          traversability::LayeredMesh map,
                                                          const traversability::RobotProfile& profile,
                                                          std::ostream& report) {
  const evaluation::RobotLimits robot = evaluation::robotLimitsFrom(profile);
  const std::string& truth_path = *options.gt_mesh;
  const datasets::LabeledMesh truth = datasets::readLabeledPly(truth_path);
  if (truth.mesh.faces.empty()) throw InputError(truth_path, "faces", "the ground truth has no faces");
  std::optional<datasets::SimilarityTransform> sim3;
  if (options.sim3) {
    sim3 = datasets::readSimilarityTransform(*options.sim3);
    map.mesh = sim3->apply(map.mesh);
  } else if (std::abs(map.metres_per_unit - 1.0) > 1e-9) {
    throw UsageError("traverse-eval: the map is not metric (metres_per_unit " + fixed(map.metres_per_unit, 6) +
                     "); give --sim3 FILE to bring it into the truth's frame");
  }
  const Eigen::Vector3d up =
      options.gt_up ? parseVector(*options.gt_up, "--gt-up") : evaluation::estimateUpFromSlopes(truth);
  evaluation::GroundTruthConfig truth_config;
  truth_config.max_edge_m = options.gt_max_edge_m;
  const evaluation::GroundTruthTraversability labelled =
      evaluation::labelTraversability(truth, robot, up, truth_config);
  evaluation::ScoreConfig config;
  config.max_distance_m = options.max_distance_m;
  config.sample_edge_m = options.sample_edge_m;
  const evaluation::TraversabilityScore score =
      evaluation::scoreTraversability(map, labelled, config, lethalCauses(map, profile));

  report << "truth " << truth_path << '\n'
         << "truth_faces " << truth.mesh.faces.size() << '\n'
         << "truth_refined_faces " << labelled.mesh.mesh.faces.size() << '\n'
         << "truth_up " << fixed(up.x(), 6) << ' ' << fixed(up.y(), 6) << ' ' << fixed(up.z(), 6) << '\n'
         << "truth_traversable_m2 " << fixed(score.truth_traversable_m2, 3) << '\n';
  const auto reason_areas = labelled.areaByReason();
  for (std::size_t r = 0; r < evaluation::kTruthReasonCount; ++r) {
    report << "truth_reason_" << evaluation::toString(static_cast<evaluation::TruthReason>(r)) << "_m2 "
           << fixed(reason_areas[r], 3) << '\n';
  }
  report << "max_distance_m " << fixed(config.max_distance_m, 3) << '\n'
         << "scored_m2 " << fixed(score.scored_m2, 3) << '\n'
         << "ignored_far_m2 " << fixed(score.ignored_far_m2, 3) << '\n'
         << "true_positive_m2 " << fixed(score.true_positive_m2, 3) << '\n'
         << "false_positive_m2 " << fixed(score.false_positive_m2, 3) << '\n'
         << "false_negative_m2 " << fixed(score.false_negative_m2, 3) << '\n'
         << "true_negative_m2 " << fixed(score.true_negative_m2, 3) << '\n'
         << "unknown_m2 " << fixed(score.unknown_m2, 3) << '\n'
         << "precision " << fixed(score.precision) << '\n'
         << "recall " << fixed(score.recall) << '\n'
         << "f1 " << fixed(score.f1) << '\n'
         << "coverage " << fixed(score.coverage) << '\n'
         << "unknown_fraction " << fixed(score.unknown_fraction) << '\n'
         << "uncertain_m2 " << fixed(score.uncertain_m2, 3) << '\n'
         << "uncertain_fraction " << fixed(score.uncertain_fraction) << '\n'
         << "free_coverage " << fixed(score.free_coverage) << '\n';
  reportAreas(report, "truth_traversable", score.by_truth[1]);
  reportAreas(report, "truth_not_traversable", score.by_truth[0]);
  for (std::size_t label = 0; label < score.by_label.size(); ++label) {
    if (score.by_label[label].total() > 0) reportAreas(report, "label_" + labelName(label), score.by_label[label]);
  }
  for (std::size_t label = 0; label < score.by_label.size(); ++label) {
    for (const int answer : {1, 0}) {
      const evaluation::ClassAreas& areas = score.by_label_and_truth[label][answer];
      if (areas.total() <= 0) continue;
      reportAreas(report, "label_" + labelName(label) + (answer ? "_traversable" : "_not_traversable"), areas);
    }
  }
  // False negatives (truth traversable, map lethal) and true negatives by the map's cause.
  for (std::size_t g = 2; g < score.by_group.size() && g < 8; ++g) {
    report << "false_negative_by_map_" << kGroupNames[g] << "_m2 " << fixed(score.by_group[g][1].lethal_m2, 3) << '\n';
  }
  for (std::size_t g = 2; g < score.by_group.size() && g < 8; ++g) {
    report << "true_negative_by_map_" << kGroupNames[g] << "_m2 " << fixed(score.by_group[g][0].lethal_m2, 3) << '\n';
  }
  for (std::size_t r = 0; r < score.by_reason.size(); ++r) {
    if (score.by_reason[r].total() <= 0) continue;
    reportAreas(report, "reason_" + std::string(evaluation::toString(static_cast<evaluation::TruthReason>(r))),
                score.by_reason[r]);
  }
  if (!options.paths.empty()) checkPaths(options.paths, sim3 ? &*sim3 : nullptr, truth, up, map.up_W, profile, report);
  return labelled;
}

/// The keyframe centres and rotations of a stream, by keyframe id (the last pose sent for each;
/// removed keyframes dropped).
void keyframePath(const datasets::SlamStream& stream, std::vector<Eigen::Vector3d>& positions,
                  std::vector<Eigen::Quaterniond>& rotations) {
  std::map<mesher::KeyframeId, const mesher::Keyframe*> latest;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) latest[keyframe->id] = keyframe;
    if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) latest.erase(removal->keyframe);
  }
  for (const auto& [id, keyframe] : latest) {
    positions.push_back(keyframe->position_W_C);
    rotations.push_back(keyframe->rotation_W_C);
  }
}

/// The map under the path against measured ground points (--lidar-ground), in the map's frame.
void reportGroundUnderPath(const TraverseEvalOptions& options, const traversability::LayeredMesh& map,
                           const std::vector<Eigen::Vector3d>& path_W, const Eigen::Vector3d& up_W,
                           const evaluation::RoadUnderPathConfig& config, std::ostream& report) {
  const mesher::TriangleMesh cloud = mesher::readMesh(*options.lidar_ground);
  if (cloud.vertices.empty()) throw InputError(*options.lidar_ground, "vertices", "the point cloud has no points");
  std::vector<Eigen::Vector3d> ground = cloud.vertices;
  if (options.lidar_sim3) {
    // x_lidar = s R x_map + t, so x_map = R^T (x_lidar - t) / s.
    const datasets::SimilarityTransform to_lidar = datasets::readSimilarityTransform(*options.lidar_sim3);
    for (Eigen::Vector3d& p : ground) p = to_lidar.rotation.transpose() * (p - to_lidar.translation) / to_lidar.scale;
  }
  const evaluation::GroundUnderPath g = evaluation::groundUnderPath(map, path_W, up_W, config, ground);
  report << "lidar_ground " << *options.lidar_ground << '\n'
         << "lidar_points " << cloud.vertices.size() << '\n'
         << "lidar_ground_points " << g.points << '\n'
         << "lidar_covered_path_m " << fixed(g.covered_path_m, 2) << '\n'
         << "lidar_free_fraction " << fixed(g.free_fraction) << '\n'
         << "lidar_lethal_fraction " << fixed(g.lethal_fraction) << '\n'
         << "lidar_unknown_fraction " << fixed(g.unknown_fraction) << '\n'
         << "lidar_uncertain_fraction " << fixed(g.uncertain_fraction) << '\n'
         << "lidar_missing_fraction " << fixed(g.missing_fraction) << '\n'
         << "lidar_free_height_median_m " << fixed(g.free_height_median_m) << '\n'
         << "lidar_free_height_p90_m " << fixed(g.free_height_p90_m) << '\n'
         << "lidar_height_median_m " << fixed(g.height_median_m) << '\n';
  reportReasons(report, "lidar", g.reason_fraction);
}

/// The keyframes of a run's trajectory.csv (run_extras.h), by id, at their latest poses.
void keyframePath(const std::vector<TrajectoryRow>& rows, std::vector<Eigen::Vector3d>& positions,
                  std::vector<Eigen::Quaterniond>& rotations) {
  std::map<std::uint64_t, const TrajectoryRow*> by_id;
  for (const TrajectoryRow& row : rows) by_id[row.id] = &row;
  for (const auto& [id, row] : by_id) {
    positions.push_back(row->position_W);
    rotations.push_back(row->rotation_W_C);
  }
}

/// The path --road-under-path names: its value, or the map's own trajectory.csv without one.
std::string pathSource(const TraverseEvalOptions& options) {
  if (!options.road_under_path->empty()) return *options.road_under_path;
  return (std::filesystem::path(options.map_dir) / "trajectory.csv").string();
}

/// The map's classes on the road under the camera path (real data).
void evaluateRoadUnderPath(const TraverseEvalOptions& options, const traversability::LayeredMesh& map,
                           std::ostream& report, const evaluation::GroundTruthTraversability* truth) {
  const std::string stream_path = pathSource(options);
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Quaterniond> rotations;
  if (std::filesystem::path(stream_path).filename() == "trajectory.csv") {
    keyframePath(readTrajectoryCsv(stream_path), positions, rotations);
  } else if (std::filesystem::path(stream_path).extension() == ".txt") {
    // A pose file: every pose is a point of the path (KITTI 3x4 rows or TUM lines, by field count).
    std::vector<Eigen::Isometry3d> poses;
    if (datasets::detectPoseFileFormat(stream_path) == datasets::PoseFileFormat::kTum) {
      for (const datasets::StampedPose& pose : datasets::readTumTrajectory(stream_path))
        poses.push_back(pose.pose_W_C);
    } else {
      poses = datasets::readKittiPoses(stream_path);
    }
    for (const Eigen::Isometry3d& T_W_C : poses) {
      positions.push_back(T_W_C.translation());
      rotations.emplace_back(T_W_C.linear());
    }
  } else {
    keyframePath(datasets::readAnyStream(stream_path), positions, rotations);
  }
  if (positions.size() < 2) throw InputError(stream_path, "keyframes", "at least 2 keyframes are needed for a path");
  const Eigen::Vector3d up = evaluation::upFromCameraRotations(rotations);
  evaluation::RoadUnderPathConfig config;
  std::string height_source = "--camera-height-m";
  if (options.camera_height_m) {
    config.camera_height_m = *options.camera_height_m;
  } else if (const MeshFrameHints hints = readMeshFrameHints(std::filesystem::path(options.map_dir) / "mesh.ply");
             hints.sensor_height_m) {
    config.camera_height_m = *hints.sensor_height_m;
    height_source = "the sensor height the run's mesh.ply records (" + hints.sensor_height_source + ")";
  } else {
    config.camera_height_m = 1.65;
    height_source = "assumed: KITTI's camera mounting (the map records no sensor height)";
  }
  config.lateral_m = options.lateral_m;
  config.height_tolerance_m = options.height_tolerance_m;
  config.sample_edge_m = options.sample_edge_m;
  const evaluation::RoadUnderPath road = evaluation::roadUnderPath(map, positions, up, config, truth);
  report << "path " << stream_path << '\n'
         << "path_keyframes " << positions.size() << '\n'
         << "path_length_m " << fixed(road.path_length_m, 2) << '\n'
         << "path_up " << fixed(up.x(), 6) << ' ' << fixed(up.y(), 6) << ' ' << fixed(up.z(), 6) << '\n'
         << "metres_per_unit " << fixed(map.metres_per_unit, 6) << '\n'
         << "camera_height_m " << fixed(config.camera_height_m, 3) << '\n'
         << "camera_height_source " << height_source << '\n'
         << "lateral_m " << fixed(config.lateral_m, 3) << '\n'
         << "height_tolerance_m " << fixed(config.height_tolerance_m, 3) << '\n';
  reportAreas(report, "road", road.areas);
  report << "road_facing_down_m2 " << fixed(road.facing_down_m2) << '\n'
         << "road_free_fraction " << fixed(road.free_fraction) << '\n'
         << "road_lethal_fraction " << fixed(road.lethal_fraction) << '\n'
         << "road_unknown_fraction " << fixed(road.unknown_fraction) << '\n'
         << "road_uncertain_fraction " << fixed(road.uncertain_fraction) << '\n';
  reportReasons(report, "road", road.reason_fraction);
  report << "road_underfoot_free_fraction " << fixed(road.underfoot_free_fraction) << '\n'
         << "road_underfoot_lethal_fraction " << fixed(road.underfoot_lethal_fraction) << '\n'
         << "road_underfoot_unknown_fraction " << fixed(road.underfoot_unknown_fraction) << '\n'
         << "road_underfoot_uncertain_fraction " << fixed(road.underfoot_uncertain_fraction) << '\n'
         << "road_underfoot_none_fraction " << fixed(road.underfoot_none_fraction) << '\n';
  if (truth) {
    report << "road_free_truth_distance_median_m " << fixed(road.free_truth_distance_median_m) << '\n'
           << "road_free_truth_distance_p90_m " << fixed(road.free_truth_distance_p90_m) << '\n'
           << "road_truth_fits_fraction " << fixed(road.truth_fits_fraction) << '\n'
           << "road_free_where_truth_fits_fraction " << fixed(road.free_where_truth_fits_fraction) << '\n'
           << "road_underfoot_free_where_truth_fits_fraction "
           << fixed(road.underfoot_free_where_truth_fits_fraction) << '\n';
    reportAreas(report, "road_truth_fits", road.where_truth_fits);
  }
  if (options.lidar_ground) reportGroundUnderPath(options, map, positions, up, config, report);
}

}  // namespace

int runTraverseEval(const std::vector<std::string>& args) {
  CLI::App app{"traversability map against per-robot ground truth (precision, recall, F1) or the road under a path",
               "terramesh traverse-eval"};
  app.option_defaults()->always_capture_default();
  app.footer(
      "With --gt-mesh: every face of the truth is judged traversable or not for the map's robot "
                 "(robot.yaml) from the truth alone: a ground label (road, sidewalk, ramp, vegetation; curbs "
                 "only within the robot's step), true slope <= max slope, nothing rising more than the max step "
                 "(below the robot's height) within the footprint radius, clearance >= the robot's height. "
                 "Map pieces within --max-distance-m of the truth take the answer of the nearest truth face; "
                 "known pieces give area-weighted precision, recall and F1 of free vs traversable; coverage is "
                 "the truth's traversable area with a known map face within --max-distance-m.\n"
                 "With --road-under-path: the free / lethal / unknown / uncertain shares of the map surface "
                 "within --lateral-m of the keyframe path and --camera-height-m below it (metres via the map's "
                 "metres_per_unit; up from the keyframes' orientations); with --gt-mesh too, also how far the "
                 "free part lies from the truth (median and 90th percentile), and the share the truth does not rule "
                 "out for the robot (road_truth_fits_fraction: all but ground where its footprint does not fit) "
                 "with the free share of that part (road_free_where_truth_fits_fraction). The road_underfoot_* "
                 "shares judge the same strip by ground area: a 0.1 m grid of columns, each taking the highest "
                 "map face in the band that does not face down (none: a hole), so a steep or hidden face weighs "
                 "what it covers of the ground.\n"
                 "With --path (and --gt-mesh): per path, path_valid FILE 1 if it passes planner_demo's strict "
                 "ground-truth check for the map's robot, else 0 and path_reason FILE the first failure.\n"
                 "With --lidar-ground (and --road-under-path): the measured points in the same band are the "
                 "ground; each takes the map face straight above or below it (within --height-tolerance-m): "
                 "lidar_*_fraction of them under free, lethal, unknown, uncertain or no map surface, and the "
                 "vertical distance to the free ones (median, p90).");
  TraverseEvalOptions options;
  declareOptions(app, options);
  if (!parseCommandLine(app, args)) return kExitOk;
  const bool truth_mode = options.gt_mesh.has_value();
  const bool road_mode = options.road_under_path.has_value();
  if (!truth_mode && !road_mode) throw UsageError("traverse-eval: give --gt-mesh, --road-under-path or both");
  if ((options.lidar_ground || options.lidar_sim3) && !road_mode) {
    throw UsageError("traverse-eval: --lidar-ground and --lidar-sim3 need --road-under-path (the path to check under)");
  }
  if (options.lidar_sim3 && !options.lidar_ground) throw UsageError("traverse-eval: --lidar-sim3 needs --lidar-ground");
  if (!options.paths.empty() && !truth_mode) throw UsageError("traverse-eval: --path needs --gt-mesh (the truth to check it on)");
  if (truth_mode && road_mode && options.sim3) {
    throw UsageError("traverse-eval: --road-under-path with --gt-mesh needs the map in the truth's frame (no --sim3)");
  }
  const std::filesystem::path dir = options.map_dir;
  traversability::MapDirectory loaded = traversability::readMapDirectory(dir);
  const evaluation::RobotLimits robot = evaluation::robotLimitsFrom(loaded.profile);

  std::ostringstream report;
  report << "map " << dir.string() << '\n' << "map_faces " << loaded.map.mesh.faces.size() << '\n';
  reportRobot(report, robot);
  std::optional<evaluation::GroundTruthTraversability> truth;
  if (truth_mode) truth = evaluateAgainstMesh(options, loaded.map, loaded.profile, report);
  // With a truth too: how far the free road under the path lies from the true surface, and what
  // the truth says of it for this robot.
  if (road_mode) evaluateRoadUnderPath(options, loaded.map, report, truth ? &*truth : nullptr);
  if (options.report) writeFileAtomically(*options.report, report.str());
  if (!options.quiet) std::cout << report.str();
  return kExitOk;
}

}  // namespace terramesh::cli

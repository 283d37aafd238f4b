// terramesh generate SCENE -o DIR: a synthetic SLAM stream with its ground truth.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "datasets/kitti_odometry_reader.h"
#include "datasets/kitti_trajectory.h"
#include "datasets/labeled_mesh.h"
#include "datasets/slam_density.h"
#include "datasets/slam_json.h"
#include "datasets/slam_simulation.h"
#include "datasets/stream_format.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"
#include "generate_lidar.h"

namespace terramesh::cli {
namespace {

using datasets::SlamSimulationConfig;

/// The parsed command line; unset optionals keep the scene's or the simulation's defaults.
struct GenerateOptions {
  std::string scene;
  std::string output;
  std::optional<std::string> preset;
  std::optional<std::string> kitti_poses;
  std::optional<std::string> frames;
  std::optional<std::string> length_m;  ///< kept as typed, for generation.txt; checked as a number
  long seed = 1;
  double object_density = 1;
  std::optional<double> keyframe_spacing_m;
  std::optional<long> keyframe_every;
  std::optional<long> points_per_keyframe;
  std::map<std::string, double> reals;  ///< the simulation's real-valued options that were given
  bool measure_density = false;
  bool quiet = false;
  LidarOptions lidar;

  double lengthM() const { return std::stod(*length_m); }
};

/// The simulation's real-valued options: name, help, member.
struct RealOption {
  const char* name;
  const char* help;
  double SlamSimulationConfig::*member;
};
const RealOption kRealOptions[] = {
    {"--noise-std-m", "observation noise along the ray at zero depth (default 0.03)", &SlamSimulationConfig::noise_std_m},
    {"--depth-noise-per-m", "noise along the ray grows by K * depth^2 (default 3e-4)",
     &SlamSimulationConfig::depth_noise_per_m},
    {"--pixel-noise-px", "noise across the ray, in pixels (default 1)", &SlamSimulationConfig::pixel_noise_px},
    {"--outlier-fraction", "fraction of points that are gross outliers (default 0.01)",
     &SlamSimulationConfig::outlier_fraction},
    {"--moving-fraction", "fraction of points refined at re-observation (default 1)",
     &SlamSimulationConfig::moving_point_fraction},
    {"--match-probability", "chance of re-observing a visible tracked point (default 0.7)",
     &SlamSimulationConfig::match_probability},
    {"--max-range-m", "features farther than R are not seen (default 40)", &SlamSimulationConfig::max_range_m},
    {"--loop-closure-drift-m", "the middle third of keyframes drifts up to D metres, then is re-sent corrected (default 0)",
     &SlamSimulationConfig::loop_closure_drift_m}};

void declareOptions(CLI::App& app, GenerateOptions& options) {
  app.add_option("SCENE", options.scene, "street, offroad, garage or hazards")->required();
  app.add_option("-o,--output", options.output, "output directory (created if missing)")->option_text("DIR");
  app.add_option("--preset", options.preset,
                 "kitti-like (issue 3's benchmark stream: a keyframe every 4 frames, ~130 new points "
                 "and ~500 observations per keyframe, 10% moving points) or kitti-dense (~4,500 "
                 "observations per keyframe); street only, needs --kitti-poses")
      ->option_text("NAME");
  app.add_option("--kitti-poses", options.kitti_poses, "street: follow this KITTI odometry pose file (world frame y-down)")
      ->option_text("FILE");
  app.add_option("--frames", options.frames, "with --kitti-poses: frames A to B-1 (\"A:\" to the end)")
      ->option_text("A:B");
  app.add_option("--length-m", options.length_m,
                 "scene length: street 300, offroad 200, garage 48 (its x extent); with --kitti-poses "
                 "the trajectory is cut after L metres (default: all); hazards has a fixed 72 x 36 m plan")
      ->option_text("L")
      ->check(CLI::Number);
  app.add_option("--seed", options.seed, "seed of the scene and of the simulated SLAM")->check(nonNegativeNumber());
  app.add_option("--object-density", options.object_density, "scales cars, trees, buildings, rocks (0: none)");
  app.add_option("--keyframe-spacing-m", options.keyframe_spacing_m, "a keyframe every D metres travelled (default 2)")
      ->option_text("D");
  app.add_option("--keyframe-every", options.keyframe_every, "a keyframe every N frames instead (frames are 10 Hz)")
      ->option_text("N")
      ->check(nonNegativeNumber());
  app.add_option("--points-per-keyframe", options.points_per_keyframe, "new features per keyframe (default 130)")
      ->option_text("N")
      ->check(nonNegativeNumber());
  for (const RealOption& real : kRealOptions) {
    const std::string name = real.name;
    app.add_option_function<double>(
           name, [&options, name](double value) { options.reals[name] = value; }, real.help)
        ->option_text("X");
  }
  app.add_flag("--measure-density", options.measure_density,
               "also measure the stream's points per m^2 of the ground its keyframes see and its point errors "
               "(generation.txt: ground_*; slow on long scenes)");
  app.add_flag("--quiet", options.quiet, "print nothing but errors");
  addLidarOptions(app, options.lidar);
}

/// Parses "A:B" or "A:" into a half-open frame range.
std::pair<std::size_t, std::size_t> parseFrameRange(const std::string& text) {
  const auto fields = parseColonIntegers(text, "generate: --frames", "A:B", 2);
  if (fields.size() != 2 || !fields[0]) {
    throw UsageError("generate: --frames expects A:B with non-negative integers, got \"" + text + "\"");
  }
  const std::size_t first = *fields[0];
  const std::size_t last = fields[1].value_or(static_cast<std::size_t>(-1));
  if (last <= first) throw UsageError("generate: --frames A:B needs A < B, got \"" + text + "\"");
  return {first, last};
}

SlamSimulationConfig simulationConfig(const GenerateOptions& options) {
  // Each scene's own SLAM defaults; the options below override them.
  SlamSimulationConfig config = options.scene == "hazards" ? datasets::hazardsSlamConfig() : SlamSimulationConfig{};
  if (options.preset) {
    if (*options.preset == "kitti-like") config = datasets::kittiLikeSlamConfig();
    else if (*options.preset == "kitti-dense") config = datasets::kittiDenseSlamConfig();
    else throw UsageError("generate: --preset must be kitti-like or kitti-dense");
  }
  config.seed = static_cast<std::uint64_t>(options.seed);
  if (options.keyframe_spacing_m && options.keyframe_every) {
    throw UsageError("generate: give --keyframe-spacing-m or --keyframe-every, not both");
  }
  if (options.keyframe_spacing_m) {
    config.keyframe_spacing_m = *options.keyframe_spacing_m;
    config.keyframe_every_frames = 0;
  }
  if (options.keyframe_every) config.keyframe_every_frames = static_cast<int>(*options.keyframe_every);
  if (options.points_per_keyframe) config.new_points_per_keyframe = static_cast<int>(*options.points_per_keyframe);
  for (const RealOption& real : kRealOptions) {
    if (const auto it = options.reals.find(real.name); it != options.reals.end()) config.*real.member = it->second;
  }
  config.validate();
  return config;
}

/// Builds the scene the arguments ask for; `source` says where its trajectory came from.
datasets::SyntheticScene buildScene(const GenerateOptions& options, std::string& source) {
  const std::string& name = options.scene;
  const auto seed = static_cast<std::uint64_t>(options.seed);
  const double density = options.object_density;
  const bool kitti = options.kitti_poses.has_value();
  if (name != "street" && (kitti || options.frames || options.preset)) {
    throw UsageError("generate: --kitti-poses, --frames and --preset apply to the street scene only");
  }
  if (options.preset && !kitti) {
    throw UsageError("generate: --preset needs --kitti-poses FILE (e.g. ../shared/data/kitti_poses/00.txt)");
  }
  if (options.frames && !kitti) throw UsageError("generate: --frames needs --kitti-poses");
  source = "procedural";
  // What every scene config shares.
  auto common = [&](auto config) {
    config.seed = seed;
    config.object_density = density;
    if (options.length_m) config.length_m = options.lengthM();
    return config;
  };
  if (name == "offroad") return datasets::buildOffroadScene(common(datasets::OffroadSceneConfig{}));
  if (name == "garage") return datasets::buildGarageScene(common(datasets::GarageSceneConfig{}));
  if (name == "hazards") {
    if (options.length_m) throw UsageError("generate: --length-m does not apply to the hazards scene (fixed plan)");
    datasets::HazardsSceneConfig config;
    config.seed = seed;
    config.object_density = density;
    return datasets::buildHazardsScene(config);
  }
  if (name == "street") {
    datasets::StreetSceneConfig config = common(datasets::StreetSceneConfig{});
    if (!kitti) return datasets::buildStreetScene(config);
    if (!options.length_m) config.length_m = 0.0;  // the whole trajectory
    const std::string& file = *options.kitti_poses;
    datasets::PoseList poses = datasets::readKittiPoses(file);
    std::string range = "all";
    if (options.frames) {
      const auto [first, last] = parseFrameRange(*options.frames);
      poses = datasets::selectFrames(poses, first, last);
      range = *options.frames;
    }
    source = "kitti_poses " + file + " frames " + range;
    return datasets::buildStreetScene(config, poses);
  }
  throw UsageError("generate: SCENE must be street, offroad, garage or hazards, got \"" + name + "\"");
}

std::string describeRun(const datasets::SyntheticScene& scene, const std::string& source,
                        const GenerateOptions& options, const SlamSimulationConfig& config,
                        const datasets::SimulatedSlam& slam) {
  const datasets::SimulationStats& stats = slam.stats;
  const double keyframes = static_cast<double>(std::max<std::size_t>(stats.keyframes, 1));
  std::ostringstream out;
  out.precision(10);
  out << "scene " << scene.name << "\ntrajectory " << source << "\nframe " << scene.frame_description
      << "\nup_W " << scene.up_W.x() << ' ' << scene.up_W.y() << ' ' << scene.up_W.z() << "\nmetres_per_unit 1\nframe_rate_hz "
      << datasets::kSyntheticFrameRateHz << "\nseed " << config.seed << "\nobject_density "
      << options.object_density << "\nlength_m " << options.length_m.value_or("default") << "\npreset "
      << options.preset.value_or("none")
      << "\nkeyframe_spacing_m " << config.keyframe_spacing_m << "\nkeyframe_every_frames "
      << config.keyframe_every_frames << "\nimage_px " << config.image_width_px << ' '
      << config.image_height_px << "\nfocal_length_px " << config.focal_length_px << "\nrange_m "
      << config.min_range_m << ' ' << config.max_range_m << "\nmax_incidence_deg " << config.max_incidence_deg
      << "\nnew_points_per_keyframe "
      << config.new_points_per_keyframe << "\nmatch_probability " << config.match_probability
      << "\nmax_missed_keyframes " << config.max_missed_keyframes << "\nmax_scale_change "
      << config.max_scale_change << "\nmax_view_angle_deg " << config.max_view_angle_deg
      << "\nnoise_std_m " << config.noise_std_m << "\ndepth_noise_per_m " << config.depth_noise_per_m
      << "\npixel_noise_px " << config.pixel_noise_px << "\nmoving_point_fraction "
      << config.moving_point_fraction << "\noutlier_fraction " << config.outlier_fraction
      << "\nloop_closure_drift_m " << config.loop_closure_drift_m
      << "\nground_truth_vertices " << scene.ground_truth.mesh.vertices.size()
      << "\nground_truth_faces " << scene.ground_truth.mesh.faces.size();
  std::size_t per_label[datasets::kSurfaceLabelCount] = {};
  for (const datasets::SurfaceLabel label : scene.ground_truth.labels) ++per_label[static_cast<std::size_t>(label)];
  for (std::size_t l = 0; l < datasets::kSurfaceLabelCount; ++l) {
    out << "\nfaces_" << datasets::toString(static_cast<datasets::SurfaceLabel>(l)) << ' ' << per_label[l];
  }
  out << "\nframes " << scene.frames_T_W_C.size() << "\nkeyframes " << stats.keyframes
      << "\nkeyframe_events " << stats.keyframe_events << "\npoints " << stats.points << "\noutliers "
      << stats.outliers << "\nmoving_points " << stats.moving_points << "\nobservations "
      << stats.observations << "\nrays_cast " << stats.rays_cast << "\nmean_new_points_per_keyframe "
      << static_cast<double>(stats.points) / keyframes << "\nmean_observations_per_keyframe "
      << static_cast<double>(stats.observations) / keyframes << "\npoints_seen_twice "
      << stats.points_seen_twice << "\npoints_moved_after_second_view "
      << stats.points_moved_after_second_view << '\n';
  return out.str();
}

/// One line per hazard: what, where, how big, and the start and goal placed to test it.
std::string describeHazards(const std::vector<datasets::SceneHazard>& hazards) {
  std::ostringstream out;
  out.precision(10);
  out << "name,kind,centre_x,centre_y,centre_z,size_x_m,size_y_m,height_m,ramp_slope_deg,ramp_length_m,"
         "ramp_width_m,start_x,start_y,start_z,goal_x,goal_y,goal_z\n";
  for (const datasets::SceneHazard& h : hazards) {
    out << h.name << ',' << datasets::toString(h.kind) << ',' << h.centre_W.x() << ',' << h.centre_W.y() << ','
        << h.centre_W.z() << ',' << h.size_m.x() << ',' << h.size_m.y() << ',' << h.height_m << ','
        << h.ramp_slope_deg << ',' << h.ramp_length_m << ',' << h.ramp_width_m << ',' << h.start_W.x() << ','
        << h.start_W.y() << ',' << h.start_W.z() << ',' << h.goal_W.x() << ',' << h.goal_W.y() << ','
        << h.goal_W.z() << '\n';
  }
  return out.str();
}

std::string describeDensity(const datasets::GroundDensity& density) {
  std::ostringstream out;
  out.precision(6);
  out << "ground_area_m2 " << density.ground_area_m2 << "\nground_seen_m2 " << density.seen_area_m2
      << "\nground_points " << density.ground_points << "\nground_points_seen_twice "
      << density.ground_points_seen_twice << "\nground_points_per_m2_seen " << density.points_per_m2
      << "\nground_points_seen_twice_per_m2_seen " << density.points_seen_twice_per_m2
      << "\npoint_error_rms_m " << density.rms_error_m << "\npoint_error_median_m " << density.median_error_m
      << '\n';
  return out.str();
}

}  // namespace

int runGenerate(const std::vector<std::string>& args) {
  CLI::App app{"synthetic SLAM stream with ground truth", "terramesh generate"};
  app.option_defaults()->always_capture_default();
  app.footer(
      "writes DIR/stream.tmstream, DIR/stream.json, DIR/ground_truth.ply (labels and slopes "
      "per face), DIR/trajectory.txt (true keyframe poses, KITTI format, line i = keyframe i), "
      "DIR/frames.txt (the true pose of every 10 Hz frame from the first keyframe's to the "
      "last's, KITTI format: the path the camera took), DIR/generation.txt and, for hazards, "
      "DIR/hazards.csv (each hazard with a start and goal across it); with --lidar, DIR/lidar/ "
      "(a KITTI odometry sequence; see docs/synthetic_data.md)");
  GenerateOptions options;
  declareOptions(app, options);
  if (!parseCommandLine(app, args)) return kExitOk;
  if (options.output.empty()) throw UsageError("generate: -o/--output DIR is required");
  const auto started = std::chrono::steady_clock::now();
  // Everything is parsed and validated before any output exists.
  const SlamSimulationConfig config = simulationConfig(options);
  const auto lidar = lidarConfigFrom(options.lidar, config.seed);
  std::string source;
  const datasets::SyntheticScene scene = buildScene(options, source);
  const datasets::TriangleBvh bvh(scene.ground_truth.mesh);
  const datasets::SimulatedSlam slam = datasets::simulateSlam(scene, bvh, config);
  std::vector<Eigen::Isometry3d> lidar_poses;
  if (lidar) lidar_poses = lidarPosesFor(options.lidar, scene, bvh, *lidar);

  const std::filesystem::path output = options.output;
  std::filesystem::create_directories(output);
  datasets::writeStreamFile(output / "stream.tmstream", slam.stream);
  datasets::writeSlamJson(output / "stream.json", slam.stream);
  datasets::writeLabeledPly(output / "ground_truth.ply", scene.ground_truth);
  datasets::PoseList keyframe_poses;
  for (const datasets::SimulatedKeyframe& keyframe : slam.keyframes) keyframe_poses.push_back(keyframe.true_T_W_C);
  datasets::writeKittiPoses(output / "trajectory.txt", keyframe_poses);
  if (!slam.keyframes.empty()) {
    // The path the camera took while the SLAM ran: its first keyframe's frame to its last's.
    datasets::writeKittiPoses(
        output / "frames.txt",
        datasets::selectFrames(scene.frames_T_W_C, slam.keyframes.front().frame,
                               slam.keyframes.back().frame + 1));
  }
  std::string description = describeRun(scene, source, options, config, slam);
  if (options.measure_density) {
    description += describeDensity(datasets::measureGroundDensity(scene, bvh, slam, config));
  }
  std::optional<LidarRunSummary> lidar_run;
  if (lidar) {
    lidar_run = writeLidarSequence(output / "lidar", scene, bvh, *lidar, lidar_poses, options.quiet);
    description += describeLidar(*lidar, *lidar_run);
  }
  writeFileAtomically(output / "generation.txt", description);
  if (!scene.hazards.empty()) writeFileAtomically(output / "hazards.csv", describeHazards(scene.hazards));
  if (!options.quiet) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const double keyframes = static_cast<double>(std::max<std::size_t>(slam.stats.keyframes, 1));
    std::printf("%s: %zu faces, %zu keyframes, %zu points, %.1f new points and %.1f observations per "
                "keyframe; wrote %s in %.1f s\n",
                scene.name.c_str(), scene.ground_truth.mesh.faces.size(), slam.stats.keyframes,
                slam.stats.points, static_cast<double>(slam.stats.points) / keyframes,
                static_cast<double>(slam.stats.observations) / keyframes, output.string().c_str(), seconds);
    if (lidar_run) {
      std::printf("lidar: %zu scans, %zu returns per scan (median), %.3f s per scan\n", lidar_run->scans,
                  lidar_run->median_returns_per_scan, lidar_run->seconds / static_cast<double>(lidar_run->scans));
    }
  }
  return kExitOk;
}

}  // namespace terramesh::cli

// terramesh generate SCENE -o DIR: a synthetic SLAM stream with its ground truth.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "datasets/kitti_odometry_reader.h"
#include "datasets/kitti_trajectory.h"
#include "datasets/labeled_mesh.h"
#include "datasets/slam_json.h"
#include "datasets/slam_simulation.h"
#include "datasets/stream_format.h"
#include "datasets/synthetic_scene.h"
#include "datasets/triangle_bvh.h"

namespace terramesh::cli {
namespace {

using datasets::SlamSimulationConfig;

void declareOptions(ArgParser& parser) {
  parser.positional("SCENE", "street, offroad or garage")
      .option("--output", "DIR", "output directory (created if missing)")
      .alias("-o", "--output")
      .option("--preset", "NAME",
              "kitti-like (issue 3's benchmark stream: a keyframe every 4 frames, ~130 new points "
              "and ~500 observations per keyframe, 10% moving points) or kitti-dense (~4,500 "
              "observations per keyframe); street only, needs --kitti-poses")
      .option("--kitti-poses", "FILE", "street: follow this KITTI odometry pose file (world frame y-down)")
      .option("--frames", "A:B", "with --kitti-poses: frames A to B-1 (\"A:\" to the end)")
      .option("--length-m", "L",
              "scene length: street 300, offroad 200, garage 48 (its x extent); with --kitti-poses "
              "the trajectory is cut after L metres (default: all)")
      .option("--seed", "N", "seed of the scene and of the simulated SLAM", "1")
      .option("--object-density", "X", "scales cars, trees, buildings, rocks (0: none)", "1")
      .option("--keyframe-spacing-m", "D", "a keyframe every D metres travelled (default 2)")
      .option("--keyframe-every", "N", "a keyframe every N frames instead (frames are 10 Hz)")
      .option("--points-per-keyframe", "N", "new features per keyframe (default 130)")
      .option("--noise-std-m", "S", "observation noise along the ray at zero depth (default 0.03)")
      .option("--depth-noise-per-m", "K", "noise along the ray grows by K * depth^2 (default 3e-4)")
      .option("--pixel-noise-px", "P", "noise across the ray, in pixels (default 1)")
      .option("--outlier-fraction", "F", "fraction of points that are gross outliers (default 0.01)")
      .option("--moving-fraction", "F", "fraction of points refined at re-observation (default 1)")
      .option("--match-probability", "P", "chance of re-observing a visible tracked point (default 0.7)")
      .option("--max-range-m", "R", "features farther than R are not seen (default 40)")
      .option("--loop-closure-drift-m", "D",
              "the middle third of keyframes drifts up to D metres, then is re-sent corrected (default 0)")
      .flag("--quiet", "print nothing but errors");
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

long nonNegativeInt(const ArgParser& parser, const std::string& name) {
  const long value = parser.getInt(name);
  if (value < 0) throw UsageError("generate: " + name + " must be >= 0");
  return value;
}

SlamSimulationConfig simulationConfig(const ArgParser& parser) {
  SlamSimulationConfig config;
  if (parser.has("--preset")) {
    const std::string preset = parser.get("--preset");
    if (preset == "kitti-like") config = datasets::kittiLikeSlamConfig();
    else if (preset == "kitti-dense") config = datasets::kittiDenseSlamConfig();
    else throw UsageError("generate: --preset must be kitti-like or kitti-dense");
  }
  config.seed = static_cast<std::uint64_t>(nonNegativeInt(parser, "--seed"));
  if (parser.has("--keyframe-spacing-m") && parser.has("--keyframe-every")) {
    throw UsageError("generate: give --keyframe-spacing-m or --keyframe-every, not both");
  }
  if (parser.has("--keyframe-spacing-m")) {
    config.keyframe_spacing_m = parser.getDouble("--keyframe-spacing-m");
    config.keyframe_every_frames = 0;
  }
  if (parser.has("--keyframe-every")) config.keyframe_every_frames = static_cast<int>(nonNegativeInt(parser, "--keyframe-every"));
  if (parser.has("--points-per-keyframe")) {
    config.new_points_per_keyframe = static_cast<int>(nonNegativeInt(parser, "--points-per-keyframe"));
  }
  const std::pair<const char*, double SlamSimulationConfig::*> reals[] = {
      {"--noise-std-m", &SlamSimulationConfig::noise_std_m},
      {"--depth-noise-per-m", &SlamSimulationConfig::depth_noise_per_m},
      {"--pixel-noise-px", &SlamSimulationConfig::pixel_noise_px},
      {"--outlier-fraction", &SlamSimulationConfig::outlier_fraction},
      {"--moving-fraction", &SlamSimulationConfig::moving_point_fraction},
      {"--match-probability", &SlamSimulationConfig::match_probability},
      {"--max-range-m", &SlamSimulationConfig::max_range_m},
      {"--loop-closure-drift-m", &SlamSimulationConfig::loop_closure_drift_m}};
  for (const auto& [name, member] : reals) {
    if (parser.has(name)) config.*member = parser.getDouble(name);
  }
  config.validate();
  return config;
}

/// Builds the scene the arguments ask for; `source` says where its trajectory came from.
datasets::SyntheticScene buildScene(const ArgParser& parser, const std::string& name, std::string& source) {
  const auto seed = static_cast<std::uint64_t>(nonNegativeInt(parser, "--seed"));
  const double density = parser.getDouble("--object-density");
  const bool kitti = parser.has("--kitti-poses");
  if (name != "street" && (kitti || parser.has("--frames") || parser.has("--preset"))) {
    throw UsageError("generate: --kitti-poses, --frames and --preset apply to the street scene only");
  }
  if (parser.has("--preset") && !kitti) {
    throw UsageError("generate: --preset needs --kitti-poses FILE (e.g. ../shared/data/kitti_poses/00.txt)");
  }
  if (parser.has("--frames") && !kitti) throw UsageError("generate: --frames needs --kitti-poses");
  source = "procedural";
  // What every scene config shares.
  auto common = [&](auto config) {
    config.seed = seed;
    config.object_density = density;
    if (parser.has("--length-m")) config.length_m = parser.getDouble("--length-m");
    return config;
  };
  if (name == "offroad") return datasets::buildOffroadScene(common(datasets::OffroadSceneConfig{}));
  if (name == "garage") return datasets::buildGarageScene(common(datasets::GarageSceneConfig{}));
  if (name == "street") {
    datasets::StreetSceneConfig config = common(datasets::StreetSceneConfig{});
    if (!kitti) return datasets::buildStreetScene(config);
    if (!parser.has("--length-m")) config.length_m = 0.0;  // the whole trajectory
    const std::string file = parser.get("--kitti-poses");
    datasets::PoseList poses = datasets::readKittiPoses(file);
    std::string range = "all";
    if (parser.has("--frames")) {
      const auto [first, last] = parseFrameRange(parser.get("--frames"));
      poses = datasets::selectFrames(poses, first, last);
      range = parser.get("--frames");
    }
    source = "kitti_poses " + file + " frames " + range;
    return datasets::buildStreetScene(config, poses);
  }
  throw UsageError("generate: SCENE must be street, offroad or garage, got \"" + name + "\"");
}

std::string describeRun(const datasets::SyntheticScene& scene, const std::string& source,
                        const ArgParser& parser, const SlamSimulationConfig& config,
                        const datasets::SimulatedSlam& slam) {
  const datasets::SimulationStats& stats = slam.stats;
  const double keyframes = static_cast<double>(std::max<std::size_t>(stats.keyframes, 1));
  std::ostringstream out;
  out.precision(10);
  out << "scene " << scene.name << "\ntrajectory " << source << "\nframe " << scene.frame_description
      << "\nup_W " << scene.up_W.x() << ' ' << scene.up_W.y() << ' ' << scene.up_W.z() << "\nmetres_per_unit 1\nframe_rate_hz "
      << datasets::kSyntheticFrameRateHz << "\nseed " << config.seed << "\nobject_density "
      << parser.getDouble("--object-density") << "\nlength_m "
      << (parser.has("--length-m") ? parser.get("--length-m") : "default") << "\npreset "
      << (parser.has("--preset") ? parser.get("--preset") : "none")
      << "\nkeyframe_spacing_m " << config.keyframe_spacing_m << "\nkeyframe_every_frames "
      << config.keyframe_every_frames << "\nimage_px " << config.image_width_px << ' '
      << config.image_height_px << "\nfocal_length_px " << config.focal_length_px << "\nrange_m "
      << config.min_range_m << ' ' << config.max_range_m << "\nnew_points_per_keyframe "
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

}  // namespace

int runGenerate(const std::vector<std::string>& args) {
  ArgParser parser("generate");
  declareOptions(parser);
  parser.parse(args);
  if (parser.helpRequested()) {
    std::cout << parser.usage()
              << "\nwrites DIR/stream.tmstream, DIR/stream.json, DIR/ground_truth.ply (labels and slopes per "
                 "face), DIR/trajectory.txt (true keyframe poses, KITTI format, line i = keyframe i) and "
                 "DIR/generation.txt (see docs/synthetic_data.md)\n";
    return kExitOk;
  }
  if (!parser.has("--output")) throw UsageError("generate: -o/--output DIR is required");
  const auto started = std::chrono::steady_clock::now();
  // Everything is parsed and validated before any output exists.
  const SlamSimulationConfig config = simulationConfig(parser);
  std::string source;
  const datasets::SyntheticScene scene = buildScene(parser, parser.positionalValue("SCENE"), source);
  const datasets::TriangleBvh bvh(scene.ground_truth.mesh);
  const datasets::SimulatedSlam slam = datasets::simulateSlam(scene, bvh, config);

  const std::filesystem::path output = parser.get("--output");
  std::filesystem::create_directories(output);
  datasets::writeStreamFile(output / "stream.tmstream", slam.stream);
  datasets::writeSlamJson(output / "stream.json", slam.stream);
  datasets::writeLabeledPly(output / "ground_truth.ply", scene.ground_truth);
  datasets::PoseList keyframe_poses;
  for (const datasets::SimulatedKeyframe& keyframe : slam.keyframes) keyframe_poses.push_back(keyframe.true_T_W_C);
  datasets::writeKittiPoses(output / "trajectory.txt", keyframe_poses);
  const std::string description = describeRun(scene, source, parser, config, slam);
  writeFileAtomically(output / "generation.txt", description);
  if (!parser.flagSet("--quiet")) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const double keyframes = static_cast<double>(std::max<std::size_t>(slam.stats.keyframes, 1));
    std::printf("%s: %zu faces, %zu keyframes, %zu points, %.1f new points and %.1f observations per "
                "keyframe; wrote %s in %.1f s\n",
                scene.name.c_str(), scene.ground_truth.mesh.faces.size(), slam.stats.keyframes,
                slam.stats.points, static_cast<double>(slam.stats.points) / keyframes,
                static_cast<double>(slam.stats.observations) / keyframes, output.string().c_str(), seconds);
  }
  return kExitOk;
}

}  // namespace terramesh::cli

// terramesh compare INPUT -o OUTDIR: the mesher against OctoMap and PCL's reconstructions on the
// same stream, measured the same way (time, memory, size, accuracy, manifoldness,
// traversability, planning).
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <variant>

#include "baselines/slam_points.h"
#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "common/input_error.h"
#include "compare_maps.h"
#include "compare_planning.h"
#include "compare_report.h"
#include "datasets/kitti_odometry_reader.h"
#include "datasets/labeled_mesh.h"
#include "datasets/similarity_transform.h"
#include "datasets/stream_reader.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/geometry_truth.h"
#include "evaluation/ground_truth_traversability.h"
#include "evaluation/manifoldness.h"
#include "evaluation/robot_limits.h"
#include "evaluation/truth_pairs.h"
#include "installed_files.h"
#include "mesher_options.h"
#include "traversability/robot_profile.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::cli {
namespace {

struct CompareOptions {
  std::string input;
  std::string output;
  std::optional<std::string> gt;
  std::optional<std::string> views;
  std::optional<std::string> gt_lidar;
  std::optional<std::string> gt_poses;
  std::string gt_frames = "0:10";
  std::optional<std::string> sim3;
  std::optional<std::string> robot;
  std::string methods = "all";
  std::size_t pairs = 10;
  double pair_min_distance_m = 5;
  double snap_radius_m = 1;
  bool allow_unknown = false;
  double camera_height_m = 1.65;
  std::size_t samples = 100000;
  int stride_px = 8;
  std::size_t view_step = 1;
  std::uint64_t seed = 1;
  std::optional<std::string> figures_script;
  bool no_figures = false;
  bool quiet = false;
};

void addOptions(CLI::App& app, CompareOptions& o) {
  app.add_option("INPUT", o.input, "SLAM stream (any format `terramesh mesh` reads)")->required();
  app.add_option("-o,--output", o.output, "output directory (created if missing)")->required();
  app.add_option("--gt", o.gt, "ground truth: a labelled mesh (ground_truth.ply of terramesh generate)");
  app.add_option("--views", o.views,
                 "with --gt: camera poses (KITTI format) to render truth depth from (default: trajectory.txt beside "
                 "GT if there is one, else the stream's own keyframe poses)");
  app.add_option("--gt-lidar", o.gt_lidar, "ground truth: a KITTI odometry sequence (velodyne/*.bin, calib.txt)");
  app.add_option("--gt-poses", o.gt_poses, "with --gt-lidar: its KITTI poses (cam0-to-world)");
  app.add_option("--gt-frames", o.gt_frames, "with --gt-lidar: scans of frames A to B (inclusive)")->capture_default_str();
  app.add_option("--sim3", o.sim3, "map every surface into the truth's frame by x' = s R x + t (s, R, t lines)");
  app.add_option("--robot", o.robot, "robot profile (YAML): traversability layers and planning on every surface");
  app.add_option("--methods", o.methods,
                 "comma-separated: proposed, litvinov13, romanoni15, octomap-0.1, octomap-0.2, octomap-0.5, "
                 "greedy, poisson, marching-cubes; or all")->capture_default_str();
  app.add_option("--pairs", o.pairs, "start-goal pairs for planning")->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_option("--pair-min-distance-m", o.pair_min_distance_m, "start and goal at least this far apart")->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--snap-radius-m", o.snap_radius_m, "start/goal snap to walkable surface within this")->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_flag("--allow-unknown", o.allow_unknown,
               "planning may cross unknown faces (Nav2's allow_unknown; cost as dear as the dearest free face)");
  app.add_option("--camera-height-m", o.camera_height_m,
                 "without labelled truth: pairs are drawn on the road this far below the keyframe centres")->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--samples", o.samples, "surface samples for accuracy and completeness")->capture_default_str()->check(CLI::Range(1, 10000000));
  app.add_option("--stride-px", o.stride_px, "with --gt: render every N-th pixel in each direction")->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--view-step", o.view_step, "with --gt: use every N-th view")->capture_default_str()->check(CLI::Range(1, 100000));
  app.add_option("--seed", o.seed, "seed of the sampling and of the pairs")->capture_default_str();
  app.add_option("--figures-script", o.figures_script, "the matplotlib script that draws the figures");
  app.add_flag("--no-figures", o.no_figures, "write the CSVs only; draw no figure");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
}

std::pair<std::size_t, std::size_t> parseFrames(const std::string& text) {
  const auto fields = parseColonIntegers(text, "compare: --gt-frames", "A:B", 2);
  if (fields.size() != 2 || !fields[0] || !fields[1] || *fields[1] < *fields[0]) {
    throw UsageError("compare: --gt-frames expects A:B with A <= B, got \"" + text + "\"");
  }
  return {*fields[0], *fields[1]};
}

std::vector<evaluation::EvaluationView> readViews(const std::filesystem::path& path, std::size_t step) {
  std::vector<evaluation::EvaluationView> views;
  const std::vector<Eigen::Isometry3d> poses = datasets::readKittiPoses(path);
  for (std::size_t i = 0; i < poses.size(); i += step) {
    views.push_back({poses[i].translation(), Eigen::Quaterniond(poses[i].linear())});
  }
  return views;
}

/// The stream's keyframes as views in the truth's frame: the last pose sent for each id (removed
/// keyframes dropped), mapped by `to_truth` (positions) and `rotate` (camera-to-world rotations);
/// every `step`-th.
template <class ToTruth, class Rotate>
std::vector<evaluation::EvaluationView> streamViews(const datasets::SlamStream& stream, std::size_t step,
                                                  const ToTruth& to_truth, const Rotate& rotate) {
  std::vector<evaluation::EvaluationView> views;
  std::size_t i = 0;
  for (const datasets::LatestKeyframePose& pose : datasets::latestKeyframePoses(stream)) {
    if (i++ % step == 0) views.push_back({to_truth(pose.position_W_C), rotate(pose.rotation_W_C)});
  }
  return views;
}

/// The views file for --gt: --views (which must exist), else trajectory.txt beside the truth if
/// there is one, else empty (the stream's own keyframes).
std::filesystem::path viewsFile(const CompareOptions& o) {
  if (o.views) {
    if (!std::filesystem::is_regular_file(*o.views)) throw UsageError("compare: no views file " + *o.views);
    return *o.views;
  }
  const std::filesystem::path beside = std::filesystem::path(*o.gt).parent_path() / "trajectory.txt";
  return std::filesystem::is_regular_file(beside) ? beside : std::filesystem::path();
}

/// The views the truth is rendered from (viewsFile, or the stream's keyframes in the truth's
/// frame), and how the report names them.
std::pair<std::vector<evaluation::EvaluationView>, std::string> truthViews(
    const CompareOptions& o, const std::filesystem::path& views_path, const datasets::SlamStream& stream,
    const std::optional<datasets::SimilarityTransform>& sim3, double metres_per_unit) {
  if (!views_path.empty()) return {readViews(views_path, o.view_step), "`" + views_path.string() + "`"};
  const auto rotate = [&](const Eigen::Quaterniond& q) { return sim3 ? sim3->apply(q) : q; };
  const auto position = [&](const Eigen::Vector3d& p) {
    return sim3 ? sim3->apply(p) : Eigen::Vector3d(p * metres_per_unit);
  };
  std::vector<evaluation::EvaluationView> views = streamViews(stream, o.view_step, position, rotate);
  if (views.empty()) throw InputError(o.input, "keyframes", "no keyframe poses to render the truth from (give --views FILE)");
  const std::string text = "the stream's " + std::to_string(views.size()) + " keyframe poses";
  return {std::move(views), text};
}

std::string commandLine(const std::vector<std::string>& args) {
  std::string text = "terramesh compare";
  for (const std::string& arg : args) text += " " + arg;
  return text;
}

/// The figure script shipped beside the executable (installed or in the build tree), else empty.
std::filesystem::path defaultFiguresScript() {
  const std::filesystem::path folder = shippedFolder("share/terramesh/figures", "compare_figures.py");
  return folder.empty() ? folder : folder / "compare_figures.py";
}

/// What the maps are measured against: the geometry truth, and with a labelled mesh its labels
/// for the robot and a BVH of it. Filled in place (TriangleBvh stays where it is built).
struct CompareTruth {
  std::optional<evaluation::GeometryTruth> geometry;
  std::optional<datasets::LabeledMesh> labelled;
  std::optional<evaluation::GroundTruthTraversability> labels;
  std::optional<datasets::TriangleBvh> bvh;
};

using Say = std::function<void(const std::string&)>;

/// The geometry truth of --gt (a labelled mesh rendered from the views) or --gt-lidar, if any.
void readGeometryTruth(const CompareOptions& o, const std::filesystem::path& views_path, const datasets::SlamStream& stream,
                       const std::optional<datasets::SimilarityTransform>& sim3, double metres_per_unit,
                       CompareTruth& truth, CompareSetup& setup, const Say& say) {
  evaluation::GeometryTruthConfig truth_config;
  truth_config.samples = o.samples;
  truth_config.seed = o.seed;
  truth_config.depth.stride_px = o.stride_px;
  if (o.gt) {
    truth.labelled = datasets::readLabeledPly(*o.gt);
    if (truth.labelled->mesh.faces.empty()) throw InputError(*o.gt, "faces", "the ground truth has no faces");
    const auto [views, views_text] = truthViews(o, views_path, stream, sim3, metres_per_unit);
    if (views_path.empty()) say("views: " + views_text + " (no --views, no trajectory.txt beside " + *o.gt + ")");
    truth.geometry = evaluation::GeometryTruth::fromMesh(truth.labelled->mesh, views, truth_config);
    setup.truth = "mesh `" + *o.gt + "` rendered from " + views_text + " (" +
                  std::to_string(truth.geometry->truthRays()) + " rays)";
  } else if (o.gt_lidar) {
    evaluation::LidarTruthOptions options;
    options.poses_path = *o.gt_poses;
    std::tie(options.first_frame, options.last_frame) = parseFrames(o.gt_frames);
    truth.geometry = evaluation::GeometryTruth::fromLidar(*o.gt_lidar, options, truth_config);
    setup.truth = "KITTI LiDAR `" + *o.gt_lidar + "` frames " + o.gt_frames + " (" +
                  std::to_string(truth.geometry->truthRays()) + " rays)";
  }
  if (truth.geometry) say("ground truth ready: " + std::to_string(truth.geometry->truthRays()) + " rays");
}

/// Start/goal pairs for the planning columns: on the observed, driven part of the labelled truth's
/// traversable area (labelling it for the robot), else among the keyframe centres lowered to the
/// road. Describes them in setup.pairs.
std::vector<evaluation::ComparePair> drawPairs(const CompareOptions& o, const traversability::RobotProfile& profile,
                                               const mesher::MesherConfig& proposed,
                                               const std::vector<Eigen::Vector3d>& cameras_T,
                                               const Eigen::Vector3d& up_T, CompareTruth& truth, CompareSetup& setup) {
  setup.robot = profile.name + " (`" + *o.robot + "`)";
  if (!truth.labelled) {
    std::vector<Eigen::Vector3d> road;
    for (const Eigen::Vector3d& c : cameras_T) road.push_back(c - o.camera_height_m * up_T);
    std::vector<evaluation::ComparePair> pairs = evaluation::pairsOnPoints(road, o.pairs, o.seed, o.pair_min_distance_m);
    setup.pairs = std::to_string(pairs.size()) + " among the keyframe centres lowered by " +
                  std::to_string(o.camera_height_m) + " m (the road under the camera; no labelled truth)";
    return pairs;
  }
  truth.labels = evaluation::labelTraversability(*truth.labelled, evaluation::robotLimitsFrom(profile),
                                                 evaluation::estimateUpFromSlopes(*truth.labelled), {});
  truth.bvh.emplace(truth.labelled->mesh);
  evaluation::TruthPairsConfig pairs_config;
  pairs_config.count = o.pairs;
  pairs_config.seed = o.seed;
  pairs_config.min_distance_m = o.pair_min_distance_m;
  pairs_config.max_view_distance_m = proposed.max_camera_distance_m;
  pairs_config.min_views = std::max(1, proposed.min_views);
  const evaluation::TruthPairs drawn = evaluation::pairsOnObservedTruth(*truth.labels, *truth.bvh, cameras_T, pairs_config);
  std::ostringstream text;
  text.precision(4);
  text << drawn.pairs.size() << " drawn on the connected part of the truth's traversable area that the stream "
       << "observed and drove on (seed " << o.seed << ", >= " << o.pair_min_distance_m
       << " m apart in a straight line): " << drawn.samples << " traversable samples on a " << pairs_config.cell_m
       << " m grid, " << drawn.observed << " seen unoccluded by >= " << pairs_config.min_views
       << " keyframes within " << pairs_config.max_view_distance_m << " m, joined within "
       << pairs_config.link_radius_m << " m; the part under the camera path (nearest observed sample of "
       << drawn.component_votes << " of " << cameras_T.size() << " keyframes) holds " << drawn.component_samples
       << " (" << drawn.component_extent_m << " m across; the largest part " << drawn.largest_component_samples
       << "); truth lengths by Dijkstra over those samples";
  setup.pairs = text.str();
  return drawn.pairs;
}

/// The labelled truth as the planned paths are checked on it (empty without it or a robot).
PathTruth pathTruthFor(const CompareTruth& truth, const std::optional<traversability::RobotProfile>& profile) {
  PathTruth path_truth;
  if (!truth.labelled || !profile) return path_truth;
  path_truth.mesh = &*truth.labelled;
  path_truth.bvh = &*truth.bvh;
  path_truth.up_W = truth.labels->up_W;
  path_truth.config = evaluation::truthCheckConfigFrom(*profile);
  return path_truth;
}

/// How a built map is measured: in the truth's frame, against what the run has.
struct MeasureContext {
  const CompareOptions* options = nullptr;
  const CompareTruth* truth = nullptr;
  const traversability::RobotProfile* profile = nullptr;  ///< null: no traversability or planning
  const std::vector<evaluation::ComparePair>* pairs = nullptr;
  PathTruth path_truth;
  planning::WalkabilityConfig walkability;
  Eigen::Vector3d up_T = Eigen::Vector3d::UnitZ();
  std::filesystem::path topview_dir;
};

/// Measures one built map into its row, its surface taken into the truth's frame (metres) by
/// `to_truth` (timed with the measures).
void measureRow(CompareRow& row, const std::function<mesher::TriangleMesh(const mesher::TriangleMesh&)>& to_truth,
                const MeasureContext& c, const Say& say) {
  const auto started = std::chrono::steady_clock::now();
  const mesher::TriangleMesh surface = to_truth(row.built.surface);
  row.manifold = evaluation::measureManifoldness(surface);
  if (c.truth->geometry) {
    row.geometry = c.truth->geometry->score(surface);
    row.has_geometry = true;
  }
  std::optional<traversability::LayeredMesh> layered;
  if (c.profile && !surface.faces.empty()) {
    layered = traversability::TraversabilityMap::computeForMesh(
        surface, *c.profile, {c.up_T, 1.0}, static_cast<std::uint32_t>(std::max(c.profile->min_rays, 1)));
    if (c.truth->labels) {
      row.traversability = evaluation::scoreTraversability(*layered, *c.truth->labels, {});
      row.has_traversability = true;
    }
    row.planning = planComparePairs(*layered, *c.pairs, c.walkability, c.options->snap_radius_m, c.path_truth);
    row.has_planning = !c.pairs->empty();
    if (row.has_planning) say(row.spec.name + ": planning " + row.planning.summary());
  }
  writeTopView(c.topview_dir / (row.spec.slug + ".csv"), surface, layered ? &layered->layers : nullptr, c.up_T);
  row.measure_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  say(row.spec.name + ": measured in " + std::to_string(row.measure_s) + " s");
}

/// Runs the figure script on OUTDIR unless --no-figures; whether it drew them.
bool drawFigures(const CompareOptions& o, const std::filesystem::path& out, const Say& say) {
  if (o.no_figures) return false;
  const std::filesystem::path script = o.figures_script ? std::filesystem::path(*o.figures_script) : defaultFiguresScript();
  if (script.empty() || !std::filesystem::is_regular_file(script)) {
    say("no figure script at " + script.string() + " (give --figures-script)");
    return false;
  }
  const std::vector<std::string> call = {"/usr/bin/python3", script.string(), out.string()};
  const bool drawn = runProgram(call, o.quiet) == 0;
  if (!drawn) say("the figure script failed: /usr/bin/python3 " + script.string() + " " + out.string());
  return drawn;
}

/// What measuring a built map needs. Keeps pointers to `o`, `truth`, `profile` and `pairs`.
MeasureContext measureContext(const CompareOptions& o, const CompareTruth& truth,
                              const std::optional<traversability::RobotProfile>& profile,
                              const std::vector<evaluation::ComparePair>& pairs, const Eigen::Vector3d& up_T,
                              const std::filesystem::path& out) {
  MeasureContext measure;
  measure.options = &o;
  measure.truth = &truth;
  measure.profile = profile ? &*profile : nullptr;
  measure.pairs = &pairs;
  measure.path_truth = pathTruthFor(truth, profile);
  if (profile) measure.walkability = planning::walkabilityFor(*profile);
  measure.walkability.allow_unknown = o.allow_unknown;
  measure.up_T = up_T;
  measure.topview_dir = out / "topview";
  return measure;
}

/// The usage errors no single option shows.
void checkOptions(const CompareOptions& o) {
  if (o.gt && o.gt_lidar) throw UsageError("compare: give at most one of --gt and --gt-lidar");
  if (o.gt_lidar && !o.gt_poses) throw UsageError("compare: --gt-lidar needs --gt-poses FILE");
  if (o.views && !o.gt) throw UsageError("compare: --views goes with --gt");
}

/// What building a map needs: the stream, each mode's mesher config (from the options), the frame
/// and where the maps go (OUTDIR/maps). Keeps references to `stream` and `mesher_options`.
BuildContext buildContext(const datasets::SlamStream& stream, const MesherOptions& mesher_options,
                          const mesher::MesherConfig& proposed, const Eigen::Vector3d& up_W,
                          const std::filesystem::path& out) {
  BuildContext context;
  context.stream = &stream;
  context.mesher_config = [&stream, &mesher_options](mesher::MesherMode mode) {
    return mesherConfigFrom(mesher_options, mode, stream);
  };
  context.up_W = up_W;
  context.metres_per_unit = proposed.metres_per_unit;
  context.max_distance_m = proposed.max_camera_distance_m;
  context.min_views = proposed.min_views;
  context.maps_dir = out / "maps";
  return context;
}

/// The start-goal pairs every map is planned on (none without a robot; drawPairs), said in `setup`.
std::vector<evaluation::ComparePair> comparePairs(const CompareOptions& o,
                                                  const std::optional<traversability::RobotProfile>& profile,
                                                  const mesher::MesherConfig& proposed,
                                                  const std::vector<Eigen::Vector3d>& cameras_T,
                                                  const Eigen::Vector3d& up_T, CompareTruth& truth,
                                                  CompareSetup& setup) {
  std::vector<evaluation::ComparePair> pairs;
  if (profile) pairs = drawPairs(o, *profile, proposed, cameras_T, up_T, truth, setup);
  if (o.allow_unknown && !pairs.empty()) {
    setup.pairs += "; planning may cross unknown faces (--allow-unknown, unknown cost 1: the dearest free cost)";
  }
  return pairs;
}

/// A map's surface in the truth's frame, in metres: through the similarity when one is given, else
/// scaled.
mesher::TriangleMesh inTruthFrame(const mesher::TriangleMesh& mesh,
                                  const std::optional<datasets::SimilarityTransform>& sim3, double metres_per_unit) {
  if (sim3) return sim3->apply(mesh);
  mesher::TriangleMesh scaled = mesh;
  for (Eigen::Vector3d& v : scaled.vertices) v *= metres_per_unit;
  return scaled;
}

/// The stream's latest keyframe centres in the truth's frame (metres).
std::vector<Eigen::Vector3d> camerasInTruth(const datasets::SlamStream& stream,
                                            const std::optional<datasets::SimilarityTransform>& sim3,
                                            double metres_per_unit) {
  std::vector<Eigen::Vector3d> cameras_T;
  for (const Eigen::Vector3d& c : datasets::latestKeyframeCentres(stream)) {
    cameras_T.push_back(sim3 ? sim3->apply(c) : Eigen::Vector3d(c * metres_per_unit));
  }
  return cameras_T;
}

/// Builds every map, each in its own process, while this process holds only the stream.
std::vector<CompareRow> buildMaps(const std::vector<MapSpec>& specs, const BuildContext& context, const Say& say) {
  std::vector<CompareRow> rows;
  for (const MapSpec& spec : specs) {
    CompareRow row;
    row.spec = spec;
    row.built = buildMap(spec, context);
    say(spec.name + (row.built.ok ? ": built in " + std::to_string(row.built.build_s) + " s, " +
                                        std::to_string(row.built.surface.faces.size()) + " faces"
                                  : ": failed: " + row.built.error));
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

int runCompare(const std::vector<std::string>& args) {
  CLI::App app("The mesher against OctoMap and PCL's surface reconstructions on one stream: build time, peak "
               "memory, size, accuracy and completeness, manifoldness, traversability F1 and planning, in one "
               "table (OUTDIR/report.md, compare.csv, figures).",
               "terramesh compare");
  CompareOptions o;
  MesherOptions mesher_options;
  addOptions(app, o);
  addMesherOptions(app, mesher_options);
  if (!parseCommandLine(app, args)) return kExitOk;
  checkOptions(o);
  const std::vector<MapSpec> specs = parseMethods(o.methods);
  const Say say = [&o](const std::string& text) {
    if (!o.quiet) std::cerr << "compare: " << text << '\n';
  };

  // Read and check every input before building anything.
  const datasets::SlamStream stream = datasets::readAnyStream(o.input);
  const mesher::MesherConfig proposed = mesherConfigFrom(mesher_options, mesher::MesherMode::kProposed, stream);
  std::optional<datasets::SimilarityTransform> sim3;
  if (o.sim3) sim3 = datasets::readSimilarityTransform(*o.sim3);
  std::optional<traversability::RobotProfile> profile;
  if (o.robot) profile = traversability::loadRobotProfile(*o.robot);
  std::filesystem::path views_path;
  if (o.gt) views_path = viewsFile(o);
  const Eigen::Vector3d up_W = baselines::streamUp(stream);

  const std::filesystem::path out = o.output;
  std::filesystem::create_directories(out / "maps");
  std::filesystem::create_directories(out / "topview");
  std::vector<CompareRow> rows = buildMaps(specs, buildContext(stream, mesher_options, proposed, up_W, out), say);

  // Everything is measured in the truth's frame, in metres.
  const double metres_per_unit = proposed.metres_per_unit;
  const auto toTruth = [&sim3, metres_per_unit](const mesher::TriangleMesh& mesh) {
    return inTruthFrame(mesh, sim3, metres_per_unit);
  };
  const Eigen::Vector3d up_T = sim3 ? Eigen::Vector3d((sim3->rotation * up_W).normalized()) : up_W;
  CompareSetup setup;
  setup.command = commandLine(args);
  setup.input = o.input;
  setup.keyframes = stream.keyframeEventCount();
  setup.metres_per_unit = metres_per_unit;
  CompareTruth truth;
  readGeometryTruth(o, views_path, stream, sim3, proposed.metres_per_unit, truth, setup, say);
  const std::vector<evaluation::ComparePair> pairs =
      comparePairs(o, profile, proposed, camerasInTruth(stream, sim3, metres_per_unit), up_T, truth, setup);

  const MeasureContext measure = measureContext(o, truth, profile, pairs, up_T, out);
  for (CompareRow& row : rows) {
    if (row.built.ok) measureRow(row, toTruth, measure, say);
  }

  writeCompareCsv(out / "compare.csv", rows);
  if (!pairs.empty()) writePairsCsv(out / "pairs.csv", pairs, rows);
  const std::string report = compareMarkdown(setup, rows, drawFigures(o, out, say));
  writeFileAtomically(out / "report.md", report);
  if (!o.quiet) std::cout << report;
  return kExitOk;
}

}  // namespace terramesh::cli

// planner_demo SCENE MAP_DIR OUT_DIR: the mesh against an OctoMap built from the same SLAM
// stream, on the same start/goal pairs, judged against the synthetic scene's ground truth.
//   SCENE:   a folder written by `terramesh generate` (stream.tmstream, ground_truth.ply), or a
//            stream file (any format `terramesh mesh` reads: real data, no truth to check against)
//   MAP_DIR: written by `terramesh traverse` on the mesh of that stream
// Pairs: --pairs N random ones on the mesh's largest walkable component (default), one given pair
// (--start X Y Z --goal X Y Z, map frame and units), or N among the keyframe centres lowered by
// --camera-height-m H (the road under a car's camera path).
// Writes OUT_DIR/octomap.bt, mesh.log and octomap.log (OMPL benchmark logs, map_type as an
// experiment parameter), pairs.csv and comparison.md. The planners run through
// evaluation::runPathTrials, the harness `terramesh compare` uses too.
#include <CLI/CLI.hpp>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <variant>

#include "baselines/grid_planner.h"
#include "baselines/octomap_baseline.h"
#include "common/atomic_file.h"
#include "datasets/labeled_mesh.h"
#include "datasets/stream_reader.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/path_trials.h"
#include "evaluation/truth_checker.h"
#include "planning/face_graph.h"
#include "planning/ompl_benchmark_log.h"
#include "planning/path_planner.h"
#include "traversability/map_directory.h"

namespace {

using namespace terramesh;
using Clock = std::chrono::steady_clock;
using Pairs = std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>;

double secondsSince(Clock::time_point started) {
  return std::chrono::duration<double>(Clock::now() - started).count();
}

struct Options {
  std::filesystem::path scene, map, out;
  std::size_t pairs = 10;
  std::string planner = "bitstar";
  double time_budget_s = 1.0;
  double time_cap_s = 0.0;
  bool allow_unknown = false;
  double resolution_m = 0.2;
  std::uint32_t seed = 1;
  double snap_radius_m = 0.5;
  std::optional<Eigen::Vector3d> start, goal;
  std::optional<double> camera_height_m;
};

/// Parses the command line with CLI11. Returns nothing when --help was asked for (printed).
/// @throw CLI::ParseError on a usage error.
std::optional<Options> parse(int argc, char** argv) {
  Options o;
  std::array<double, 3> start{}, goal{};
  double camera_height_m = 0;
  CLI::App app{"The mesh against an OctoMap of the same SLAM stream, on the same start/goal pairs, judged "
               "against the scene's ground truth",
               "planner_demo"};
  app.add_option("scene", o.scene, "scene folder of `terramesh generate`, or a stream file")->required();
  app.add_option("map", o.map, "map directory of `terramesh traverse` on that stream's mesh")->required();
  app.add_option("out", o.out, "output directory")->required();
  app.add_option("--pairs", o.pairs, "random pairs (or pairs under the cameras)")->capture_default_str();
  app.add_option("--planner", o.planner, "OMPL planner")->capture_default_str();
  app.add_option("--time-budget-s", o.time_budget_s, "planning time per query")->capture_default_str();
  app.add_option("--time-cap-s", o.time_cap_s, "keep searching for a first path up to this long")->capture_default_str();
  app.add_flag("--allow-unknown", o.allow_unknown, "plan over unknown faces too");
  app.add_option("--resolution-m", o.resolution_m, "OctoMap resolution")->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the pairs and the planners")->capture_default_str();
  app.add_option("--snap-radius-m", o.snap_radius_m, "how far start and goal may move onto walkable ground")
      ->capture_default_str();
  auto* start_option = app.add_option("--start", start, "start X Y Z (map frame and units)");
  auto* goal_option = app.add_option("--goal", goal, "goal X Y Z")->needs(start_option);
  start_option->needs(goal_option);
  app.add_option("--camera-height-m", camera_height_m, "pairs among the keyframe centres lowered by this")
      ->excludes(start_option)
      ->excludes(goal_option);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    std::cout << app.help();
    return std::nullopt;
  }
  const auto point = [](const std::array<double, 3>& p, const std::string& name) {
    const Eigen::Vector3d v(p[0], p[1], p[2]);
    if (!v.allFinite()) throw std::invalid_argument(name + " needs three finite numbers");
    return v;
  };
  if (*start_option) o.start = point(start, "--start");
  if (*goal_option) o.goal = point(goal, "--goal");
  if (app.count("--camera-height-m") > 0) o.camera_height_m = camera_height_m;
  return o;
}

/// Per planner: its name in the tables and logs, and its map type.
struct Contender {
  std::string csv_name;    ///< pairs.csv's `map` column
  std::string table_name;  ///< comparison.md's row
  std::string log_name;    ///< the OMPL benchmark log's planner name
};

/// The OctoMap of the stream, its height grid for the map's robot, and how long they took.
struct OctomapSide {
  std::optional<baselines::OctomapBaseline> octomap;
  baselines::GridRobotConfig robot;
  baselines::HeightGrid grid;
  double grid_time_s = 0;
};

OctomapSide buildOctomapSide(const Options& o, const datasets::SlamStream& stream,
                             const traversability::MapDirectory& map, double cost_weight) {
  OctomapSide side;
  baselines::OctomapConfig config;
  config.resolution_m = o.resolution_m;
  config.metres_per_unit = map.map.metres_per_unit;
  config.up_W = map.map.up_W;
  side.octomap.emplace(config);
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) side.octomap->insertKeyframe(*keyframe);
  }
  side.octomap->writeBinary(o.out / "octomap.bt");
  side.robot.max_step_m = map.profile.max_step_m;
  side.robot.max_slope_deg = map.profile.max_slope_deg;
  side.robot.min_clearance_m = map.profile.min_clearance_m;
  side.robot.footprint_radius_m = map.profile.inscribed_radius_m;
  side.robot.cost_weight = cost_weight;
  const auto started = Clock::now();
  side.grid = side.octomap->heightGrid(side.robot);
  side.grid_time_s = secondsSince(started);
  return side;
}

/// `count` pairs among the keyframe centres lowered by `height_m` along the map's up, at least
/// `min_distance_m` apart; deterministic for a seed. Map frame and units.
Pairs pairsUnderCameras(const datasets::SlamStream& stream, const traversability::LayeredMesh& map, double height_m,
                        std::size_t count, std::uint32_t seed, double min_distance_m) {
  const Eigen::Vector3d down = -map.up_W.normalized() * (height_m / map.metres_per_unit);
  std::vector<Eigen::Vector3d> road;
  for (const Eigen::Vector3d& centre : datasets::latestKeyframeCentres(stream)) road.push_back(centre + down);
  Pairs pairs;
  if (road.size() < 2) return pairs;
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<std::size_t> pick(0, road.size() - 1);
  for (std::size_t attempt = 0; attempt < 100 * count && pairs.size() < count; ++attempt) {
    const std::size_t a = pick(random), b = pick(random);
    if ((road[a] - road[b]).norm() * map.metres_per_unit >= min_distance_m) pairs.emplace_back(road[a], road[b]);
  }
  return pairs;
}

/// The pairs the options ask for, and how the tables name them.
Pairs choosePairs(const Options& o, const datasets::SlamStream& stream, const traversability::LayeredMesh& map,
                  const planning::FaceGraph& graph, std::string& described) {
  Pairs pairs;
  if (o.start) {
    pairs.emplace_back(*o.start, *o.goal);
    described = "the given start and goal";
  } else if (o.camera_height_m) {
    pairs = pairsUnderCameras(stream, map, *o.camera_height_m, o.pairs, o.seed, 5.0);
    described = std::to_string(pairs.size()) + " pairs among the keyframe centres lowered by " +
                std::to_string(*o.camera_height_m) + " m";
  } else {
    for (const auto& [a, b] : planning::drawRandomPairs(graph, o.pairs, o.seed, 5.0)) pairs.emplace_back(a.point_W, b.point_W);
    described = std::to_string(pairs.size()) + " random pairs on the mesh's largest walkable component";
  }
  return pairs;
}

std::string pairsCsv(const Pairs& pairs, const std::vector<Contender>& contenders,
                     const std::vector<evaluation::PlannerTrials>& trials) {
  std::ostringstream csv;
  csv << "pair,map,status,length_m,cost,time_s,truth_valid,truth_reason,start_x,start_y,start_z,goal_x,goal_y,goal_z,"
         "reason\n";
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Eigen::Vector3d& a = pairs[i].first;
    const Eigen::Vector3d& b = pairs[i].second;
    for (std::size_t p = 0; p < contenders.size(); ++p) {
      const evaluation::PathTrial& t = trials[p].trials[i];
      const planning::PlanResult& r = t.result;
      csv << i << ',' << contenders[p].csv_name << ',' << planning::toString(r.status) << ',' << r.length_m << ','
          << r.cost << ',' << r.planning_time_s << ',' << (t.checked ? (t.check.valid ? "1" : "0") : "") << ",\""
          << t.check.reason << "\"," << a.x() << ',' << a.y() << ',' << a.z() << ',' << b.x() << ',' << b.y() << ','
          << b.z() << ",\"" << r.reason << "\"\n";
    }
  }
  return csv.str();
}

/// One planner's runs for an OMPL benchmark log.
planning::BenchmarkPlannerRuns benchmarkRuns(const Contender& contender, const evaluation::PlannerTrials& trials) {
  planning::BenchmarkPlannerRuns runs{contender.log_name,
                                      {"time REAL", "solved BOOLEAN", "surface length REAL", "path cost REAL",
                                       "valid against ground truth BOOLEAN"},
                                      {}};
  const double nan = std::nan("");
  for (const evaluation::PathTrial& t : trials.trials) {
    const bool ok = t.result.solved();
    runs.runs.push_back({t.result.planning_time_s, ok ? 1.0 : 0.0, ok ? t.result.length_m : nan,
                         ok ? t.result.cost : nan, ok ? (t.check.valid ? 1.0 : 0.0) : nan});
  }
  return runs;
}

void writeBenchmarkLogs(const Options& o, const std::string& described, std::size_t pair_count,
                        const std::vector<Contender>& contenders, const std::vector<evaluation::PlannerTrials>& trials) {
  auto experiment = [&](const std::string& type, std::vector<planning::BenchmarkPlannerRuns> runs) {
    planning::BenchmarkExperiment e;
    e.name = "terramesh_planner_demo";
    e.parameters = {{"map_type", type}};
    e.setup = "scene " + o.scene.string() + ", map " + o.map.string() + ", " + described;
    e.seed = o.seed;
    e.time_limit_s = o.time_budget_s;
    e.run_count = pair_count;
    e.planners = std::move(runs);
    return e;
  };
  planning::writeOmplBenchmarkLog(
      o.out / "mesh.log",
      experiment("mesh", {benchmarkRuns(contenders[0], trials[0]), benchmarkRuns(contenders[1], trials[1])}));
  planning::writeOmplBenchmarkLog(o.out / "octomap.log", experiment("octomap", {benchmarkRuns(contenders[2], trials[2])}));
}

/// What comparison.md says besides the planners' rows.
struct MapFacts {
  double graph_time_s = 0;
  std::size_t mesh_bytes = 0;
  bool has_truth = false;
};

std::string comparisonTable(const std::string& described, std::size_t pair_count,
                            const std::vector<Contender>& contenders,
                            const std::vector<evaluation::PlannerTrials>& trials, const MapFacts& facts,
                            const planning::FaceGraph& graph, const OctomapSide& octo, double metres_per_unit) {
  const baselines::OctomapStats stats = octo.octomap->stats();
  std::ostringstream table;
  table.precision(4);
  auto line = [&](std::size_t p, double build_s, std::size_t bytes) {
    const evaluation::PlannerTrials& t = trials[p];
    const double n = static_cast<double>(std::max<std::size_t>(t.solved, 1));
    table << "| " << contenders[p].table_name << " | " << t.solved << "/" << pair_count << " | " << t.length_m / n
          << " | " << t.cost / n << " | " << t.time_s / static_cast<double>(std::max<std::size_t>(pair_count, 1))
          << " | " << build_s << " | " << static_cast<double>(bytes) / 1e6 << " | ";
    if (facts.has_truth) table << t.truth_valid << "/" << t.truth_checked << " |\n";
    else table << "- (no truth) |\n";
  };
  table << "| map | solved | mean length (m) | mean cost | mean planning time (s) | map build time (s) | map memory (MB) | "
           "valid on ground truth |\n|---|---|---|---|---|---|---|---|\n";
  line(0, facts.graph_time_s, facts.mesh_bytes);
  line(1, facts.graph_time_s, facts.mesh_bytes);
  line(2, stats.build_time_s + octo.grid_time_s, stats.memory_bytes + octo.grid.memoryBytes());
  double walkable_area = 0, largest = 0;
  for (std::uint32_t c = 0; c < graph.componentCount(); ++c) {
    walkable_area += graph.componentArea(c);
    largest = std::max(largest, graph.componentArea(c));
  }
  const double area_scale = metres_per_unit * metres_per_unit;
  table << "\npairs: " << described << "\nmesh: " << graph.walkableFaceCount() << " walkable faces of " << graph.faceCount()
        << ", " << walkable_area * area_scale << " m^2 in " << graph.componentCount() << " walkable components, the largest "
        << largest * area_scale << " m^2 (build time here: the planner's face graph only; the mesher and layers are "
        << "timed by their commands)\n"
        << "octomap: " << stats.keyframes << " keyframes, " << stats.points << " points, " << stats.leaves << " leaves ("
        << stats.occupied_leaves << " occupied), insertion " << stats.build_time_s << " s, grid " << octo.grid_time_s
        << " s; grid " << octo.grid.width << " x " << octo.grid.height << ", " << octo.grid.knownCells()
        << " known cells, " << octo.grid.traversableCells() << " traversable\n";
  return table.str();
}

int run(const Options& o) {
  planning::setOmplLogging(false);
  planning::seedOmpl(o.seed);
  std::filesystem::create_directories(o.out);
  const traversability::MapDirectory map = traversability::readMapDirectory(o.map);
  planning::WalkabilityConfig walkability = planning::walkabilityFor(map.profile);
  walkability.allow_unknown = o.allow_unknown;
  const auto graph_started = Clock::now();
  const planning::FaceGraph graph(map.map, walkability);
  MapFacts facts;
  facts.graph_time_s = secondsSince(graph_started);
  facts.mesh_bytes = map.map.mesh.vertices.size() * sizeof(Eigen::Vector3d) +
                     map.map.mesh.faces.size() * (sizeof(std::array<std::uint32_t, 3>) + sizeof(traversability::FaceLayers));
  const bool scene_dir = std::filesystem::is_directory(o.scene);
  const datasets::SlamStream stream = datasets::readAnyStream(scene_dir ? o.scene / "stream.tmstream" : o.scene);
  const OctomapSide octo = buildOctomapSide(o, stream, map, walkability.cost_weight);

  // The truth, when there is one (a generated scene).
  facts.has_truth = scene_dir && std::filesystem::is_regular_file(o.scene / "ground_truth.ply");
  const datasets::LabeledMesh truth =
      facts.has_truth ? datasets::readLabeledPly(o.scene / "ground_truth.ply") : datasets::LabeledMesh{};
  const datasets::TriangleBvh bvh(truth.mesh);
  std::optional<evaluation::TruthChecker> checker;
  if (facts.has_truth) checker.emplace(truth, bvh);
  const evaluation::PathTruth path_truth{checker ? &*checker : nullptr, evaluation::truthCheckConfigFrom(map.profile), map.map.up_W,
                                         map.map.metres_per_unit};

  planning::PlannerConfig config;
  config.planner = o.planner;
  config.time_budget_s = o.time_budget_s;
  config.time_cap_s = o.time_cap_s;
  config.seed = o.seed;
  config.snap_radius_m = o.snap_radius_m;
  config.validate();
  std::string described;
  const Pairs pairs = choosePairs(o, stream, map.map, graph, described);
  const planning::SurfacePlanner on_mesh(graph, config, false), on_graph(graph, config, true);
  const baselines::GridPlanner on_grid(octo.grid, config, octo.robot.cost_weight);
  const std::vector<Contender> contenders = {
      {"mesh", "mesh, " + o.planner, "geometric_" + o.planner},
      {"mesh_graph", "mesh, graph A*", "graph_astar"},
      {"octomap", "octomap " + std::to_string(o.resolution_m).substr(0, 4) + " m, " + o.planner, "geometric_" + o.planner}};
  const std::vector<evaluation::PlannerTrials> trials =
      evaluation::runPathTrials({&on_mesh, &on_graph, &on_grid}, pairs, path_truth);

  writeFileAtomically(o.out / "pairs.csv", pairsCsv(pairs, contenders, trials));
  writeBenchmarkLogs(o, described, pairs.size(), contenders, trials);
  const std::string table =
      comparisonTable(described, pairs.size(), contenders, trials, facts, graph, octo, map.map.metres_per_unit);
  writeFileAtomically(o.out / "comparison.md", table);
  std::cout << table;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::optional<Options> options = parse(argc, argv);
    return options ? run(*options) : 0;
  } catch (const CLI::ParseError& error) {
    std::cerr << "planner_demo: " << error.what() << '\n';
    return 2;
  } catch (const std::invalid_argument& error) {
    std::cerr << "planner_demo: " << error.what() << '\n';
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "planner_demo: " << error.what() << '\n';
    return 1;
  }
}

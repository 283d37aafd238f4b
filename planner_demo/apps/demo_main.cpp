// planner_demo SCENE MAP_DIR OUT_DIR: the mesh against an OctoMap built from the same SLAM
// stream, on the same start/goal pairs, judged against the synthetic scene's ground truth.
//   SCENE:   a folder written by `terramesh generate` (stream.tmstream, ground_truth.ply), or a
//            stream file (any format `terramesh mesh` reads: real data, no truth to check against)
//   MAP_DIR: written by `terramesh traverse` on the mesh of that stream
// Pairs: --pairs N random ones on the mesh's largest walkable component (default), one given pair
// (--start X Y Z --goal X Y Z, map frame and units), or N among the keyframe centres lowered by
// --camera-height-m H (the road under a car's camera path).
// Writes OUT_DIR/octomap.bt, mesh.log and octomap.log (OMPL benchmark logs, map_type as an
// experiment parameter), pairs.csv and comparison.md.
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
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
#include "evaluation/truth_checker.h"
#include "planning/face_graph.h"
#include "planning/ompl_benchmark_log.h"
#include "planning/surface_planner.h"
#include "traversability/map_directory.h"

namespace {

using namespace terramesh;
using Clock = std::chrono::steady_clock;

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

Eigen::Vector3d parsePoint(int& i, int argc, char** argv, const std::string& name) {
  if (i + 3 >= argc) throw std::invalid_argument(name + " needs X Y Z");
  Eigen::Vector3d p;
  for (int k = 0; k < 3; ++k) p[k] = std::stod(argv[++i]);
  if (!p.allFinite()) throw std::invalid_argument(name + " needs three finite numbers");
  return p;
}

Options parse(int argc, char** argv) {
  Options options;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--pairs") options.pairs = std::stoul(value());
    else if (arg == "--planner") options.planner = value();
    else if (arg == "--time-budget-s") options.time_budget_s = std::stod(value());
    else if (arg == "--time-cap-s") options.time_cap_s = std::stod(value());
    else if (arg == "--allow-unknown") options.allow_unknown = true;
    else if (arg == "--resolution-m") options.resolution_m = std::stod(value());
    else if (arg == "--seed") options.seed = static_cast<std::uint32_t>(std::stoul(value()));
    else if (arg == "--snap-radius-m") options.snap_radius_m = std::stod(value());
    else if (arg == "--start") options.start = parsePoint(i, argc, argv, arg);
    else if (arg == "--goal") options.goal = parsePoint(i, argc, argv, arg);
    else if (arg == "--camera-height-m") options.camera_height_m = std::stod(value());
    else if (arg.rfind("--", 0) == 0) throw std::invalid_argument("unknown option " + arg);
    else positional.push_back(arg);
  }
  if (positional.size() != 3) {
    throw std::invalid_argument(
        "usage: planner_demo SCENE_DIR|STREAM MAP_DIR OUT_DIR [--pairs N] [--planner NAME] [--time-budget-s T] "
        "[--time-cap-s T] [--allow-unknown] [--resolution-m R] [--seed S] [--snap-radius-m R] [--start X Y Z --goal X Y Z | --camera-height-m H]");
  }
  if (options.start.has_value() != options.goal.has_value()) throw std::invalid_argument("give both --start and --goal");
  if (options.start && options.camera_height_m) throw std::invalid_argument("--start/--goal and --camera-height-m exclude each other");
  options.scene = positional[0];
  options.map = positional[1];
  options.out = positional[2];
  return options;
}

/// Per map type: the runs for the benchmark log and the totals for the table.
struct Tally {
  planning::BenchmarkPlannerRuns runs;
  std::size_t solved = 0, truth_valid = 0, truth_checked = 0;
  double length = 0, cost = 0, time = 0;
  void add(bool ok, double length_m, double path_cost, double time_s, bool valid, bool checked) {
    const double nan = std::nan("");
    runs.runs.push_back({time_s, ok ? 1.0 : 0.0, ok ? length_m : nan, ok ? path_cost : nan, ok ? (valid ? 1.0 : 0.0) : nan});
    time += time_s;
    if (!ok) return;
    ++solved;
    truth_valid += valid ? 1 : 0;
    truth_checked += checked ? 1 : 0;
    length += length_m;
    cost += path_cost;
  }
};

/// `count` pairs among the keyframe centres (the last pose of each) lowered by `height_m` along
/// the map's up, at least `min_distance_m` apart; deterministic for a seed. Map frame and units.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairsUnderCameras(const datasets::SlamStream& stream,
                                                                          const traversability::LayeredMesh& map,
                                                                          double height_m, std::size_t count,
                                                                          std::uint32_t seed, double min_distance_m) {
  std::map<mesher::KeyframeId, Eigen::Vector3d> latest;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) latest[keyframe->id] = keyframe->position_W_C;
  }
  const Eigen::Vector3d down = -map.up_W.normalized() * (height_m / map.metres_per_unit);
  std::vector<Eigen::Vector3d> road;
  for (const auto& [id, centre] : latest) road.push_back(centre + down);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  if (road.size() < 2) return pairs;
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<std::size_t> pick(0, road.size() - 1);
  for (std::size_t attempt = 0; attempt < 100 * count && pairs.size() < count; ++attempt) {
    const std::size_t a = pick(random), b = pick(random);
    if ((road[a] - road[b]).norm() * map.metres_per_unit >= min_distance_m) pairs.emplace_back(road[a], road[b]);
  }
  return pairs;
}

int run(const Options& options) {
  planning::setOmplLogging(false);
  planning::seedOmpl(options.seed);
  std::filesystem::create_directories(options.out);

  const traversability::MapDirectory map = traversability::readMapDirectory(options.map);
  planning::WalkabilityConfig walkability;
  walkability.min_lethal_distance_m = map.profile.inscribed_radius_m;
  walkability.allow_unknown = options.allow_unknown;
  const auto graph_started = Clock::now();
  const planning::FaceGraph graph(map.map, walkability);
  const double graph_time = std::chrono::duration<double>(Clock::now() - graph_started).count();
  const std::size_t mesh_bytes = map.map.mesh.vertices.size() * sizeof(Eigen::Vector3d) +
                                 map.map.mesh.faces.size() * (sizeof(std::array<std::uint32_t, 3>) + sizeof(traversability::FaceLayers));

  const bool scene_dir = std::filesystem::is_directory(options.scene);
  const datasets::SlamStream stream =
      datasets::readAnyStream(scene_dir ? options.scene / "stream.tmstream" : options.scene);
  baselines::OctomapConfig octomap_config;
  octomap_config.resolution_m = options.resolution_m;
  octomap_config.metres_per_unit = map.map.metres_per_unit;
  octomap_config.up_W = map.map.up_W;
  baselines::OctomapBaseline octomap(octomap_config);
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) octomap.insertKeyframe(*keyframe);
  }
  octomap.writeBinary(options.out / "octomap.bt");
  baselines::GridRobotConfig robot;
  robot.max_step_m = map.profile.max_step_m;
  robot.max_slope_deg = map.profile.max_slope_deg;
  robot.min_clearance_m = map.profile.min_clearance_m;
  robot.footprint_radius_m = map.profile.inscribed_radius_m;
  robot.cost_weight = walkability.cost_weight;
  const auto grid_started = Clock::now();
  const baselines::HeightGrid grid = octomap.heightGrid(robot);
  const double grid_time = std::chrono::duration<double>(Clock::now() - grid_started).count();
  const baselines::OctomapStats octo = octomap.stats();

  // The truth, when there is one (a generated scene).
  const bool has_truth = scene_dir && std::filesystem::is_regular_file(options.scene / "ground_truth.ply");
  const datasets::LabeledMesh truth =
      has_truth ? datasets::readLabeledPly(options.scene / "ground_truth.ply") : datasets::LabeledMesh{};
  const datasets::TriangleBvh bvh(truth.mesh);
  evaluation::TruthCheckConfig truth_config;  // the map's robot; a rectangle as its circumscribed disc
  truth_config.footprint_radius_m = map.profile.footprintCircumradiusM();
  truth_config.max_step_m = map.profile.max_step_m;
  truth_config.min_clearance_m = map.profile.min_clearance_m;
  truth_config.max_slope_deg = map.profile.max_slope_deg;
  std::optional<evaluation::TruthChecker> checker;
  if (has_truth) checker.emplace(truth, bvh);

  planning::PlannerConfig config;
  config.planner = options.planner;
  config.time_budget_s = options.time_budget_s;
  config.time_cap_s = options.time_cap_s;
  config.seed = options.seed;
  config.snap_radius_m = options.snap_radius_m;
  config.validate();
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  std::string pairs_text;
  if (options.start) {
    pairs.emplace_back(*options.start, *options.goal);
    pairs_text = "the given start and goal";
  } else if (options.camera_height_m) {
    pairs = pairsUnderCameras(stream, map.map, *options.camera_height_m, options.pairs, options.seed, 5.0);
    pairs_text = std::to_string(pairs.size()) + " pairs among the keyframe centres lowered by " +
                 std::to_string(*options.camera_height_m) + " m";
  } else {
    for (const auto& [a, b] : planning::drawRandomPairs(graph, options.pairs, options.seed, 5.0)) {
      pairs.emplace_back(a.point_W, b.point_W);
    }
    pairs_text = std::to_string(pairs.size()) + " random pairs on the mesh's largest walkable component";
  }
  const std::vector<std::string> properties = {"time REAL", "solved BOOLEAN", "surface length REAL", "path cost REAL",
                                               "valid against ground truth BOOLEAN"};
  Tally mesh{{"geometric_" + options.planner, properties, {}}}, voxels{{"geometric_" + options.planner, properties, {}}};
  Tally graph_tally{{"graph_astar", properties, {}}};
  std::ostringstream csv;
  csv << "pair,map,status,length_m,cost,time_s,truth_valid,truth_reason,start_x,start_y,start_z,goal_x,goal_y,goal_z,"
         "reason\n";
  auto row = [&](std::size_t i, const char* type, planning::PlanStatus status, double length, double cost, double time,
                 const evaluation::TruthCheck& check, bool checked, const std::string& reason) {
    const Eigen::Vector3d& a = pairs[i].first;
    const Eigen::Vector3d& b = pairs[i].second;
    csv << i << ',' << type << ',' << planning::toString(status) << ',' << length << ',' << cost << ',' << time << ','
        << (checked ? (check.valid ? "1" : "0") : "") << ",\"" << check.reason << "\"," << a.x() << ',' << a.y() << ','
        << a.z() << ',' << b.x() << ',' << b.y() << ',' << b.z() << ",\"" << reason << "\"\n";
  };
  // Checks a path against the truth (only when solved), tallies it and writes its CSV row.
  auto record = [&](std::size_t i, const char* type, Tally& tally, planning::PlanStatus status, bool solved,
                    const std::vector<Eigen::Vector3d>& path, double length, double cost, double time,
                    const std::string& reason) {
    const bool checked = solved && has_truth;
    const evaluation::TruthCheck check =
        checked ? checker->check(path, map.map.up_W, map.map.metres_per_unit, truth_config)
                : evaluation::TruthCheck{};
    tally.add(solved, length, cost, time, check.valid, checked);
    row(i, type, status, length, cost, time, check, checked, reason);
  };
  auto statesOf = [](const planning::PlanResult& result) {
    std::vector<Eigen::Vector3d> points;
    for (const planning::PathState& s : result.states) points.push_back(s.location.point_W);
    return points;
  };
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Eigen::Vector3d a = pairs[i].first, b = pairs[i].second;
    const planning::PlanResult on_mesh = planning::planOnSurface(graph, a, b, config);
    record(i, "mesh", mesh, on_mesh.status, on_mesh.solved(), statesOf(on_mesh), on_mesh.length_m, on_mesh.cost,
           on_mesh.planning_time_s, on_mesh.reason);
    const planning::PlanResult on_graph = planning::planOnFaceGraph(graph, a, b, config);
    record(i, "mesh_graph", graph_tally, on_graph.status, on_graph.solved(), statesOf(on_graph), on_graph.length_m,
           on_graph.cost, on_graph.planning_time_s, on_graph.reason);
    const baselines::GridPlanResult on_grid = baselines::planOnGrid(grid, a, b, config, robot.cost_weight);
    record(i, "octomap", voxels, on_grid.status, on_grid.solved(), on_grid.points_W, on_grid.length_m, on_grid.cost,
           on_grid.planning_time_s, on_grid.reason);
  }
  writeFileAtomically(options.out / "pairs.csv", csv.str());

  auto experiment = [&](const std::string& type, std::vector<planning::BenchmarkPlannerRuns> runs) {
    planning::BenchmarkExperiment e;
    e.name = "terramesh_planner_demo";
    e.parameters = {{"map_type", type}};
    e.setup = "scene " + options.scene.string() + ", map " + options.map.string() + ", " + pairs_text;
    e.seed = options.seed;
    e.time_limit_s = options.time_budget_s;
    e.run_count = pairs.size();
    e.planners = std::move(runs);
    return e;
  };
  planning::writeOmplBenchmarkLog(options.out / "mesh.log", experiment("mesh", {mesh.runs, graph_tally.runs}));
  planning::writeOmplBenchmarkLog(options.out / "octomap.log", experiment("octomap", {voxels.runs}));

  std::ostringstream table;
  table.precision(4);
  auto line = [&](const std::string& name, const Tally& t, double build_s, std::size_t bytes) {
    const double n = static_cast<double>(std::max<std::size_t>(t.solved, 1));
    table << "| " << name << " | " << t.solved << "/" << pairs.size() << " | " << t.length / n << " | " << t.cost / n
          << " | " << t.time / static_cast<double>(std::max<std::size_t>(pairs.size(), 1)) << " | " << build_s << " | "
          << static_cast<double>(bytes) / 1e6 << " | ";
    if (has_truth) table << t.truth_valid << "/" << t.truth_checked << " |\n";
    else table << "- (no truth) |\n";
  };
  table << "| map | solved | mean length (m) | mean cost | mean planning time (s) | map build time (s) | map memory (MB) | "
           "valid on ground truth |\n|---|---|---|---|---|---|---|---|\n";
  line("mesh, " + options.planner, mesh, graph_time, mesh_bytes);
  line("mesh, graph A*", graph_tally, graph_time, mesh_bytes);
  line("octomap " + std::to_string(options.resolution_m).substr(0, 4) + " m, " + options.planner, voxels,
       octo.build_time_s + grid_time, octo.memory_bytes + grid.memoryBytes());
  double walkable_area = 0, largest = 0;
  for (std::uint32_t c = 0; c < graph.componentCount(); ++c) {
    walkable_area += graph.componentArea(c);
    largest = std::max(largest, graph.componentArea(c));
  }
  const double area_scale = map.map.metres_per_unit * map.map.metres_per_unit;
  table << "\npairs: " << pairs_text << "\nmesh: " << graph.walkableFaceCount() << " walkable faces of " << graph.faceCount()
        << ", " << walkable_area * area_scale << " m^2 in " << graph.componentCount() << " walkable components, the largest "
        << largest * area_scale << " m^2 (build time here: the planner's face graph only; the mesher and layers are "
        << "timed by their commands)\n"
        << "octomap: " << octo.keyframes << " keyframes, " << octo.points << " points, " << octo.leaves << " leaves ("
        << octo.occupied_leaves << " occupied), insertion " << octo.build_time_s << " s, grid " << grid_time << " s; grid "
        << grid.width << " x " << grid.height << ", " << grid.knownCells() << " known cells, " << grid.traversableCells()
        << " traversable\n";
  writeFileAtomically(options.out / "comparison.md", table.str());
  std::cout << table.str();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::invalid_argument& error) {
    std::cerr << "planner_demo: " << error.what() << '\n';
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "planner_demo: " << error.what() << '\n';
    return 1;
  }
}

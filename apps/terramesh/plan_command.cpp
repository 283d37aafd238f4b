// terramesh plan MAP --start X Y Z --goal X Y Z -o OUT: a path a ground robot can drive, on the
// traversability mesh, with OMPL; or --random-pairs N for a benchmark against the face-graph optimum.
// MAP is a map directory or a tiled map (plan_tiles.h).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <unistd.h>

#include "cli_args.h"
#include "commands.h"
#include "plan_tiles.h"
#include "common/atomic_file.h"
#include "planning/face_graph.h"
#include "planning/ompl_benchmark_log.h"
#include "planning/path_planner.h"
#include "planning/surface_planner.h"
#include "traversability/map_directory.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/traversability_map.h"

namespace terramesh::cli {
namespace {

/// Three finite numbers into a point.
/// @throw UsageError naming the option.
Eigen::Vector3d toPoint(const std::vector<double>& values, const std::string& name) {
  const Eigen::Vector3d p(values.at(0), values.at(1), values.at(2));
  if (!p.allFinite()) throw UsageError("plan: " + name + " expects three finite numbers X Y Z");
  return p;
}

void writePathFiles(const std::filesystem::path& out, const planning::PlanResult& result) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "x,y,z,yaw,face,cost\n";
  for (const planning::PathState& state : result.states) {
    const Eigen::Vector3d& p = state.location.point_W;
    csv << p.x() << ',' << p.y() << ',' << p.z() << ',' << state.yaw_rad << ',' << state.location.face << ','
        << state.face_cost << '\n';
  }
  writeFileAtomically(out / "path.csv", csv.str());
  std::ostringstream ply;
  ply.precision(10);
  ply << "ply\nformat ascii 1.0\ncomment terramesh plan: the path as a line set\nelement vertex " << result.states.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nelement edge "
      << (result.states.empty() ? 0 : result.states.size() - 1)
      << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  for (const planning::PathState& state : result.states) {
    const Eigen::Vector3d& p = state.location.point_W;
    ply << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  }
  for (std::size_t i = 1; i < result.states.size(); ++i) ply << i - 1 << ' ' << i << '\n';
  writeFileAtomically(out / "path.ply", ply.str());
}

std::string describe(const planning::PlanResult& result) {
  std::ostringstream out;
  out << "planner " << result.planner << "\nstatus " << planning::toString(result.status) << "\nreason "
      << (result.reason.empty() ? "-" : result.reason) << "\ntime_s " << result.planning_time_s << "\nsimplify_time_s "
      << result.simplify_time_s << "\nlength_m " << result.length_m << "\ncost " << result.cost << "\nunknown_length_m "
      << result.unknown_length_m << "\nfirst_cost " << result.first_cost << "\nfirst_time_s " << result.first_time_s
      << "\nstates " << result.states.size() << '\n';
  return out.str();
}

std::string hostname() {
  char name[256] = {};
  return gethostname(name, sizeof(name) - 1) == 0 ? std::string(name) : std::string("unknown");
}

/// `count` random pairs planned with the chosen planner (`graph_only`: the face-graph A*) and with
/// the graph baseline beside it.
int runRandomPairs(const planning::FaceGraph& graph, const planning::PlannerConfig& config, bool graph_only,
                   std::size_t count, const std::filesystem::path& out, bool quiet) {
  const std::string planner_name = graph_only ? std::string("graph") : config.planner;
  const auto started = std::chrono::steady_clock::now();
  const auto pairs = planning::drawRandomPairs(graph, count, config.seed, 5.0);
  if (pairs.empty()) throw std::runtime_error("plan: no walkable component to draw pairs from");
  planning::BenchmarkPlannerRuns sampled{graph_only ? std::string("graph_astar") : "geometric_" + config.planner,
                                         {"time REAL", "solved BOOLEAN", "surface length REAL", "path cost REAL",
                                          "first solution time REAL", "simplification time REAL",
                                          "graph optimum cost REAL", "cost over graph optimum REAL"},
                                         {}};
  planning::BenchmarkPlannerRuns graph_runs{"graph_astar", {"time REAL", "solved BOOLEAN", "surface length REAL", "path cost REAL"}, {}};
  std::ostringstream csv;
  csv << "pair,start_x,start_y,start_z,goal_x,goal_y,goal_z,status,length_m,cost,time_s,graph_cost,graph_time_s,"
         "unknown_length_m\n";
  std::size_t solved = 0;
  const planning::SurfacePlanner graph_astar(graph, config, true), sampled_planner(graph, config, graph_only);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Eigen::Vector3d a = pairs[i].first.point_W, b = pairs[i].second.point_W;
    const planning::PlanResult graph_result = graph_astar.plan(a, b);
    const planning::PlanResult result = sampled_planner.plan(a, b);
    solved += result.solved() ? 1 : 0;
    const double nan = std::nan("");
    sampled.runs.push_back({result.planning_time_s, result.solved() ? 1.0 : 0.0, result.solved() ? result.length_m : nan,
                            result.solved() ? result.cost : nan, result.first_time_s, result.simplify_time_s,
                            graph_result.cost, result.solved() ? result.cost / graph_result.cost : nan});
    graph_runs.runs.push_back({graph_result.planning_time_s, graph_result.solved() ? 1.0 : 0.0, graph_result.length_m,
                               graph_result.cost});
    csv << i << ',' << a.x() << ',' << a.y() << ',' << a.z() << ',' << b.x() << ',' << b.y() << ',' << b.z() << ','
        << planning::toString(result.status) << ',' << result.length_m << ',' << result.cost << ','
        << result.planning_time_s << ',' << graph_result.cost << ',' << graph_result.planning_time_s << ','
        << result.unknown_length_m << '\n';
  }
  planning::BenchmarkExperiment experiment;
  experiment.name = "terramesh_plan";
  experiment.parameters = {{"map_type", "mesh"}};
  experiment.hostname = hostname();
  experiment.setup = std::to_string(pairs.size()) + " random start/goal pairs on the largest walkable component";
  experiment.seed = config.seed;
  experiment.time_limit_s = config.time_budget_s;
  experiment.run_count = pairs.size();
  experiment.total_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  experiment.planners = {sampled};
  if (!graph_only) experiment.planners.push_back(graph_runs);
  planning::writeOmplBenchmarkLog(out / "benchmark.log", experiment);
  writeFileAtomically(out / "pairs.csv", csv.str());
  std::ostringstream summary;
  summary << "planner " << planner_name << "\npairs " << pairs.size() << "\nsolved " << solved << '\n';
  writeFileAtomically(out / "plan.txt", summary.str());
  if (!quiet) std::cout << summary.str();
  return kExitOk;
}

/// The options of `terramesh plan`.
struct PlanOptions {
  std::string map_dir, output_dir, planner = "bitstar";
  std::vector<double> start_xyz, goal_xyz;
  double time_budget_s = 2, time_cap_s = 0, snap_radius_m = 0.5, unknown_cost = 1.0;
  std::uint32_t seed = 1;
  std::optional<std::size_t> random_pairs;
  std::optional<std::string> robot;
  std::optional<double> tile_margin_m;
  bool no_simplify = false, quiet = false, allow_unknown = false, allow_uncertain = false;
};

void declareOptions(CLI::App& app, PlanOptions& o) {
  app.option_defaults()->always_capture_default();
  app.footer(
      "writes OUT/path.csv (x,y,z,yaw,face,cost), OUT/path.ply (line set) and OUT/plan.txt; exit code 3 when the "
      "goal is unreachable (one-line reason)");
  app.add_option("MAP", o.map_dir,
                 "map directory written by terramesh traverse or mesh (traversability.ply, robot.yaml, "
                 "map_frame.yaml), or a tiled map: its tile index (tiles.json of terramesh tiles merge) or its folder")
      ->required();
  app.add_option("--start", o.start_xyz, "start point, map frame and units (snapped to the nearest walkable face)")
      ->expected(3)
      ->option_text("X Y Z");
  app.add_option("--goal", o.goal_xyz, "goal point")->expected(3)->option_text("X Y Z");
  app.add_option("-o,--output", o.output_dir, "output directory (created if missing)")->option_text("DIR");
  app.add_option("--planner", o.planner,
                 "rrtstar, informed-rrtstar, prmstar, lazyprmstar, bitstar, aitstar, or graph (A* baseline)");
  app.add_option("--time-budget-s", o.time_budget_s, "planning time budget per query");
  app.add_option("--time-cap-s", o.time_cap_s,
                 "without a path after the budget, keep searching until one is found or this much time has passed "
                 "(0: no extension)");
  app.add_flag("--allow-unknown", o.allow_unknown,
               "drive over unknown faces too (Nav2's allow_unknown), at --unknown-cost; never over lethal ones");
  app.add_option("--unknown-cost", o.unknown_cost, "cost in [0, 1] of an unknown face with --allow-unknown")
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag("--allow-uncertain", o.allow_uncertain,
               "drive over uncertain faces too (measured, the evidence cannot decide), at the profile's "
               "evidence.uncertain_cost");
  app.add_option("--seed", o.seed, "random seed (> 0)")->check(positiveNumber());
  app.add_option("--snap-radius-m", o.snap_radius_m, "start and goal must lie this close to a walkable face");
  app.add_option("--random-pairs", o.random_pairs,
                 "plan between N random pairs instead; writes benchmark.log and pairs.csv")
      ->option_text("N")
      ->check(positiveNumber());
  app.add_option("--robot", o.robot, "recompute the layers for this robot profile (YAML) instead of robot.yaml")
      ->option_text("FILE");
  app.add_option("--tile-margin-m", o.tile_margin_m,
                 "tiled map: load the tiles within this distance of start and goal first, twice as far while they "
                 "do not connect the two (default: one tile)")
      ->option_text("M");
  app.add_flag("--no-simplify", o.no_simplify, "keep the planner's raw path");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
}

/// The planner's settings from the options ("graph" plans with A* on the face graph; the OMPL
/// planner configured then is never run).
/// @throw std::invalid_argument for settings out of range.
planning::PlannerConfig plannerConfig(const PlanOptions& o) {
  planning::PlannerConfig config;
  config.planner = o.planner == "graph" ? "rrtstar" : o.planner;
  config.time_budget_s = o.time_budget_s;
  config.time_cap_s = o.time_cap_s;
  config.seed = o.seed;
  config.snap_radius_m = o.snap_radius_m;
  config.simplify = !o.no_simplify;
  config.validate();
  return config;
}

/// The map directory, its layers recomputed for --robot when given.
traversability::MapDirectory loadMap(const PlanOptions& o) {
  traversability::MapDirectory map = traversability::readMapDirectory(o.map_dir);
  if (!o.robot) return map;
  map.profile = traversability::loadRobotProfile(*o.robot);
  map.profile.validate();
  traversability::MapFrame frame;
  frame.up_W = map.map.up_W;
  frame.metres_per_unit = map.map.metres_per_unit;
  map.map = traversability::TraversabilityMap::computeForMesh(map.map.mesh, map.profile, frame,
                                                              static_cast<std::uint32_t>(map.profile.min_rays));
  return map;
}

/// Writes plan.txt (`describe` and `extra` lines) and, for a path, path.csv and path.ply; the exit
/// code: 0 solved, 1 not found in the budget, 3 unreachable.
int finishPlan(const planning::PlanResult& result, const std::filesystem::path& out, bool quiet,
               const std::string& extra) {
  writeFileAtomically(out / "plan.txt", describe(result) + extra);
  if (result.solved()) {
    writePathFiles(out, result);
    if (!quiet) std::cout << describe(result) << extra;
    return kExitOk;
  }
  if (result.status == planning::PlanStatus::kNotFound) {
    std::cerr << "terramesh: plan: " << result.reason << '\n';
    return kExitFailure;
  }
  std::cerr << "terramesh: plan: unreachable: " << result.reason << '\n';
  return kExitUnreachable;
}

/// The walkability the options ask for, for `profile`.
planning::WalkabilityConfig walkabilityOf(const PlanOptions& o, const traversability::RobotProfile& profile) {
  planning::WalkabilityConfig walkability = planning::walkabilityFor(profile);
  walkability.allow_unknown = o.allow_unknown;
  walkability.unknown_cost = o.unknown_cost;
  walkability.allow_uncertain = o.allow_uncertain;
  return walkability;
}

/// One query on a tiled map: the tiles around start and goal, joined (plan_tiles.h).
int runPlanOnTiles(const PlanOptions& o, const std::filesystem::path& index, const planning::PlannerConfig& config) {
  if (o.robot) throw UsageError("plan: --robot recomputes one map's layers; a tiled map's were computed per tile");
  if (o.random_pairs) throw UsageError("plan: --random-pairs needs a map directory, not a tile index");
  if (o.tile_margin_m && !(*o.tile_margin_m > 0)) throw UsageError("plan: --tile-margin-m must be > 0");
  const Eigen::Vector3d start = toPoint(o.start_xyz, "--start"), goal = toPoint(o.goal_xyz, "--goal");
  const TiledPlan tiled = planOnTiles(
      index, start, goal, o.tile_margin_m, o.snap_radius_m,
      [&](const traversability::LayeredMesh& map, const traversability::RobotProfile& profile) {
        const planning::FaceGraph graph(map, walkabilityOf(o, profile));
        return planning::SurfacePlanner(graph, config, o.planner == "graph").plan(start, goal);
      });
  const std::filesystem::path out = o.output_dir;
  std::filesystem::create_directories(out);
  return finishPlan(tiled.result, out, o.quiet, tiled.describe());
}

}  // namespace

int runPlan(const std::vector<std::string>& args) {
  CLI::App app{"drivable path on a traversability map (OMPL on the surface; exit 3 if unreachable)", "terramesh plan"};
  PlanOptions o;
  declareOptions(app, o);
  if (!parseCommandLine(app, args)) return kExitOk;
  if (o.output_dir.empty()) throw UsageError("plan: -o/--output DIR is required");
  const bool random = o.random_pairs.has_value();
  if (!random && (o.start_xyz.empty() || o.goal_xyz.empty())) {
    throw UsageError("plan: give --start X Y Z and --goal X Y Z, or --random-pairs N");
  }
  const planning::PlannerConfig config = plannerConfig(o);
  planning::setOmplLogging(false);
  planning::seedOmpl(config.seed);
  if (const std::optional<std::filesystem::path> index = tileIndexOf(o.map_dir)) {
    return runPlanOnTiles(o, *index, config);
  }
  if (o.tile_margin_m) throw UsageError("plan: --tile-margin-m needs a tile index (tiles.json) as MAP");
  const traversability::MapDirectory map = loadMap(o);
  const planning::FaceGraph graph(map.map, walkabilityOf(o, map.profile));

  const std::filesystem::path out = o.output_dir;
  std::filesystem::create_directories(out);
  if (random) return runRandomPairs(graph, config, o.planner == "graph", *o.random_pairs, out, o.quiet);
  const Eigen::Vector3d start = toPoint(o.start_xyz, "--start"), goal = toPoint(o.goal_xyz, "--goal");
  return finishPlan(planning::SurfacePlanner(graph, config, o.planner == "graph").plan(start, goal), out, o.quiet, "");
}

}  // namespace terramesh::cli

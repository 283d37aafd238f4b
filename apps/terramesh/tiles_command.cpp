// terramesh tiles plan|merge: a stream cut into tiles meshed apart (`mesh --tile`), and the tiled
// map joined from them (docs/tiles.md).
#include <iomanip>
#include <iostream>
#include <sstream>

#include "cli_args.h"
#include "commands.h"
#include "common/input_error.h"
#include "datasets/stream_reader.h"
#include "input_options.h"
#include "mesher_options.h"
#include "tiling/tile_files.h"
#include "tiling/tile_merge.h"
#include "tiling/tile_plan.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability_session.h"

namespace terramesh::cli {
namespace {

struct PlanOptions {
  std::string input_path, plan_path;
  tiling::TilingConfig tiling;
  std::optional<std::string> robot;
  std::optional<double> metres_per_unit;
  bool quiet = false;
  InputOptions input;
};

int runTilesPlan(const std::vector<std::string>& args) {
  CLI::App app{"cut a stream into tiles: writes the plan (tiles, bounds, each tile's input)", "terramesh tiles plan"};
  app.option_defaults()->always_capture_default();
  PlanOptions o;
  app.add_option("INPUT", o.input_path, "SLAM stream (any format mesh reads)")->required();
  app.add_option("-o,--output", o.plan_path, "plan file (JSON); the tiles' outputs go beside it")->option_text("PLAN");
  app.add_option("--tile-m", o.tiling.tile_m, "side of a tile in the map plane, metres")->check(positiveNumber());
  app.add_option("--overlap-m", o.tiling.overlap_m,
                 "how far beyond its bounds a tile's map reaches (where neighbours' maps meet), metres")
      ->check(nonNegativeNumber());
  app.add_option("--guard-m", o.tiling.guard_m,
                 "how much farther than the overlap a tile also reads the stream, so that its input's edge "
                 "leaves the overlap's surface as a run on the whole stream meshes it, metres")
      ->check(nonNegativeNumber());
  app.add_option("--robot", o.robot, "the robot profile the tiles will be meshed with (its gravity gives up)")
      ->option_text("YAML");
  app.add_option("--metres-per-unit", o.metres_per_unit, "the scale mesh will use (default: the stream's, else 1)")
      ->check(positiveNumber());
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
  addInputOptions(app, o.input);
  if (!parseCommandLine(app, args)) return kExitOk;
  if (o.plan_path.empty()) throw UsageError("tiles plan: -o/--output PLAN is required");
  o.tiling.validate();
  const datasets::SlamStream stream = datasets::readAnyStream(o.input_path, streamReadOptionsFrom(o.input));
  if (!o.quiet) printReaderNotes(std::cerr, stream);
  MesherOptions scale;
  scale.metres_per_unit = o.metres_per_unit;
  const double metres_per_unit = mesherConfigFrom(scale, mesher::MesherMode::kProposed, stream).metres_per_unit;
  std::optional<StreamUp> up;
  if (o.robot) {
    up = mapUpFor(traversability::loadRobotProfile(*o.robot), stream);
  } else {
    up = upFromKeyframes(stream);
  }
  if (!up) throw InputError(o.input_path, "", "no keyframe: nothing to tile");
  const tiling::TilePlan plan = tiling::planTiles(stream, up->up_W, metres_per_unit, o.tiling);
  const std::filesystem::path plan_path = o.plan_path;
  if (plan_path.has_parent_path()) std::filesystem::create_directories(plan_path.parent_path());
  tiling::writeTilePlan(plan_path, plan);
  if (o.quiet) return kExitOk;
  std::cout << "plan: " << plan_path.string() << ", " << plan.tiles.size() << " tile(s) of " << o.tiling.tile_m
            << " m with " << o.tiling.overlap_m << " m overlap and " << o.tiling.guard_m << " m guard; up "
            << up->up_W.transpose() << " (" << up->source << ")\n";
  for (const tiling::TileSpec& tile : plan.tiles) {
    std::cout << "  " << tile.index << " " << tile.name << ": x [" << tile.bounds.min_x_m << ", " << tile.bounds.max_x_m
              << ") y [" << tile.bounds.min_y_m << ", " << tile.bounds.max_y_m << ") m, " << tile.keyframes
              << " keyframes, " << tile.points << " points\n";
  }
  return kExitOk;
}

int runTilesMerge(const std::vector<std::string>& args) {
  CLI::App app{"join the meshed tiles of a plan: tile index (tiles.json) and overview Nav2 maps",
               "terramesh tiles merge"};
  app.option_defaults()->always_capture_default();
  std::string plan_path;
  tiling::MergeConfig config;
  bool quiet = false;
  app.add_option("PLAN", plan_path, "plan file written by terramesh tiles plan")->required();
  app.add_option("--overview-resolution-m", config.overview_resolution_m, "cell size of the overview Nav2 maps, metres")
      ->check(positiveNumber());
  app.add_flag("--check-borders", config.check_borders,
               "also print how far the classes of neighbouring tiles agree over their overlap, and within half "
               "the overlap of their border");
  app.add_option("--border-cell-m", config.border_cell_m, "cell size of that comparison, metres")->check(positiveNumber());
  std::optional<std::string> compare_with;
  app.add_option("--compare-with", compare_with,
                 "also print how far the joined tiles' classes agree with the map in this folder (same frame, e.g. "
                 "a run without --freeze-radius-m) over the tiled area, at --border-cell-m")
      ->option_text("MAPDIR");
  app.add_flag("--quiet", quiet, "print nothing but errors");
  if (!parseCommandLine(app, args)) return kExitOk;
  if (compare_with) config.compare_with = *compare_with;
  const tiling::MergeReport report = tiling::mergeTiles(plan_path, config);
  if (quiet) return kExitOk;
  std::cout << "merged: " << report.tiles << " tile(s), " << report.faces << " faces, overview " << report.overview_levels
            << " level(s) at " << config.overview_resolution_m << " m; index "
            << (std::filesystem::path(plan_path).parent_path() / "tiles.json").string() << '\n';
  if (report.compared) {
    std::cout << "against " << *compare_with << ": classes agree on " << std::fixed << std::setprecision(4)
              << report.compared->fraction() << " (free or not: " << report.compared->freeFraction() << ") of "
              << std::setprecision(1) << report.compared->compared_m2 << " m2 both cover; the tiles alone cover "
              << report.compared->only_a_m2 << " m2, the other map alone " << report.compared_only_other_m2 << " m2\n"
              << std::defaultfloat << std::setprecision(6);
  }
  for (const tiling::BorderAgreement& border : report.borders) {
    std::cout << "border " << border.tile_a << "|" << border.tile_b << ": classes agree on " << std::fixed
              << std::setprecision(4) << border.agreement.fraction() << " (free or not: "
              << border.agreement.freeFraction() << ") of " << std::setprecision(1)
              << border.agreement.compared_m2 << " m2 compared in the overlap; within " << 0.5 * report.overlap_m
              << " m of the border: " << std::setprecision(4) << border.at_seam.fraction() << " (free or not: "
              << border.at_seam.freeFraction() << ") of " << std::setprecision(1) << border.at_seam.compared_m2 << " m2\n"
              << std::defaultfloat << std::setprecision(6);
  }
  return kExitOk;
}

}  // namespace

int runTiles(const std::vector<std::string>& args) {
  const std::string usage = "tiles: expected a subcommand, plan or merge (terramesh tiles plan --help)";
  if (args.empty()) throw UsageError(usage);
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (args.front() == "plan") return runTilesPlan(rest);
  if (args.front() == "merge") return runTilesMerge(rest);
  if (args.front() == "-h" || args.front() == "--help") {
    std::cout << "usage: terramesh tiles plan STREAM --tile-m M --overlap-m M -o PLAN\n"
                 "       terramesh tiles merge PLAN\n(see docs/tiles.md)\n";
    return kExitOk;
  }
  throw UsageError(usage + ", got \"" + args.front() + "\"");
}

}  // namespace terramesh::cli

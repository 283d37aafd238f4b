// terramesh pairs GT.ply --robot R.yaml -o pairs.csv: start/goal pairs on a labelled ground truth
// with, per pair, whether the truth joins them for that robot (evaluation::TruthReachability).
// Random pairs come from evaluation::pairsOnObservedTruth (as in terramesh compare); the hazards
// scene adds one pair across each of its hazards (hazards.csv of terramesh generate).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "common/input_error.h"
#include "datasets/kitti_odometry_reader.h"
#include "datasets/labeled_mesh.h"
#include "datasets/triangle_bvh.h"
#include "evaluation/ground_truth_traversability.h"
#include "evaluation/robot_limits.h"
#include "evaluation/truth_checker.h"
#include "evaluation/truth_pairs.h"
#include "evaluation/truth_reachability.h"
#include "traversability/robot_profile.h"
#include "traversability/robot_profile_yaml.h"

namespace terramesh::cli {
namespace {

struct PairsOptions {
  std::string truth;
  std::string robot;
  std::string output;
  std::optional<std::string> trajectory, hazards;
  std::size_t pairs = 10;
  long seed = 1;
  double min_distance_m = 5.0;
  bool quiet = false;
};

void declareOptions(CLI::App& app, PairsOptions& o) {
  app.add_option("GT", o.truth, "labelled ground truth (ground_truth.ply of terramesh generate)")->required();
  app.add_option("--robot", o.robot, "robot profile (traversability/robots/*.yaml)")->required()->option_text("FILE");
  app.add_option("-o,--output", o.output, "CSV to write")->required()->option_text("FILE");
  app.add_option("--pairs", o.pairs, "random pairs on the observed, driven truth (0: none)");
  app.add_option("--seed", o.seed, "seed of the random pairs")->check(nonNegativeNumber());
  app.add_option("--min-distance-m", o.min_distance_m, "random pairs are at least D apart in a straight line")
      ->check(nonNegativeNumber());
  app.add_option("--trajectory", o.trajectory,
                 "keyframe poses (KITTI format) that observed the truth (default: trajectory.txt beside GT)")
      ->option_text("FILE");
  app.add_option("--hazards", o.hazards, "hazards to cross (default: hazards.csv beside GT, if any)")
      ->option_text("FILE");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
}

/// A start and goal to write, with where it came from.
struct PairRow {
  std::string source;  ///< "random" or the hazard's kind
  std::string name;    ///< "random_3" or the hazard's name
  Eigen::Vector3d start_W, goal_W;
  double truth_length_m = std::nan("");
};

/// The pairs of a hazards.csv (terramesh generate hazards): name, kind, ..., start, goal.
std::vector<PairRow> readHazardPairs(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "file", "cannot be opened");
  std::vector<PairRow> rows;
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    if (++number == 1 || line.empty()) continue;  // header
    std::vector<std::string> fields;
    std::istringstream split(line);
    for (std::string field; std::getline(split, field, ',');) fields.push_back(field);
    if (fields.size() != 17) {
      throw InputError(path.string(), lineLocation(number), "expected 17 fields, got " + std::to_string(fields.size()));
    }
    PairRow row;
    row.name = fields[0];
    row.source = fields[1];
    try {
      for (int k = 0; k < 3; ++k) {
        row.start_W[k] = std::stod(fields[11 + k]);
        row.goal_W[k] = std::stod(fields[14 + k]);
      }
    } catch (const std::exception&) {
      throw InputError(path.string(), lineLocation(number), "start and goal must be numbers");
    }
    if (!row.start_W.allFinite() || !row.goal_W.allFinite()) {
      throw InputError(path.string(), lineLocation(number), "start and goal must be finite");
    }
    rows.push_back(row);
  }
  return rows;
}

/// Random pairs on the truth's traversable area that the keyframes at `trajectory` observed.
std::vector<PairRow> randomPairs(const evaluation::GroundTruthTraversability& labels,
                                 const datasets::TriangleBvh& truth_bvh, const std::filesystem::path& trajectory,
                                 const PairsOptions& options) {
  std::vector<Eigen::Vector3d> cameras;
  for (const Eigen::Isometry3d& pose : datasets::readKittiPoses(trajectory)) cameras.push_back(pose.translation());
  evaluation::TruthPairsConfig config;
  config.count = options.pairs;
  config.seed = static_cast<std::uint64_t>(options.seed);
  config.min_distance_m = options.min_distance_m;
  std::vector<PairRow> rows;
  const evaluation::TruthPairs drawn = evaluation::pairsOnObservedTruth(labels, truth_bvh, cameras, config);
  for (const evaluation::ComparePair& pair : drawn.pairs) {
    rows.push_back({"random", "random_" + std::to_string(rows.size() + 1), pair.start_W, pair.goal_W,
                    pair.truth_length_m});
  }
  return rows;
}

/// The straight line from start to goal in plan, draped on the truth: every `spacing_m`, the
/// first surface below the line lifted by `lift_m` (on a wall or a rock it is their top, which the
/// path check then refuses). Where nothing is below, the line itself.
std::vector<Eigen::Vector3d> drapedLine(const datasets::TriangleBvh& truth_bvh, const Eigen::Vector3d& start_W,
                                        const Eigen::Vector3d& goal_W, const Eigen::Vector3d& up_W, double spacing_m,
                                        double lift_m) {
  const auto steps = static_cast<std::size_t>(std::ceil((goal_W - start_W).norm() / spacing_m));
  std::vector<Eigen::Vector3d> path;
  for (std::size_t i = 0; i <= std::max<std::size_t>(steps, 1); ++i) {
    const Eigen::Vector3d p = start_W + (goal_W - start_W) * static_cast<double>(i) / std::max<std::size_t>(steps, 1);
    const double top = std::max(start_W.dot(up_W), goal_W.dot(up_W)) + lift_m;
    const Eigen::Vector3d above = p + (top - p.dot(up_W)) * up_W;
    const auto hit = truth_bvh.firstHit(above, -up_W, 2 * lift_m + (top - p.dot(up_W)));
    path.push_back(hit ? hit->point : p);
  }
  return path;
}

std::optional<std::filesystem::path> besideTruth(const PairsOptions& options, const std::optional<std::string>& given,
                                                 const char* name) {
  if (given) return std::filesystem::path(*given);
  const std::filesystem::path beside = std::filesystem::path(options.truth).parent_path() / name;
  if (std::filesystem::is_regular_file(beside)) return beside;
  return std::nullopt;
}

/// pairs.csv: every row with the truth's answer and the straight line's check; counts the
/// reachable ones into `reachable`.
std::string pairsCsv(const std::vector<PairRow>& rows, const datasets::LabeledMesh& truth,
                     const datasets::TriangleBvh& truth_bvh, const evaluation::TruthReachability& reach,
                     const Eigen::Vector3d& up, const traversability::RobotProfile& profile, std::size_t& reachable) {
  const evaluation::TruthChecker checker(truth, truth_bvh);
  const evaluation::TruthCheckConfig check = evaluation::truthCheckConfigFrom(profile);
  std::ostringstream csv;
  csv.precision(10);
  csv << "pair,source,name,start_x,start_y,start_z,goal_x,goal_y,goal_z,reachable,reason,truth_length_m,"
         "straight_valid,straight_reason\n";
  reachable = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const PairRow& r = rows[i];
    const evaluation::ReachAnswer answer = reach.connects(r.start_W, r.goal_W);
    const evaluation::TruthCheck straight =
        checker.check(drapedLine(truth_bvh, r.start_W, r.goal_W, up, check.spacing_m, 2.5), up, 1.0, check);
    reachable += answer.reachable() ? 1 : 0;
    csv << i << ',' << r.source << ',' << r.name << ',' << r.start_W.x() << ',' << r.start_W.y() << ','
        << r.start_W.z() << ',' << r.goal_W.x() << ',' << r.goal_W.y() << ',' << r.goal_W.z() << ','
        << (answer.reachable() ? 1 : 0) << ',' << evaluation::toString(answer.status) << ',' << r.truth_length_m
        << ',' << (straight.valid ? 1 : 0) << ",\"" << straight.reason << "\"\n";
  }
  return csv.str();
}

}  // namespace

int runPairs(const std::vector<std::string>& args) {
  CLI::App app{"start/goal pairs on a labelled ground truth, each with whether the truth joins them for a robot",
               "terramesh pairs"};
  app.option_defaults()->always_capture_default();
  app.footer(
      "Writes one row per pair: reachable is 1 when start and goal land on traversable truth faces of one "
      "component (faces joined through shared edges, both traversable for the robot), with the reason "
      "otherwise; straight_valid says whether driving straight at them (the line in plan, draped on the truth) "
      "is drivable on the truth (planner_demo's path check), straight_reason why not. See docs/synthetic_data.md.");
  PairsOptions options;
  declareOptions(app, options);
  if (!parseCommandLine(app, args)) return kExitOk;
  const traversability::RobotProfile profile = traversability::loadRobotProfile(options.robot);
  const datasets::LabeledMesh truth = datasets::readLabeledPly(options.truth);
  if (truth.mesh.faces.empty()) throw InputError(options.truth, "faces", "the ground truth has no faces");
  const Eigen::Vector3d up = evaluation::estimateUpFromSlopes(truth);
  const evaluation::GroundTruthTraversability labels =
      evaluation::labelTraversability(truth, evaluation::robotLimitsFrom(profile), up, {});
  const evaluation::TruthReachability reach(labels);
  const datasets::TriangleBvh truth_bvh(truth.mesh);

  std::vector<PairRow> rows;
  const auto trajectory = besideTruth(options, options.trajectory, "trajectory.txt");
  if (options.pairs > 0 && !trajectory) {
    throw UsageError("pairs: random pairs need the keyframe poses: give --trajectory FILE (or --pairs 0)");
  }
  if (options.pairs > 0) rows = randomPairs(labels, truth_bvh, *trajectory, options);
  if (const auto hazards = besideTruth(options, options.hazards, "hazards.csv")) {
    for (const PairRow& row : readHazardPairs(*hazards)) rows.push_back(row);
  }
  if (rows.empty()) throw UsageError("pairs: no pairs: no random pairs drawn and no hazards file");

  std::size_t reachable = 0;
  writeFileAtomically(options.output, pairsCsv(rows, truth, truth_bvh, reach, up, profile, reachable));
  if (!options.quiet) {
    std::printf("%zu pairs for %s, %zu reachable on the truth (%zu traversable components); wrote %s\n", rows.size(),
                profile.name.c_str(), reachable, reach.componentCount(), options.output.c_str());
  }
  return kExitOk;
}

}  // namespace terramesh::cli

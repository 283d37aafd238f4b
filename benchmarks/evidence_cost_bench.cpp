// The price of trajectory evidence per keyframe: a stream meshed with its traversability layers
// kept current after every event, as `terramesh mesh STREAM --robot R` does, once without and once
// with the evidence (TrajectoryEvidence::integrate, the sensor height decided from the data as the
// CLI decides it), alternating within this one run. Times are thread CPU seconds, so that other
// processes on the machine do not enter them. Prints, per round and over all rounds, the mean and
// median per keyframe of the mesher's updates, of the layer update and of both, and the ratio with
// over without; where the mesher's time goes (its steps and work per keyframe); then the machine.
//
//   terramesh_evidence_bench [STREAM] [--robot R.yaml] [--rounds N] [--street-length-m L]
//                            [--station-spacing-m S]
//
// Without STREAM: the KITTI-like street of terramesh_traversability_bench (--street-length-m,
// 200 m). --robot defaults to the shipped small_wheeled profile; --rounds (2) pairs of runs;
// --station-spacing-m as `terramesh mesh` takes it.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "bench_streams.h"
#include "common/machine_info.h"
#include "mesher/mesher.h"
#include "traversability/robot_profile_yaml.h"
#include "traversability/trajectory_evidence.h"
#include "traversability/traversability_map.h"

namespace {

using namespace terramesh;

struct Options {
  std::string stream;
  std::string robot = std::string(TERRAMESH_SOURCE_DIR) + "/traversability/robots/small_wheeled.yaml";
  int rounds = 2;
  double street_length_m = 200.0;
  double station_spacing_m = traversability::TrajectoryEvidenceConfig{}.station_spacing_m;
  int body_view_ends = 2;
  bool body_boxes = true;
};

/// What the CLI decides for the evidence: the sensor height from the profile, else from the data.
struct Setup {
  traversability::RobotProfile profile;
  traversability::MapFrame frame;
  traversability::TrajectoryEvidenceConfig evidence_config;
  traversability::TrajectoryEvidenceDecision decision;
  Eigen::Vector3d forward_S = Eigen::Vector3d::UnitZ();
};

Setup decide(const bench::BenchStream& s, const traversability::RobotProfile& profile, const Options& options) {
  Setup setup;
  setup.profile = profile;
  setup.evidence_config.station_spacing_m = options.station_spacing_m;
  setup.evidence_config.body_views_from_both_ends = options.body_view_ends == 2;
  setup.evidence_config.body_boxes = options.body_boxes;
  setup.evidence_config.validate();
  setup.frame.up_W = s.up_W;
  setup.frame.metres_per_unit = s.stream.metres_per_unit;
  const traversability::SensorHeightEstimate estimate =
      traversability::estimateSensorHeight(datasets::latestKeyframeCentres(s.stream), datasets::latestPointEstimates(s.stream),
                                           s.up_W, s.stream.metres_per_unit, setup.evidence_config);
  setup.decision =
      traversability::decideTrajectoryEvidence(estimate, profile.mountedSensorHeightM(), {}, setup.evidence_config);
  setup.forward_S = traversability::sensorForwardAxis(s.stream.sensor_up_S);
  return setup;
}

/// Thread CPU seconds per keyframe (events between keyframes count with the keyframe before them).
struct Times {
  std::vector<double> mesher_s, layers_s;
  std::size_t faces = 0;
  mesher::UpdateStats work;  ///< the mesher's updates summed (steps in wall time, counts)
};

Times run(const bench::BenchStream& s, const Setup& setup, bool with_evidence) {
  mesher::MesherConfig config = mesher::MesherConfig::forMode(mesher::MesherMode::kProposed);
  config.metres_per_unit = s.stream.metres_per_unit;
  datasets::applyMeshingAdvice(s.stream, config);
  std::optional<traversability::TrajectoryEvidence> evidence;
  if (with_evidence) {
    evidence.emplace(setup.profile, s.up_W, s.stream.metres_per_unit, setup.decision.sensor_height_m, setup.forward_S,
                     setup.evidence_config);
    evidence->configureMesher(config);
  }
  mesher::Mesher mesher(config);
  traversability::TraversabilityMap map(setup.profile, setup.frame);
  if (evidence) map.setDrivePoses([&evidence](mesher::PointId id) { return evidence->baseOf(id); });
  Times times;
  std::uint64_t revision = 0;
  for (const datasets::StreamEvent& event : s.stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event);
    const double start = bench::threadCpuSeconds();
    if (evidence && keyframe) {
      times.work += evidence->integrate(mesher, *keyframe);
    } else if (evidence && removal) {
      times.work += evidence->removeKeyframe(mesher, removal->keyframe);
    } else {
      times.work += datasets::applyEvent(mesher, event);
    }
    const double meshed = bench::threadCpuSeconds();
    map.update(mesher, revision);
    revision = mesher.revision();
    const double layered = bench::threadCpuSeconds();
    if (keyframe || times.mesher_s.empty()) {
      times.mesher_s.push_back(0);
      times.layers_s.push_back(0);
    }
    times.mesher_s.back() += meshed - start;
    times.layers_s.back() += layered - meshed;
  }
  times.faces = map.faceCount();
  return times;
}

double mean(const std::vector<double>& values) {
  return values.empty() ? 0.0 : std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

std::vector<double> sum(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> total(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) total[i] = a[i] + b[i];
  return total;
}

void printRow(const std::string& what, const std::vector<double>& without, const std::vector<double>& with) {
  std::printf("| %s | %.2f | %.2f | %.3f | %.2f | %.2f | %.3f |\n", what.c_str(), 1e3 * mean(without), 1e3 * mean(with),
              mean(with) / mean(without), 1e3 * bench::percentile(without, 0.5), 1e3 * bench::percentile(with, 0.5),
              bench::percentile(with, 0.5) / bench::percentile(without, 0.5));
}

void append(Times& all, const Times& one) {
  all.mesher_s.insert(all.mesher_s.end(), one.mesher_s.begin(), one.mesher_s.end());
  all.layers_s.insert(all.layers_s.end(), one.layers_s.begin(), one.layers_s.end());
  all.faces = one.faces;
  all.work += one.work;
}

/// Where the mesher's time goes: its steps (wall time) and work per keyframe, without and with.
void printWork(const Times& without, const Times& with) {
  const auto perKeyframe = [](const Times& t, double value) { return value / static_cast<double>(t.mesher_s.size()); };
  std::printf("\n| mesher per keyframe | without | with | ratio |\n|---|---|---|---|\n");
  const auto row = [&](const char* what, double scale, double a, double b) {
    std::printf("| %s | %.2f | %.2f | %.3f |\n", what, scale * perKeyframe(without, a), scale * perKeyframe(with, b),
                b / a);
  };
  const mesher::UpdateStats& a = without.work;
  const mesher::UpdateStats& b = with.work;
  row("Steiner grid ms", 1e3, a.time.steiner_s, b.time.steiner_s);
  row("shrink ms", 1e3, a.time.shrink_s, b.time.shrink_s);
  row("insertion ms", 1e3, a.time.insertion_s, b.time.insertion_s);
  row("ray tracing ms", 1e3, a.time.ray_tracing_s, b.time.ray_tracing_s);
  row("grow ms", 1e3, a.time.grow_s, b.time.grow_s);
  const auto count = [](std::size_t n) { return static_cast<double>(n); };
  row("points inserted", 1, count(a.new_points + a.moved_points), count(b.new_points + b.moved_points));
  row("rays traced", 1, count(a.rays_traced), count(b.rays_traced));
  row("rays retraced", 1, count(a.rays_retraced), count(b.rays_retraced));
  row("walk steps", 1, count(a.walk_steps), count(b.walk_steps));
  row("cells shrunk", 1, count(a.cells_shrunk), count(b.cells_shrunk));
  row("cells grown", 1, count(a.cells_grown), count(b.cells_grown));
}

void printTable(const std::string& title, const Times& without, const Times& with) {
  std::printf("\n%s (%zu and %zu keyframes; %zu and %zu faces at the end)\n\n", title.c_str(), without.mesher_s.size(),
              with.mesher_s.size(), without.faces, with.faces);
  std::printf("| per keyframe, thread CPU | mean without ms | mean with ms | ratio | median without ms | "
              "median with ms | ratio |\n|---|---|---|---|---|---|---|\n");
  printRow("mesher", without.mesher_s, with.mesher_s);
  printRow("layers", without.layers_s, with.layers_s);
  printRow("mesher + layers", sum(without.mesher_s, without.layers_s), sum(with.mesher_s, with.layers_s));
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app("The price of trajectory evidence per keyframe: mesher and layers without and with it");
  app.add_option("stream", options.stream, "stream file (default: the built-in KITTI-like street)")
      ->check(CLI::ExistingFile);
  app.add_option("--robot", options.robot, "robot profile YAML")->capture_default_str()->check(CLI::ExistingFile);
  app.add_option("--rounds", options.rounds, "pairs of runs, alternating which runs first")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("--street-length-m", options.street_length_m, "length of the built-in street")
      ->capture_default_str()
      ->check(CLI::Range(20.0, 5000.0));
  app.add_option("--station-spacing-m", options.station_spacing_m, "as `terramesh mesh --station-spacing-m`")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--body-view-ends", options.body_view_ends,
                 "body views over both ends of each stretch (2, as `terramesh mesh`) or over the previous "
                 "keyframe's base only (1)")
      ->capture_default_str()
      ->check(CLI::Range(1, 2));
  bool no_body_boxes = false;
  app.add_flag("--no-body-boxes", no_body_boxes,
               "the body views' rays only, without the body's free boxes (ablation)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  options.body_boxes = !no_body_boxes;
  try {
    const bench::BenchStream s =
        options.stream.empty() ? bench::builtinStreet(options.street_length_m) : bench::fileStream(options.stream);
    const Setup setup = decide(s, traversability::loadRobotProfile(options.robot), options);
    std::printf("stream %s, robot %s: %s\n", s.name.c_str(), setup.profile.name.c_str(),
                setup.decision.summary.c_str());
    if (!setup.decision.enabled) {
      std::fprintf(stderr, "terramesh_evidence_bench: the stream gets no trajectory evidence; nothing to compare\n");
      return 2;
    }
    Times all_without, all_with;
    for (int round = 0; round < options.rounds; ++round) {
      // Alternate which runs first, so that a drift of the machine's speed falls on both.
      const bool evidence_first = round % 2 == 1;
      const Times first = run(s, setup, evidence_first);
      const Times second = run(s, setup, !evidence_first);
      const Times& without = evidence_first ? second : first;
      const Times& with = evidence_first ? first : second;
      printTable("round " + std::to_string(round + 1), without, with);
      append(all_without, without);
      append(all_with, with);
    }
    printTable("all rounds", all_without, all_with);
    printWork(all_without, all_with);
    std::printf("\nmachine: %s\n", describeMachine().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "terramesh_evidence_bench: %s\n", e.what());
    return 2;
  }
}

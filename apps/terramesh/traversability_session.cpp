#include "traversability_session.h"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <variant>

#include "common/atomic_file.h"
#include "traversability/robot_profile_yaml.h"

namespace terramesh::cli {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

constexpr const char* kUpdatesCsv = "traversability_updates.csv";

}  // namespace

void addTraversabilityExportOptions(CLI::App& app, TraversabilityExportOptions& options) {
  app.add_option("--robot", options.robot,
                 "robot profile (traversability/robots/*.yaml); for mesh: enables the traversability map")
      ->option_text("YAML");
  app.add_option("--grid-resolution-m", options.grid_resolution_m, "cell size of the Nav2 maps and GeoTIFF layers, metres")
      ->check(positiveNumber());
  app.add_flag("--no-geotiff", options.no_geotiff, "do not write the GeoTIFF layers (layers_level_N.tif)");
  app.add_flag("--no-mesh-map-h5", options.no_mesh_map_h5,
               "do not write traversability.h5 (the HDF5 mesh map of mesh_navigation)");
}

std::optional<StreamUp> upFromKeyframes(const datasets::SlamStream& stream) {
  std::vector<Eigen::Matrix3d> rotations;
  for (const datasets::StreamEvent& event : stream.events) {
    if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
      rotations.push_back(keyframe->rotation_W_C.toRotationMatrix());
    }
  }
  if (rotations.empty()) return std::nullopt;
  return StreamUp{traversability::estimateUpFromCameras(rotations, stream.sensor_up_S),
                  "estimated from " + std::to_string(rotations.size()) + " keyframe rotations"};
}

StreamUp mapUpFor(const traversability::RobotProfile& profile, const datasets::SlamStream& stream) {
  if (profile.gravity_W) return StreamUp{-profile.gravity_W->normalized(), "the robot profile's gravity"};
  std::optional<StreamUp> up = upFromKeyframes(stream);
  if (!up) throw std::invalid_argument("mesh: --robot: the stream has no keyframes to estimate up from");
  return *up;
}

traversability::ExportConfig exportConfigFrom(const TraversabilityExportOptions& options) {
  traversability::ExportConfig config;
  config.grid_resolution_m = options.grid_resolution_m;
  if (!(config.grid_resolution_m > 0) || !std::isfinite(config.grid_resolution_m)) {
    throw UsageError("--grid-resolution-m must be > 0");
  }
  config.write_geotiff = !options.no_geotiff;
  config.write_mesh_map_h5 = !options.no_mesh_map_h5;
  config.validate();
  return config;
}

traversability::RobotProfile robotFrom(const TraversabilityExportOptions& options) {
  if (!options.robot) throw UsageError("--robot YAML is required");
  const std::filesystem::path path = *options.robot;
  traversability::RobotProfile profile = traversability::loadRobotProfile(path);
  try {
    profile.validate();
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(path.string() + ": " + error.what());
  }
  return profile;
}

Eigen::Vector3d parseUpVector(const std::string& text) {
  std::istringstream in(text);
  Eigen::Vector3d up;
  char comma1 = 0, comma2 = 0;
  if (!(in >> up.x() >> comma1 >> up.y() >> comma2 >> up.z()) || comma1 != ',' || comma2 != ',' ||
      !(in >> std::ws).eof() || !up.allFinite() || up.norm() < 1e-12) {
    throw UsageError("--up must be X,Y,Z, a finite non-zero vector (got \"" + text + "\")");
  }
  return up.normalized();
}

void TraversabilitySession::addOptions(CLI::App& app, TraversabilitySessionOptions& options) {
  addTraversabilityExportOptions(app, options.exports);
  app.add_option("--export-every", options.export_every,
                 "with --robot: rewrite the map exports every K keyframes (0: only at the end)")
      ->option_text("K")
      ->check(nonNegativeNumber());
}

std::optional<TraversabilitySession> TraversabilitySession::fromOptions(const TraversabilitySessionOptions& options,
                                                                        const datasets::SlamStream& stream,
                                                                        double metres_per_unit,
                                                                        std::filesystem::path output) {
  if (!options.exports.robot) {
    if (options.export_every != 0) throw UsageError("mesh: --export-every needs --robot");
    return std::nullopt;
  }
  const std::size_t export_every = options.export_every;
  const traversability::ExportConfig config = exportConfigFrom(options.exports);
  const traversability::RobotProfile profile = robotFrom(options.exports);
  traversability::MapFrame frame;
  frame.metres_per_unit = metres_per_unit;
  const StreamUp up = mapUpFor(profile, stream);
  frame.up_W = up.up_W;
  frame.validate();
  return TraversabilitySession(profile, frame, config, std::move(output), export_every, up.source);
}

TraversabilitySession::TraversabilitySession(traversability::RobotProfile profile, traversability::MapFrame frame,
                                             traversability::ExportConfig config, std::filesystem::path output,
                                             std::size_t export_every, std::string up_source)
    : profile_(std::move(profile)),
      config_(config),
      output_(std::move(output)),
      export_every_(export_every),
      up_source_(std::move(up_source)),
      map_(std::make_unique<traversability::TraversabilityMap>(profile_, frame)) {
  csv_ << "event,keyframes,revision,faces_added,faces_removed,faces_recomputed,faces_total,full_rebuild,"
          "unconfirmed_points,layer_update_s,export_s\n";
}

void TraversabilitySession::update(const mesher::Mesher& mesher, const std::string& event) {
  // update() also refreshes the observation counts of faces that were not replaced (`rays`).
  const traversability::LayerUpdateStats stats = map_->update(mesher, revision_);
  if (stats.full_rebuild) ++full_rebuilds_;
  revision_ = mesher.revision();
  update_seconds_ += stats.seconds;
  unconfirmed_points_ = stats.unconfirmed_points;
  csv_ << event << ',' << keyframes_ << ',' << revision_ << ',' << stats.faces_added << ','
       << stats.faces_removed << ',' << stats.faces_recomputed << ',' << stats.faces_total << ','
       << (stats.full_rebuild ? 1 : 0) << ',' << stats.unconfirmed_points << ',' << stats.seconds << ',';
}

traversability::ExportReport TraversabilitySession::exportNow() {
  const auto start = Clock::now();
  traversability::LayeredMesh snapshot = map_->snapshot();
  const traversability::ExportReport report = traversability::writeMapDirectory(output_, snapshot, profile_, config_);
  ++exports_;
  exported_revision_ = revision_;
  last_report_ = report;
  if (export_hook_) export_hook_(snapshot, revision_);
  export_seconds_ += secondsSince(start);
  return report;
}

void TraversabilitySession::afterEvent(const mesher::Mesher& mesher, std::size_t event_index, bool is_keyframe) {
  if (is_keyframe) ++keyframes_;
  update(mesher, std::to_string(event_index));
  double export_s = 0;
  if (is_keyframe && export_every_ > 0 && keyframes_ % export_every_ == 0) {
    const auto start = Clock::now();
    exportNow();
    export_s = secondsSince(start);
    writeFileAtomically(output_ / kUpdatesCsv, csv_.str() + std::to_string(export_s) + "\n");
  }
  csv_ << export_s << '\n';
}

void TraversabilitySession::resume(const mesher::Mesher& mesher, std::size_t keyframes) {
  keyframes_ = keyframes;
  unconfirmed_points_ = map_->setUnconfirmedPoints(mesher.unconfirmedPoints()).unconfirmed_points;
  const traversability::LayerUpdateStats stats = map_->reset(mesher.surfaceFaces());
  ++full_rebuilds_;
  revision_ = mesher.revision();
  update_seconds_ += stats.seconds;
}

void TraversabilitySession::finish(const mesher::Mesher& mesher, std::ostream& summary) {
  const auto start = Clock::now();
  if (mesher.revision() != revision_) update(mesher, "end");
  else csv_ << "end," << keyframes_ << ',' << revision_ << ",0,0,0," << map_->faceCount() << ",0," << unconfirmed_points_ << ",0,";
  // The last keyframe may have exported this very revision already.
  const bool current = exports_ > 0 && exported_revision_ == revision_;
  const traversability::ExportReport report = current ? last_report_ : exportNow();
  csv_ << (current ? 0.0 : secondsSince(start)) << '\n';
  writeFileAtomically(output_ / kUpdatesCsv, csv_.str());
  summary << "traversability: robot " << profile_.name << ", up " << map_->frame().up_W.transpose() << " ("
          << up_source_ << "), " << map_->faceCount() << " faces, " << report.levels << " level(s); "
          << exports_ << " export(s), layer updates " << update_seconds_ << " s in total (" << full_rebuilds_
          << " full rebuild(s): the map changed by half or more, or its history was gone), exports "
          << export_seconds_ << " s; " << unconfirmed_points_
          << " SLAM point(s) seen by too few keyframes to mesh, judged as possible obstacles\n";
  for (std::size_t l = 0; l < report.levels; ++l) {
    summary << "  level " << l << ": mean height " << report.level_heights_m[l] << " m -> level_" << l
            << ".yaml\n";
  }
  summary << "  traversability map: " << (output_ / "traversability.ply").string()
          << " (details in traversability_summary.txt, per-update times in " << kUpdatesCsv << ")\n";
}

}  // namespace terramesh::cli

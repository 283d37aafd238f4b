// terramesh mesh INPUT -o OUTDIR: runs the incremental mesher over a SLAM stream.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "common/input_error.h"
#include "datasets/stream_reader.h"
#include "mesher/mesh_io.h"
#include "mesher/mesher.h"
#include "input_options.h"
#include "mesh_checkpoint.h"
#include "mesh_frame_hints.h"
#include "mesh_freeze.h"
#include "mesh_tile.h"
#include "mesher_options.h"
#include "process_memory.h"
#include "progress_bar.h"
#include "stop_signal.h"
#include "stats_table.h"
#include "run_extras.h"
#include "trajectory_evidence_run.h"
#include "traversability_session.h"

namespace terramesh::cli {
namespace {

std::string eventKind(const datasets::StreamEvent& event, std::uint64_t& id) {
  if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
    id = keyframe->id.value;
    return "keyframe";
  }
  if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
    id = removal->keyframe.value;
    return "remove_keyframe";
  }
  id = std::get<datasets::PointRemoval>(event).points.size();
  return "remove_points";
}

void writeMesh(const std::filesystem::path& path, const mesher::TriangleMesh& mesh,
               const std::vector<std::string>& comments) {
  if (path.extension() == ".obj") {
    mesher::writeObj(path, mesh);
  } else {
    mesher::writePly(path, mesh, comments);
  }
}

/// What the run knows of the mesh's frame, for its header (mesh_frame_hints.h).
/// The scale only when known (from the data or --metres-per-unit): an SfM model's unit is not a metre.
std::vector<std::string> frameComments(const datasets::SlamStream& stream, std::optional<double> metres_per_unit,
                                       const std::optional<TraversabilitySession>& traversability,
                                       const TrajectoryEvidenceRun& evidence) {
  MeshFrameHints hints;
  hints.metres_per_unit = metres_per_unit;
  if (traversability) {
    hints.up_W = traversability->frame().up_W;
    hints.up_source = traversability->upSource();
  } else if (const std::optional<StreamUp> up = upFromKeyframes(stream)) {
    hints.up_W = up->up_W;
    hints.up_source = up->source;
  }
  if (evidence.enabled()) {
    hints.sensor_height_m = evidence.sensorHeightM();
    hints.sensor_height_source = evidence.sensorHeightSource();
  }
  return meshFrameComments(hints);
}

std::string describeTopology(const mesher::MeshTopology& t) {
  std::ostringstream out;
  out << t.vertices << " vertices, " << t.faces << " faces, " << t.components << " component(s), "
      << "genus " << t.total_genus << (t.isClosedManifold() ? ", closed 2-manifold" : "");
  return out.str();
}

constexpr const char* kExitCodesHelp =
    "\nExit codes: 0 done; 1 failed (e.g. cannot write the output); 2 bad input, options or checkpoint;\n"
    "130 / 143 stopped by SIGINT / SIGTERM: the update in progress was finished and the mesh, layers,\n"
    "CSV and summary written for the events applied so far (and a checkpoint, with --checkpoint-every).\n";

/// The options of `terramesh mesh`.
struct MeshOptions {
  std::string input_path, output_dir, mode_name = "proposed", format = "ply";
  long snapshot_every = 0, checkpoint_every = 0;
  std::optional<std::string> resume_path;
  std::optional<std::string> tile;  ///< PLAN:I
  bool drop_steiner = false, check = false, quiet = false, memory_log = false;
  InputOptions input;
  MesherOptions mesher;
  TraversabilitySessionOptions traversability;
  TrajectoryEvidenceOptions evidence;
  FreezeOptions freeze;
};

void declareOptions(CLI::App& app, MeshOptions& o) {
  app.option_defaults()->always_capture_default();
  app.footer(kExitCodesHelp);
  app.add_option("INPUT", o.input_path,
                 "SLAM stream: the authors' JSON (.json), terramesh's (.tmstream), OpenMVG sfm_data.json, Bundler "
                 ".out, a ROS 1 bag (.bag), or a COLMAP or KITTI directory")
      ->required();
  app.add_option("-o,--output", o.output_dir, "output directory (created if missing)")->option_text("DIR");
  app.add_option("--mode", o.mode_name, "proposed, litvinov13 or romanoni15");
  app.add_option("--format", o.format, "mesh format: ply or obj");
  app.add_option("--snapshot-every", o.snapshot_every, "also write the mesh every K keyframes (0: never)")
      ->check(nonNegativeNumber());
  app.add_option("--checkpoint-every", o.checkpoint_every,
                 "save the whole mapper state to OUTDIR/checkpoint.tmckpt every K keyframes and when stopped by a "
                 "signal (written atomically; 0: never)")
      ->check(nonNegativeNumber());
  app.add_option("--resume", o.resume_path,
                 "continue an interrupted run from its checkpoint: give the same INPUT and input options; the "
                 "mesher options come from the checkpoint")
      ->option_text("CHECKPOINT");
  app.add_option("--tile", o.tile,
                 "mesh tile I of a plan written by terramesh tiles plan, from INPUT (the planned stream); writes "
                 "into the tile's folder beside the plan (no -o); needs --robot (docs/tiles.md)")
      ->option_text("PLAN:I");
  app.add_flag("--drop-steiner", o.drop_steiner,
               "also write mesh_open.ply: the surface without faces touching Steiner vertices");
  app.add_flag("--memory-log", o.memory_log,
               "also write memory.csv: the process's resident memory after every keyframe (not reproducible "
               "byte for byte: it is the machine's)");
  app.add_flag("--check-invariants", o.check, "check every invariant after each update (slow; for testing)");
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
  addInputOptions(app, o.input);
  addMesherOptions(app, o.mesher);
  TraversabilitySession::addOptions(app, o.traversability);
  addTrajectoryEvidenceOptions(app, o.evidence);
  addFreezeOptions(app, o.freeze);
}

/// One run of `terramesh mesh`: everything read and validated by the constructor before any
/// output exists, then the events (run), then the outputs and the summary (finish).
class MeshJob {
 public:
  MeshJob(const MeshOptions& o, mesher::MesherMode mode, std::optional<MeshTile> tile);
  /// Applies the events from the first one not yet applied; stops early on SIGINT/SIGTERM (within a
  /// StopSignalScope).
  void run();
  /// Writes the mesh, the CSV, the extras and the summary; returns the exit code.
  int finish();

 private:
  void afterEvent(std::size_t i, const datasets::StreamEvent& event, const mesher::UpdateStats& stats);
  /// The freeze after event `i`: tiles written, keyframes retired from the mesher, layers updated.
  void freezeAfter(std::size_t i, const datasets::StreamEvent& event);
  void saveCheckpoint(std::size_t next_event);
  /// --resume of a run with the freeze: the freeze's decisions and the evidence up to event
  /// `next_event`, replayed from the stream without the mesher (the checkpoint's), then the records
  /// of the tiles written before it.
  void replayFreeze(std::size_t next_event);
  void writeSummary(const mesher::TriangleMesh& mesh, const std::filesystem::path& mesh_path);
  /// The events meshed: the stream's, or the tile's input.
  const std::vector<datasets::StreamEvent>& events() const { return tile_ ? tile_->input().events : stream_.events; }

  const MeshOptions& o_;
  const std::filesystem::path input_, output_;
  const datasets::SlamStream stream_;
  std::optional<MeshTile> tile_;
  std::optional<ResumedMeshRun> resumed_;
  mesher::MesherConfig config_;
  std::optional<TraversabilitySession> traversability_;
  TrajectoryEvidenceRun evidence_;
  std::optional<MeshFreeze> freeze_;
  MeshRunState state_;
  std::optional<mesher::Mesher> mesher_;
  std::vector<std::string> frame_comments_;
  /// What the configuration took from the data (describeInferredSettings), for stderr and the summary.
  std::vector<std::string> inferred_;
  std::ostringstream csv_;
  std::ostringstream memory_csv_;  ///< with --memory-log
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  mesher::UpdateStats totals_;
  std::size_t keyframes_ = 0;
  std::size_t first_event_ = 0;
  std::size_t end_event_ = 0;
  int stop_signal_ = 0;
};

MeshJob::MeshJob(const MeshOptions& o, mesher::MesherMode mode, std::optional<MeshTile> tile)
    : o_(o),
      input_(o.input_path),
      output_(o.output_dir),
      stream_(datasets::readAnyStream(input_, streamReadOptionsFrom(o.input))),
      tile_(std::move(tile)) {
  if (!o.quiet) printReaderNotes(std::cerr, stream_);
  // A tile meshes its own events in the frame of the whole stream (config, up and evidence from all).
  if (tile_) tile_->selectInput(stream_, input_);
  if (o.resume_path) resumed_ = readMeshCheckpoint(*o.resume_path, stream_);
  config_ = resumed_ ? resumed_->mesher.config() : mesherConfigFrom(o.mesher, mode, stream_);
  // The tiles of a plan share one lattice where they overlap, so that they mesh it alike.
  if (tile_) config_.steiner_global_phase = true;
  if (!resumed_) inferred_ = describeInferredSettings(o.mesher, stream_, config_);
  traversability_ = TraversabilitySession::fromOptions(o.traversability, stream_, config_.metres_per_unit, output_);
  if (tile_) tile_->attach(*traversability_, exportConfigFrom(o.traversability.exports), config_.metres_per_unit);
  evidence_ = TrajectoryEvidenceRun::fromOptions(o.evidence, stream_, traversability_ ? &*traversability_ : nullptr,
                                                 config_.min_views);
  freeze_ = MeshFreeze::fromOptions(o.freeze, traversability_ ? &*traversability_ : nullptr,
                                    config_.max_camera_distance_m, output_);
  const std::string freeze_settings = freeze_ ? freeze_->settings() : "off";
  if (resumed_ && resumed_->state.freeze_settings != freeze_settings) {
    throw InputError(*o.resume_path, "run state.freeze_settings",
                     "made with the freeze \"" + resumed_->state.freeze_settings + "\", this run has \"" +
                         freeze_settings + "\"; resume with the freeze options of the interrupted run");
  }
  if (resumed_ && resumed_->state.trajectory_evidence != evidence_.settings()) {
    throw InputError(*o.resume_path, "run state.trajectory_evidence",
                     "made with trajectory evidence \"" + resumed_->state.trajectory_evidence + "\", this run has \"" +
                         evidence_.settings() + "\"; resume with the robot and evidence options of the interrupted run");
  }
  // No ray from above frees anything under the driven ground (a resumed mesher keeps its own setting).
  if (!resumed_) evidence_.configureMesher(config_);
  std::filesystem::create_directories(output_);
  if (o.snapshot_every > 0) std::filesystem::create_directories(output_ / "snapshots");

  if (resumed_) state_ = resumed_->state;
  state_.events = events().size();
  if (o.checkpoint_every > 0 && !resumed_) state_.stream_fingerprint = streamFingerprint(stream_);
  state_.trajectory_evidence = evidence_.settings();
  state_.freeze_settings = freeze_settings;
  mesher_.emplace(resumed_ ? std::move(resumed_->mesher) : mesher::Mesher(config_));
  if (traversability_ && evidence_.enabled()) {
    traversability_->setDrivePoses(evidence_.drivePoses(), evidence_.sensorHeightM());
  }
  // The poses first: the layers read where the robot faced on its driven samples.
  if (resumed_ && freeze_) {
    replayFreeze(state_.next_event);
  } else if (resumed_) {
    evidence_.replay(stream_, state_.next_event);
  }
  if (traversability_ && resumed_) traversability_->resume(*mesher_, state_.keyframes);
  // Said once the options proved valid: a refused run prints its one error line only.
  if (!o.quiet) {
    for (const std::string& line : inferred_) std::cerr << "terramesh: inferred: " << line << '\n';
  }
  if (!o.quiet && !evidence_.summary().empty()) std::cerr << "terramesh: " << evidence_.summary() << '\n';
  if (!o.quiet && evidence_.warning()) std::cerr << "terramesh: warning: " << *evidence_.warning() << '\n';
  const bool scale_known = stream_.scale_known || o.mesher.metres_per_unit.has_value();
  frame_comments_ = frameComments(stream_, scale_known ? std::optional<double>(config_.metres_per_unit) : std::nullopt,
                                  traversability_, evidence_);
  csv_ << (resumed_ ? state_.csv : updateCsvHeader() + "\n");
  totals_ = state_.totals;
  keyframes_ = state_.keyframes;
  first_event_ = state_.next_event;
  end_event_ = events().size();
}

void MeshJob::saveCheckpoint(std::size_t next_event) {
  state_.next_event = next_event;
  state_.keyframes = keyframes_;
  state_.totals = totals_;
  state_.csv = csv_.str();
  if (freeze_) state_.freeze_state = freeze_->state();
  writeMeshCheckpoint(output_ / kCheckpointFileName, *mesher_, state_);
}

void MeshJob::replayFreeze(std::size_t next_event) {
  for (std::size_t i = 0; i < next_event; ++i) {
    const datasets::StreamEvent& event = events()[i];
    if (freeze_->skips(event, i)) continue;
    evidence_.replayEvent(event);
    if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) freeze_->removed(removal->keyframe);
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (keyframe == nullptr) continue;
    const MeshFreeze::Step step = freeze_->afterKeyframe(*keyframe, i, nullptr, 0);
    for (std::size_t e : step.returned_events) evidence_.replayEvent(events()[e]);
    if (step.retire.empty()) continue;
    evidence_.replayRetire(step.retire);
    evidence_.forgetPointsBeyond(freeze_->liveCentres(), 2 * config_.max_camera_distance_m);
  }
  freeze_->restore(state_.freeze_state, o_.resume_path.value_or(""));
}

void MeshJob::run() {
  ProgressBar progress("meshing", events().size());
  for (std::size_t i = first_event_; i < events().size(); ++i) {
    const datasets::StreamEvent& event = events()[i];
    if (freeze_ && freeze_->skips(event, i)) {
      progress.update(i + 1);
      continue;
    }
    afterEvent(i, event, evidence_.apply(*mesher_, event));
    if (freeze_) freezeAfter(i, event);
    stop_signal_ = StopSignalScope::requested();
    const bool checkpoint_due = o_.checkpoint_every > 0 && std::holds_alternative<mesher::Keyframe>(event) &&
                                keyframes_ % static_cast<std::size_t>(o_.checkpoint_every) == 0;
    if (checkpoint_due || (stop_signal_ != 0 && o_.checkpoint_every > 0)) saveCheckpoint(i + 1);
    progress.update(i + 1);
    if (stop_signal_ != 0) {
      end_event_ = i + 1;
      break;
    }
  }
}

void MeshJob::afterEvent(std::size_t i, const datasets::StreamEvent& event, const mesher::UpdateStats& stats) {
  totals_ += stats;
  std::uint64_t id = 0;
  const std::string kind = eventKind(event, id);
  csv_ << updateCsvRow(i, kind, id, stats, mesher_->size()) << '\n';
  if (o_.check) {
    const mesher::InvariantReport report = mesher_->checkInvariants();
    if (!report.ok()) {
      throw std::runtime_error("invariant check failed after event " + std::to_string(i) + ": " + report.summary());
    }
  }
  if (traversability_) traversability_->afterEvent(*mesher_, i, kind == "keyframe");
  if (kind != "keyframe") return;
  ++keyframes_;
  if (o_.memory_log) {
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    memory_csv_ << keyframes_ << ',' << i << ',' << elapsed_s << ',' << residentMib() << ',' << peakResidentMib() << ','
                << mesher_->size().totalBytes() << '\n';
  }
  if (o_.snapshot_every > 0 && keyframes_ % static_cast<std::size_t>(o_.snapshot_every) == 0) {
    char name[64];
    std::snprintf(name, sizeof(name), "mesh_%06zu.%s", keyframes_, o_.format.c_str());
    writeMesh(output_ / "snapshots" / name, mesher_->extractMesh(), frame_comments_);
  }
}

void MeshJob::freezeAfter(std::size_t i, const datasets::StreamEvent& event) {
  if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
    freeze_->removed(removal->keyframe);
  }
  const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
  if (keyframe == nullptr) return;
  const MeshFreeze::Step step = freeze_->afterKeyframe(*keyframe, i, &*traversability_, mesher_->revision());
  // Retired keyframes that saw a tile reached again come back, each at its latest version.
  for (std::size_t e : step.returned_events) {
    const mesher::UpdateStats stats = evidence_.apply(*mesher_, events()[e]);
    totals_ += stats;
    csv_ << updateCsvRow(i, "return_keyframe", std::get<mesher::Keyframe>(events()[e]).id.value, stats,
                         mesher_->size())
         << '\n';
  }
  if (!step.retire.empty()) {
    const mesher::UpdateStats retired = evidence_.retire(*mesher_, step.retire);
    totals_ += retired;
    csv_ << updateCsvRow(i, "retire_keyframes", step.retire.size(), retired, mesher_->size()) << '\n';
    // The lattice and the evidence's points left behind go too: memory follows the active region.
    const std::vector<Eigen::Vector3d> live = freeze_->liveCentres();
    const mesher::UpdateStats released = mesher_->releaseFarSteiner(live, config_.max_camera_distance_m);
    evidence_.forgetPointsBeyond(live, 2 * config_.max_camera_distance_m);
    totals_ += released;
    csv_ << updateCsvRow(i, "release_steiner", released.steiner_released, released, mesher_->size()) << '\n';
  }
  if (step.retire.empty() && step.returned_events.empty()) return;
  if (o_.check) {
    const mesher::InvariantReport report = mesher_->checkInvariants();
    if (!report.ok()) {
      throw std::runtime_error("invariant check failed after the freeze at event " + std::to_string(i) + ": " +
                               report.summary());
    }
  }
  traversability_->afterEvent(*mesher_, i, false);
}

int MeshJob::finish() {
  const mesher::TriangleMesh mesh = mesher_->extractMesh();
  const std::filesystem::path mesh_path = output_ / ("mesh." + o_.format);
  writeMesh(mesh_path, mesh, frame_comments_);
  writeFileAtomically(output_ / "keyframes.csv", csv_.str());
  if (o_.memory_log) {
    writeFileAtomically(output_ / "memory.csv", "keyframes,event,elapsed_s,rss_mib,peak_rss_mib,map_bytes\n" +
                                                    memory_csv_.str());
  }
  writeRunExtras(tile_ ? tile_->input() : stream_, output_);
  writeSummary(mesh, mesh_path);
  return stop_signal_ != 0 ? exitCodeForSignal(stop_signal_) : kExitOk;
}

void MeshJob::writeSummary(const mesher::TriangleMesh& mesh, const std::filesystem::path& mesh_path) {
  std::ostringstream summary;
  summary << "input: " << input_.string() << "\nmode: " << mesher::toString(config_.mode())
          << "\nmetres_per_unit: " << config_.metres_per_unit << "\nkeyframes: " << keyframes_
          << "\nevents: " << events().size() << "\nmesh: " << mesh_path.string() << " ("
          << describeTopology(mesher::analyzeTopology(mesh)) << ")\n";
  for (const std::string& line : inferred_) summary << "inferred: " << line << '\n';
  for (const std::string& note : stream_.reader_notes) summary << "input: " << note << '\n';
  for (const std::string& warning : stream_.reader_warnings) summary << "warning: " << warning << '\n';
  if (tile_) summary << tile_->describe() << '\n';
  if (resumed_) summary << "resumed: from " << *o_.resume_path << " at event " << first_event_ << '\n';
  if (stop_signal_ != 0) {
    summary << "stopped: by signal " << stop_signal_ << " after event " << end_event_ - 1 << " (" << keyframes_
            << " keyframes); exit code " << exitCodeForSignal(stop_signal_) << '\n';
  }
  printStepTotals(summary, totals_, keyframes_);
  if (autoMaxDistance(o_.mesher, stream_)) {
    summary << "max_camera_distance_m: auto, " << kAutoMaxDistanceFactor << " x the "
            << 100 * kAutoMaxDistanceQuantile << "th percentile of the camera-to-point distances\n";
  }
  printInputFilters(summary, totals_, mesher_->size(), config_);
  for (const std::string& warning : inputFilterWarnings(totals_, mesher_->size(), config_)) {
    if (!o_.quiet) std::cerr << "terramesh: warning: " << warning << '\n';
  }
  if (o_.drop_steiner) {
    const mesher::TriangleMesh open = mesher::dropSteinerFaces(mesh);
    const std::filesystem::path open_path = output_ / ("mesh_open." + o_.format);
    writeMesh(open_path, open, frame_comments_);
    const mesher::MeshTopology open_topology = mesher::analyzeTopology(open);
    summary << "open surface: " << open_path.string() << " (" << open_topology.vertices << " vertices, "
            << open_topology.faces << " faces, " << open_topology.boundary_edges << " boundary edges, "
            << open_topology.non_manifold_vertices << " non-manifold vertices)\n";
  }
  if (!evidence_.summary().empty()) summary << evidence_.summary() << '\n';
  if (evidence_.enabled()) {
    summary << "trajectory evidence: " << evidence_.contradictedPoints()
            << " SLAM point(s) inside the robot's body where it drove, dropped as outliers; "
            << evidence_.absorbedPoints()
            << " on the ground it drove (near the contact plane, under the footprint), stood for by the "
               "driven samples; "
            << evidence_.overriddenKeyframes()
            << " keyframe(s) whose drive an obstacle seen later overrode (a point " << evidence_.laterObstacleMinViews()
            << " keyframe(s) saw; their driven evidence withdrawn); "
            << evidence_.undersidedKeyframes()
            << " keyframe(s) with a level beneath their drive (its ground given undersides); "
            << evidence_.turnKeyframes() << " keyframe(s) driven to through a turn (stations along the curve)\n";
  }
  if (evidence_.warning()) summary << "warning: " << *evidence_.warning() << '\n';
  if (traversability_) traversability_->finish(*mesher_, summary);
  if (freeze_) freeze_->finish(*traversability_, stream_, mesher_->revision(), summary);  // never with --tile
  writeFileAtomically(output_ / "summary.txt", summary.str());
  if (!o_.quiet) std::cout << summary.str();
}

}  // namespace

int runMesh(const std::vector<std::string>& args) {
  CLI::App app{"incremental manifold mesh from a SLAM stream", "terramesh mesh"};
  MeshOptions o;
  declareOptions(app, o);
  if (!parseCommandLine(app, args)) return kExitOk;
  if (o.format != "ply" && o.format != "obj") throw UsageError("mesh: --format must be ply or obj");
  const auto mode = mesher::parseMesherMode(o.mode_name);
  if (!mode) throw UsageError("mesh: --mode must be proposed, litvinov13 or romanoni15");
  std::optional<MeshTile> tile;
  if (o.tile) {
    if (!o.output_dir.empty()) throw UsageError("mesh: --tile writes into the tile's folder beside the plan; drop -o");
    if (o.resume_path) throw UsageError("mesh: --tile and --resume cannot be combined");
    if (!o.traversability.exports.robot) throw UsageError("mesh: --tile needs --robot YAML (a tile's map is its layers)");
    tile = MeshTile::fromOption(*o.tile);
    o.output_dir = tile->outputDirectory().string();
  }
  if (o.output_dir.empty()) throw UsageError("mesh: -o/--output DIR is required");
  if (o.freeze.radius_m && o.tile) throw UsageError("mesh: --freeze-radius-m cannot be combined with --tile");
  // Read and validate everything before creating any output.
  MeshJob job(o, *mode, std::move(tile));
  // From the first event to the last output, a signal finishes the work in progress.
  const StopSignalScope stop_scope;
  job.run();
  return job.finish();
}

}  // namespace terramesh::cli

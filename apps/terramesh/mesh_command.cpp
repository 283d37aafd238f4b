// terramesh mesh INPUT -o OUTDIR: runs the incremental mesher over a SLAM stream.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

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
#include "mesher_options.h"
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

}  // namespace

int runMesh(const std::vector<std::string>& args) {
  CLI::App app{"incremental manifold mesh from a SLAM stream", "terramesh mesh"};
  app.option_defaults()->always_capture_default();
  app.footer(kExitCodesHelp);
  std::string input_path, output_dir, mode_name = "proposed", format = "ply";
  long snapshot_every = 0, checkpoint_every = 0;
  std::optional<std::string> resume_path;
  bool drop_steiner = false, check = false, quiet = false;
  InputOptions input_options;
  MesherOptions mesher_options;
  TraversabilitySessionOptions traversability_options;
  TrajectoryEvidenceOptions evidence_options;
  app.add_option("INPUT", input_path,
                 "SLAM stream: the authors' JSON (.json), terramesh's (.tmstream), OpenMVG sfm_data.json, Bundler "
                 ".out, a ROS 1 bag (.bag), or a COLMAP or KITTI directory")
      ->required();
  app.add_option("-o,--output", output_dir, "output directory (created if missing)")->option_text("DIR");
  app.add_option("--mode", mode_name, "proposed, litvinov13 or romanoni15");
  app.add_option("--format", format, "mesh format: ply or obj");
  app.add_option("--snapshot-every", snapshot_every, "also write the mesh every K keyframes (0: never)")
      ->check(nonNegativeNumber());
  app.add_option("--checkpoint-every", checkpoint_every,
                 "save the whole mapper state to OUTDIR/checkpoint.tmckpt every K keyframes and when stopped by a "
                 "signal (written atomically; 0: never)")
      ->check(nonNegativeNumber());
  app.add_option("--resume", resume_path,
                 "continue an interrupted run from its checkpoint: give the same INPUT and input options; the "
                 "mesher options come from the checkpoint")
      ->option_text("CHECKPOINT");
  app.add_flag("--drop-steiner", drop_steiner,
               "also write mesh_open.ply: the surface without faces touching Steiner vertices");
  app.add_flag("--check-invariants", check, "check every invariant after each update (slow; for testing)");
  app.add_flag("--quiet", quiet, "print nothing but errors");
  addInputOptions(app, input_options);
  addMesherOptions(app, mesher_options);
  TraversabilitySession::addOptions(app, traversability_options);
  addTrajectoryEvidenceOptions(app, evidence_options);
  if (!parseCommandLine(app, args)) return kExitOk;
  if (output_dir.empty()) throw UsageError("mesh: -o/--output DIR is required");
  if (format != "ply" && format != "obj") throw UsageError("mesh: --format must be ply or obj");
  const auto mode = mesher::parseMesherMode(mode_name);
  if (!mode) throw UsageError("mesh: --mode must be proposed, litvinov13 or romanoni15");
  const datasets::StreamReadOptions read_options = streamReadOptionsFrom(input_options);

  // Read and validate everything before creating any output.
  const std::filesystem::path input = input_path;
  const datasets::SlamStream stream = datasets::readAnyStream(input, read_options);
  if (!quiet) printReaderNotes(std::cerr, stream);
  std::optional<ResumedMeshRun> resumed;
  if (resume_path) resumed = readMeshCheckpoint(*resume_path, stream);
  mesher::MesherConfig config = resumed ? resumed->mesher.config() : mesherConfigFrom(mesher_options, *mode, stream);
  const std::filesystem::path output = output_dir;
  std::optional<TraversabilitySession> traversability =
      TraversabilitySession::fromOptions(traversability_options, stream, config.metres_per_unit, output);
  TrajectoryEvidenceRun evidence =
      TrajectoryEvidenceRun::fromOptions(evidence_options, stream, traversability ? &*traversability : nullptr);
  if (resumed && resumed->state.trajectory_evidence != evidence.settings()) {
    throw InputError(*resume_path, "run state.trajectory_evidence",
                     "made with trajectory evidence \"" + resumed->state.trajectory_evidence + "\", this run has \"" +
                         evidence.settings() + "\"; resume with the robot and evidence options of the interrupted run");
  }
  // Nothing under the driven ground is free space (a resumed mesher keeps its own setting).
  if (evidence.enabled() && !resumed) config.driven_ground_up_W = traversability->frame().up_W;
  std::filesystem::create_directories(output);
  if (snapshot_every > 0) std::filesystem::create_directories(output / "snapshots");

  MeshRunState run;
  if (resumed) run = resumed->state;
  run.events = stream.events.size();
  if (checkpoint_every > 0 && !resumed) run.stream_fingerprint = streamFingerprint(stream);
  run.trajectory_evidence = evidence.settings();
  mesher::Mesher mesher = resumed ? std::move(resumed->mesher) : mesher::Mesher(config);
  if (traversability && evidence.enabled()) traversability->setDrivePoses(evidence.drivePoses());
  // The poses first: the layers read where the robot faced on its driven samples.
  if (resumed) evidence.replay(stream, run.next_event);
  if (traversability && resumed) traversability->resume(mesher, run.keyframes);
  if (!quiet && !evidence.summary().empty()) std::cerr << "terramesh: " << evidence.summary() << '\n';
  if (!quiet && evidence.warning()) std::cerr << "terramesh: warning: " << *evidence.warning() << '\n';
  const bool scale_known = stream.scale_known || mesher_options.metres_per_unit.has_value();
  const std::vector<std::string> frame_comments = frameComments(
      stream, scale_known ? std::optional<double>(config.metres_per_unit) : std::nullopt, traversability, evidence);
  std::ostringstream csv;
  csv << (resumed ? run.csv : updateCsvHeader() + "\n");
  mesher::UpdateStats totals = run.totals;
  std::size_t keyframes = run.keyframes;
  const std::size_t first_event = run.next_event;
  const std::filesystem::path checkpoint_path = output / kCheckpointFileName;
  auto saveCheckpoint = [&](std::size_t next_event) {
    run.next_event = next_event;
    run.keyframes = keyframes;
    run.totals = totals;
    run.csv = csv.str();
    writeMeshCheckpoint(checkpoint_path, mesher, run);
  };
  int stop_signal = 0;
  std::size_t end_event = stream.events.size();
  const StopSignalScope stop_scope;
  ProgressBar progress("meshing", stream.events.size());
  for (std::size_t i = first_event; i < stream.events.size(); ++i) {
    const datasets::StreamEvent& event = stream.events[i];
    const mesher::UpdateStats stats = evidence.apply(mesher, event);
    totals += stats;
    std::uint64_t id = 0;
    const std::string kind = eventKind(event, id);
    csv << updateCsvRow(i, kind, id, stats, mesher.size()) << '\n';
    if (check) {
      const mesher::InvariantReport report = mesher.checkInvariants();
      if (!report.ok()) {
        throw std::runtime_error("invariant check failed after event " + std::to_string(i) + ": " +
                                 report.summary());
      }
    }
    if (traversability) traversability->afterEvent(mesher, i, kind == "keyframe");
    if (kind == "keyframe") {
      ++keyframes;
      if (snapshot_every > 0 && keyframes % static_cast<std::size_t>(snapshot_every) == 0) {
        char name[64];
        std::snprintf(name, sizeof(name), "mesh_%06zu.%s", keyframes, format.c_str());
        writeMesh(output / "snapshots" / name, mesher.extractMesh(), frame_comments);
      }
    }
    stop_signal = StopSignalScope::requested();
    const bool checkpoint_due = checkpoint_every > 0 && kind == "keyframe" &&
                                keyframes % static_cast<std::size_t>(checkpoint_every) == 0;
    if (checkpoint_due || (stop_signal != 0 && checkpoint_every > 0)) saveCheckpoint(i + 1);
    progress.update(i + 1);
    if (stop_signal != 0) {
      end_event = i + 1;
      break;
    }
  }

  const mesher::TriangleMesh mesh = mesher.extractMesh();
  const std::filesystem::path mesh_path = output / ("mesh." + format);
  writeMesh(mesh_path, mesh, frame_comments);
  writeFileAtomically(output / "keyframes.csv", csv.str());
  writeRunExtras(stream, output);
  const mesher::MeshTopology topology = mesher::analyzeTopology(mesh);
  std::ostringstream summary;
  summary << "input: " << input.string() << "\nmode: " << mesher::toString(config.mode())
          << "\nmetres_per_unit: " << config.metres_per_unit << "\nkeyframes: " << keyframes
          << "\nevents: " << stream.events.size() << "\nmesh: " << mesh_path.string() << " ("
          << describeTopology(topology) << ")\n";
  for (const std::string& note : stream.reader_notes) summary << "input: " << note << '\n';
  for (const std::string& warning : stream.reader_warnings) summary << "warning: " << warning << '\n';
  if (resumed) summary << "resumed: from " << *resume_path << " at event " << first_event << '\n';
  if (stop_signal != 0) {
    summary << "stopped: by signal " << stop_signal << " after event " << end_event - 1 << " (" << keyframes
            << " keyframes); exit code " << exitCodeForSignal(stop_signal) << '\n';
  }
  printStepTotals(summary, totals, keyframes);
  if (autoMaxDistance(mesher_options, stream)) {
    summary << "max_camera_distance_m: auto, " << kAutoMaxDistanceFactor << " x the "
            << 100 * kAutoMaxDistanceQuantile << "th percentile of the camera-to-point distances\n";
  }
  printInputFilters(summary, totals, mesher.size(), config);
  for (const std::string& warning : inputFilterWarnings(totals, mesher.size(), config)) {
    if (!quiet) std::cerr << "terramesh: warning: " << warning << '\n';
  }
  if (drop_steiner) {
    const mesher::TriangleMesh open = mesher::dropSteinerFaces(mesh);
    const std::filesystem::path open_path = output / ("mesh_open." + format);
    writeMesh(open_path, open, frame_comments);
    const mesher::MeshTopology open_topology = mesher::analyzeTopology(open);
    summary << "open surface: " << open_path.string() << " (" << open_topology.vertices
            << " vertices, " << open_topology.faces << " faces, " << open_topology.boundary_edges
            << " boundary edges, " << open_topology.non_manifold_vertices
            << " non-manifold vertices)\n";
  }
  if (!evidence.summary().empty()) summary << evidence.summary() << '\n';
  if (evidence.enabled()) {
    summary << "trajectory evidence: " << evidence.contradictedPoints()
            << " SLAM point(s) inside the robot's body where it drove, dropped as outliers; "
            << evidence.absorbedPoints()
            << " on the ground it drove (near the contact plane, under the footprint), stood for by the "
               "driven samples; "
            << evidence.overriddenKeyframes()
            << " keyframe(s) whose drive an obstacle seen later overrode (their driven evidence withdrawn)\n";
  }
  if (evidence.warning()) summary << "warning: " << *evidence.warning() << '\n';
  if (traversability) traversability->finish(mesher, summary);
  writeFileAtomically(output / "summary.txt", summary.str());
  if (!quiet) std::cout << summary.str();
  return stop_signal != 0 ? exitCodeForSignal(stop_signal) : kExitOk;
}

}  // namespace terramesh::cli

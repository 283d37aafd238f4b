// terramesh mesh INPUT -o OUTDIR: runs the incremental mesher over a SLAM stream.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli_args.h"
#include "commands.h"
#include "common/atomic_file.h"
#include "datasets/stream_reader.h"
#include "mesher/mesh_io.h"
#include "mesher/mesher.h"
#include "input_options.h"
#include "mesher_options.h"
#include "progress_bar.h"
#include "stats_table.h"
#include "run_extras.h"
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

void writeMesh(const std::filesystem::path& path, const mesher::TriangleMesh& mesh) {
  if (path.extension() == ".obj") {
    mesher::writeObj(path, mesh);
  } else {
    mesher::writePly(path, mesh);
  }
}

std::string describeTopology(const mesher::MeshTopology& t) {
  std::ostringstream out;
  out << t.vertices << " vertices, " << t.faces << " faces, " << t.components << " component(s), "
      << "genus " << t.total_genus << (t.isClosedManifold() ? ", closed 2-manifold" : "");
  return out.str();
}

}  // namespace

int runMesh(const std::vector<std::string>& args) {
  ArgParser parser("mesh");
  parser
      .positional("INPUT",
                  "SLAM stream: the authors' JSON (.json), terramesh's (.tmstream), "
                  "OpenMVG sfm_data.json, Bundler .out, or a COLMAP or KITTI directory")
      .option("--output", "DIR", "output directory (created if missing)")
      .alias("-o", "--output")
      .option("--mode", "MODE", "proposed, litvinov13 or romanoni15", "proposed")
      .option("--format", "FMT", "mesh format: ply or obj", "ply")
      .option("--snapshot-every", "K", "also write the mesh every K keyframes (0: never)", "0")
      .flag("--drop-steiner",
            "also write mesh_open.ply: the surface without faces touching Steiner vertices")
      .flag("--check-invariants", "check every invariant after each update (slow; for testing)")
      .flag("--quiet", "print nothing but errors");
  declareInputOptions(parser);
  declareMesherOptions(parser);
  TraversabilitySession::declareOptions(parser);
  parser.parse(args);
  if (parser.helpRequested()) {
    std::cout << parser.usage();
    return kExitOk;
  }
  if (!parser.has("--output")) throw UsageError("mesh: -o/--output DIR is required");
  const std::string format = parser.get("--format");
  if (format != "ply" && format != "obj") throw UsageError("mesh: --format must be ply or obj");
  const long snapshot_every = parser.getInt("--snapshot-every");
  if (snapshot_every < 0) throw UsageError("mesh: --snapshot-every must be >= 0");
  const auto mode = mesher::parseMesherMode(parser.get("--mode"));
  if (!mode) throw UsageError("mesh: --mode must be proposed, litvinov13 or romanoni15");
  const bool quiet = parser.flagSet("--quiet");
  const datasets::StreamReadOptions read_options = streamReadOptionsFromArgs(parser);

  // Read and validate everything before creating any output.
  const std::filesystem::path input = parser.positionalValue("INPUT");
  const datasets::SlamStream stream = datasets::readAnyStream(input, read_options);
  const mesher::MesherConfig config = mesherConfigFromArgs(parser, *mode, stream);
  const std::filesystem::path output = parser.get("--output");
  std::optional<TraversabilitySession> traversability =
      TraversabilitySession::fromArgs(parser, stream, config.metres_per_unit, output);
  std::filesystem::create_directories(output);
  if (snapshot_every > 0) std::filesystem::create_directories(output / "snapshots");

  mesher::Mesher mesher(config);
  std::ostringstream csv;
  csv << updateCsvHeader() << '\n';
  mesher::UpdateStats totals;
  std::size_t keyframes = 0;
  ProgressBar progress("meshing", stream.events.size());
  const bool check = parser.flagSet("--check-invariants");
  for (std::size_t i = 0; i < stream.events.size(); ++i) {
    const datasets::StreamEvent& event = stream.events[i];
    const mesher::UpdateStats stats = datasets::applyEvent(mesher, event);
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
        writeMesh(output / "snapshots" / name, mesher.extractMesh());
      }
    }
    progress.update(i + 1);
  }

  const mesher::TriangleMesh mesh = mesher.extractMesh();
  const std::filesystem::path mesh_path = output / ("mesh." + format);
  writeMesh(mesh_path, mesh);
  writeFileAtomically(output / "keyframes.csv", csv.str());
  writeRunExtras(stream, output);
  const mesher::MeshTopology topology = mesher::analyzeTopology(mesh);
  std::ostringstream summary;
  summary << "input: " << input.string() << "\nmode: " << mesher::toString(config.mode)
          << "\nmetres_per_unit: " << config.metres_per_unit << "\nkeyframes: " << keyframes
          << "\nevents: " << stream.events.size() << "\nmesh: " << mesh_path.string() << " ("
          << describeTopology(topology) << ")\n";
  printStepTotals(summary, totals, keyframes);
  if (autoMaxDistance(parser, stream)) {
    summary << "max_camera_distance_m: auto, " << kAutoMaxDistanceFactor << " x the "
            << 100 * kAutoMaxDistanceQuantile << "th percentile of the camera-to-point distances\n";
  }
  printInputFilters(summary, totals, mesher.size(), config);
  for (const std::string& warning : inputFilterWarnings(totals, mesher.size(), config)) {
    if (!quiet) std::cerr << "terramesh: warning: " << warning << '\n';
  }
  if (parser.flagSet("--drop-steiner")) {
    const mesher::TriangleMesh open = mesher::dropSteinerFaces(mesh);
    const std::filesystem::path open_path = output / ("mesh_open." + format);
    writeMesh(open_path, open);
    const mesher::MeshTopology open_topology = mesher::analyzeTopology(open);
    summary << "open surface: " << open_path.string() << " (" << open_topology.vertices
            << " vertices, " << open_topology.faces << " faces, " << open_topology.boundary_edges
            << " boundary edges, " << open_topology.non_manifold_vertices
            << " non-manifold vertices)\n";
  }
  if (traversability) traversability->finish(mesher, summary);
  writeFileAtomically(output / "summary.txt", summary.str());
  if (!quiet) std::cout << summary.str();
  return kExitOk;
}

}  // namespace terramesh::cli

// terramesh view OUTDIR: serves a run folder and the bundled web viewer on 127.0.0.1.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <fstream>
#include <string>
#include <vector>

#include "cli_args.h"
#include "commands.h"
#include "common/input_error.h"
#include "datasets/stream_reader.h"
#include "installed_files.h"
#include "run_extras.h"
#include "view_server.h"

#ifndef TERRAMESH_VIEWER_BUILD_DIR
#define TERRAMESH_VIEWER_BUILD_DIR ""
#endif
#ifndef TERRAMESH_VIEWER_INSTALL_SUBDIR
#define TERRAMESH_VIEWER_INSTALL_SUBDIR "share/terramesh/viewer"
#endif

namespace terramesh::cli {
namespace {

namespace fs = std::filesystem;

/// --bundle, else the installed bundle beside the executable (bin/../share/...), else the build
/// tree's. Empty if none holds index.html.
fs::path findBundle(const std::optional<std::string>& bundle) {
  if (bundle) {
    const fs::path dir = *bundle;
    if (!fs::is_regular_file(dir / "index.html")) throw InputError(dir.string(), "index.html", "missing (expected a viewer bundle: build/viewer/dist)");
    return dir;
  }
  const fs::path installed = shippedFolder(TERRAMESH_VIEWER_INSTALL_SUBDIR, "index.html");
  if (!installed.empty()) return installed;
  const fs::path built = TERRAMESH_VIEWER_BUILD_DIR;
  if (!built.empty() && fs::is_regular_file(built / "index.html")) return built;
  return {};
}

/// The stream named by --stream, else by summary.txt's "input:" line if that path exists.
fs::path findStream(const std::optional<std::string>& stream, const fs::path& run_dir) {
  if (stream) return *stream;
  std::ifstream summary(run_dir / "summary.txt");
  std::string line;
  while (std::getline(summary, line)) {
    if (line.rfind("input: ", 0) != 0) continue;
    const fs::path input = line.substr(7);
    std::error_code error;
    if (fs::exists(input, error)) return input;
  }
  return {};
}

/// The first OctoMap file of the run folder's top level (sorted by name), if any.
fs::path findOctomap(const fs::path& run_dir) {
  std::vector<fs::path> found;
  for (const auto& entry : fs::directory_iterator(run_dir)) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".bt" || ext == ".ot")) found.push_back(entry.path());
  }
  std::sort(found.begin(), found.end());
  return found.empty() ? fs::path() : found.front();
}

/// What the viewer serves beside the run folder's own files: the trajectory and points from the
/// stream when the folder lacks them, and voxels from its OctoMap file when it has no voxels.bin.
RunExtras runExtras(const fs::path& run_dir, const std::optional<std::string>& stream_file) {
  RunExtras extras;
  const bool has_trajectory = fs::is_regular_file(run_dir / "trajectory.csv");
  const bool has_points = fs::is_regular_file(run_dir / "points.ply");
  if (!has_trajectory || !has_points) {
    const fs::path stream_path = findStream(stream_file, run_dir);
    if (!stream_path.empty()) {
      const datasets::SlamStream stream = datasets::readAnyStream(stream_path);
      if (!has_trajectory) extras.trajectory_csv = trajectoryCsv(stream);
      if (!has_points) extras.points_ply = pointsPly(stream);
    }
  }
  if (!fs::is_regular_file(run_dir / "voxels.bin")) {
    const fs::path octomap_file = findOctomap(run_dir);
    if (!octomap_file.empty()) {
      extras.voxels_bin = octomapToVoxels(octomap_file);
      extras.voxels_source = octomap_file.filename().string();
    }
  }
  return extras;
}

}  // namespace

int runView(const std::vector<std::string>& args) {
  CLI::App app{"serve a run folder's web viewer on 127.0.0.1", "terramesh view"};
  app.option_defaults()->always_capture_default();
  std::string run_dir;
  int port = 8765;
  std::optional<std::string> stream_file, bundle;
  bool open = false;
  app.add_option("OUTDIR", run_dir,
                 "a run folder of `terramesh mesh` (mesh.ply; traversability.ply, snapshots/, path*.csv, "
                 "voxels.bin or *.bt when present), or a tiled map's folder (tiles.json of terramesh tiles merge: "
                 "the tiles around the view are loaded as it moves)")
      ->required();
  app.add_option("--port", port, "TCP port on 127.0.0.1 (0: any free port)")->check(CLI::Range(0, 65535));
  app.add_option("--stream", stream_file,
                 "the run's SLAM stream, for the trajectory and points when OUTDIR has no trajectory.csv / "
                 "points.ply (default: summary.txt's input, if it exists)")
      ->option_text("FILE");
  app.add_option("--bundle", bundle, "the viewer bundle (default: the installed one, else the build tree's)")
      ->option_text("DIR");
  app.add_flag("--open", open, "also open the page with xdg-open (off by default: headless machines)");
  if (!parseCommandLine(app, args)) return kExitOk;
  ViewServerConfig config;
  config.run_dir = run_dir;
  config.port = port;
  if (!fs::is_directory(config.run_dir)) throw InputError(config.run_dir.string(), "OUTDIR", "not a directory (expected a run folder of terramesh mesh)");
  if (!fs::is_regular_file(config.run_dir / "mesh.ply") && !fs::is_regular_file(config.run_dir / "tiles.json")) {
    throw InputError((config.run_dir / "mesh.ply").string(), "file",
                     "missing (expected the run's mesh: terramesh mesh STREAM -o OUTDIR; or a tiled map's tiles.json)");
  }
  config.bundle_dir = findBundle(bundle);
  if (config.bundle_dir.empty()) {
    std::cerr << "terramesh view: no viewer bundle found (configured with TERRAMESH_BUILD_VIEWER=OFF, or npm was "
                 "missing at build time); pass --bundle DIR\n";
    return kExitFailure;
  }

  const RunExtras extras = runExtras(config.run_dir, stream_file);
  serveRun(config, extras, [&](int bound_port) {
    const std::string url = "http://127.0.0.1:" + std::to_string(bound_port) + "/";
    std::cout << "terramesh view: serving " << config.run_dir.string() << " at " << url << "  (Ctrl-C to stop)"
              << std::endl;
    if (open) {
      if (!startProgram({"xdg-open", url})) std::cerr << "terramesh view: xdg-open failed; open " << url << '\n';
    }
  });
  return kExitOk;
}

}  // namespace terramesh::cli

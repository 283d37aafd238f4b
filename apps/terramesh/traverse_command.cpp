// terramesh traverse MESH --robot R.yaml -o OUT: traversability layers of a finished mesh and every
// export of the map directory (traversability.ply, Nav2 maps per level, GeoTIFF layers).
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>

#include "cli_args.h"
#include "commands.h"
#include "mesh_frame_hints.h"
#include "mesher/mesh_io.h"
#include "traversability/map_directory.h"
#include "traversability/traversability_map.h"
#include "traversability_session.h"

namespace terramesh::cli {

namespace {

/// The mesh's frame: the given scale and up first, then the profile's gravity (up only), then what
/// the mesh's header records (said through `say`), else 1 and +z (said too).
/// @throw std::invalid_argument if the frame does not validate.
traversability::MapFrame resolveFrame(const std::optional<double>& metres_per_unit, const Eigen::Vector3d* given_up,
                                      const traversability::RobotProfile& profile, const MeshFrameHints& hints,
                                      const std::function<void(const std::string&)>& say) {
  traversability::MapFrame frame;
  if (metres_per_unit) {
    frame.metres_per_unit = *metres_per_unit;
  } else if (hints.metres_per_unit) {
    frame.metres_per_unit = *hints.metres_per_unit;
    std::ostringstream text;
    text << "metres_per_unit " << frame.metres_per_unit << ", from the mesh's header (--metres-per-unit overrides)";
    say(text.str());
  } else {
    say("the mesh's header records no scale: metres_per_unit 1 (--metres-per-unit sets it)");
  }
  if (given_up != nullptr) {
    frame.up_W = *given_up;
  } else if (profile.gravity_W) {
    frame.up_W = -profile.gravity_W->normalized();
  } else if (hints.up_W) {
    frame.up_W = *hints.up_W;
    std::ostringstream text;
    text << "up (" << frame.up_W.x() << ", " << frame.up_W.y() << ", " << frame.up_W.z() << "), from the mesh's header"
         << (hints.up_source.empty() ? "" : " (" + hints.up_source + ")") << " (--up overrides)";
    say(text.str());
  } else {
    say("the profile's gravity is auto and the mesh's header records no up: using up = +z (--up sets it)");
    frame.up_W = Eigen::Vector3d::UnitZ();
  }
  frame.validate();
  return frame;
}

}  // namespace

int runTraverse(const std::vector<std::string>& args) {
  CLI::App app{"traversability map of a finished mesh for a robot: PLY layers, Nav2 maps, GeoTIFF",
               "terramesh traverse"};
  app.option_defaults()->always_capture_default();
  std::string mesh_file, output_dir;
  std::optional<double> metres_per_unit;
  std::optional<std::string> up;
  bool quiet = false;
  TraversabilityExportOptions export_options;
  app.add_option("MESH", mesh_file,
                 "mesh (.ply with the per-vertex `steiner` flag of terramesh mesh; .obj/.off: all measured)")
      ->required();
  app.add_option("-o,--output", output_dir, "map directory to write (created if missing)")->option_text("DIR");
  app.add_option("--metres-per-unit", metres_per_unit,
                 "size of one mesh unit in metres (default: what the mesh's header records, else 1)")
      ->check(positiveNumber());
  app.add_option("--up", up,
                 "up vector in the mesh frame (default: the profile's gravity, else what the mesh's header records, "
                 "else +z)")
      ->option_text("X,Y,Z");
  app.add_flag("--quiet", quiet, "print nothing but errors");
  addTraversabilityExportOptions(app, export_options);
  if (!parseCommandLine(app, args)) return kExitOk;
  if (output_dir.empty()) throw UsageError("traverse: -o/--output DIR is required");
  if (!export_options.robot) throw UsageError("traverse: --robot YAML is required");
  if (metres_per_unit && (!(*metres_per_unit > 0) || !std::isfinite(*metres_per_unit))) {
    throw UsageError("traverse: --metres-per-unit must be > 0");
  }
  const Eigen::Vector3d given_up = up ? parseUpVector(*up) : Eigen::Vector3d::UnitZ();  // checked first
  const traversability::ExportConfig config = exportConfigFrom(export_options);
  const traversability::RobotProfile profile = robotFrom(export_options);
  const std::filesystem::path input = mesh_file;
  const MeshFrameHints hints = readMeshFrameHints(input);
  const std::function<void(const std::string&)> say = [quiet](const std::string& text) {
    if (!quiet) std::cerr << "terramesh traverse: " << text << '\n';
  };
  const traversability::MapFrame frame = resolveFrame(metres_per_unit, up ? &given_up : nullptr, profile, hints, say);
  const mesher::TriangleMesh mesh = mesher::readMesh(input);

  // Without Steiner flags every face counts as measured: it gets enough rays to be known.
  const auto rays_if_unknown = static_cast<std::uint32_t>(profile.min_rays);
  traversability::LayeredMesh map = traversability::TraversabilityMap::computeForMesh(mesh, profile, frame, rays_if_unknown);
  map.up_W = frame.up_W;
  map.metres_per_unit = frame.metres_per_unit;
  const std::filesystem::path output = output_dir;
  const traversability::ExportReport report = traversability::writeMapDirectory(output, map, profile, config);
  if (!quiet) {
    std::cout << "input: " << input.string() << "\nrobot: " << profile.name << "\nmap directory: " << output.string()
              << " (" << report.files.size() << " files)\n"
              << report.summary;
  }
  return kExitOk;
}

}  // namespace terramesh::cli

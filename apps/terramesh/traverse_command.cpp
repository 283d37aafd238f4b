// terramesh traverse MESH --robot R.yaml -o OUT: traversability layers of a finished mesh and every
// export of the map directory (traversability.ply, Nav2 maps per level, GeoTIFF layers).
#include <filesystem>
#include <iostream>

#include "cli_args.h"
#include "commands.h"
#include "mesher/mesh_io.h"
#include "traversability/map_directory.h"
#include "traversability/traversability_map.h"
#include "traversability_session.h"

namespace terramesh::cli {

int runTraverse(const std::vector<std::string>& args) {
  ArgParser parser("traverse");
  parser.positional("MESH", "mesh (.ply with the per-vertex `steiner` flag of terramesh mesh; .obj/.off: all measured)")
      .option("--output", "DIR", "map directory to write (created if missing)")
      .alias("-o", "--output")
      .option("--metres-per-unit", "S", "size of one mesh unit in metres", "1")
      .option("--up", "X,Y,Z", "up vector in the mesh frame (default: the profile's gravity, else +z)")
      .flag("--quiet", "print nothing but errors");
  declareTraversabilityExportOptions(parser);
  parser.parse(args);
  if (parser.helpRequested()) {
    std::cout << parser.usage();
    return kExitOk;
  }
  if (!parser.has("--output")) throw UsageError("traverse: -o/--output DIR is required");
  if (!parser.has("--robot")) throw UsageError("traverse: --robot YAML is required");
  const double metres_per_unit = parser.getDouble("--metres-per-unit");
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit)) {
    throw UsageError("traverse: --metres-per-unit must be > 0");
  }
  const bool quiet = parser.flagSet("--quiet");
  const traversability::ExportConfig config = exportConfigFromArgs(parser);
  const traversability::RobotProfile profile = robotFromArgs(parser);
  traversability::MapFrame frame;
  frame.metres_per_unit = metres_per_unit;
  if (parser.has("--up")) {
    frame.up_W = parseUpVector(parser.get("--up"));
  } else if (profile.gravity_W) {
    frame.up_W = -profile.gravity_W->normalized();
  } else {
    // A mesh file has no cameras to estimate gravity from.
    if (!quiet) std::cerr << "terramesh traverse: the profile's gravity is auto and a mesh has no cameras: using up = +z\n";
    frame.up_W = Eigen::Vector3d::UnitZ();
  }
  frame.validate();
  const std::filesystem::path input = parser.positionalValue("MESH");
  const mesher::TriangleMesh mesh = mesher::readMesh(input);

  // Without Steiner flags every face counts as measured: it gets enough rays to be known.
  const auto rays_if_unknown = static_cast<std::uint32_t>(profile.min_rays);
  traversability::LayeredMesh map = traversability::TraversabilityMap::computeForMesh(mesh, profile, frame, rays_if_unknown);
  map.up_W = frame.up_W;
  map.metres_per_unit = frame.metres_per_unit;
  const std::filesystem::path output = parser.get("--output");
  const traversability::ExportReport report = traversability::writeMapDirectory(output, map, profile, config);
  if (!quiet) {
    std::cout << "input: " << input.string() << "\nrobot: " << profile.name << "\nmap directory: " << output.string()
              << " (" << report.files.size() << " files)\n"
              << report.summary;
  }
  return kExitOk;
}

}  // namespace terramesh::cli

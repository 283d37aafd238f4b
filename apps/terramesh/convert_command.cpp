// terramesh convert IN OUT: maps to and from the PCL and OctoMap worlds, chosen by extension.
#include <filesystem>
#include <iostream>
#include <sstream>

#include "baselines/pcl_io.h"
#include "baselines/slam_points.h"
#include "baselines/voxel_surface.h"
#include "cli_args.h"
#include "commands.h"
#include "common/input_error.h"
#include "datasets/stream_format.h"
#include "datasets/stream_reader.h"
#include "input_options.h"
#include "mesher/mesh_io.h"
#include "traversability/map_directory.h"

namespace terramesh::cli {
namespace {

struct ConvertOptions {
  std::string input;
  std::string output;
  std::string to = "pcl";
  double resolution_m = 0.2;
  double max_range_m = 40;
  std::optional<double> metres_per_unit;
  std::optional<int> min_views;
  std::vector<double> up;
  bool quiet = false;
};

std::string extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool isMeshExtension(const std::string& ext) { return ext == ".ply" || ext == ".obj" || ext == ".off" || ext == ".vtk"; }

/// A traversability map: a map directory, or the traversability.ply inside one.
bool isMapDirectory(const std::filesystem::path& path) {
  const std::filesystem::path dir = std::filesystem::is_directory(path) ? path : path.parent_path();
  return std::filesystem::is_regular_file(dir / "traversability.ply") && std::filesystem::is_regular_file(dir / "map_frame.yaml") &&
         (std::filesystem::is_directory(path) || path.filename() == "traversability.ply");
}

void writeMeshOurs(const std::filesystem::path& path, const mesher::TriangleMesh& mesh) {
  const std::string ext = extension(path);
  if (ext == ".ply") {
    mesher::writePly(path, mesh);
  } else if (ext == ".obj") {
    mesher::writeObj(path, mesh);
  } else {
    throw UsageError("convert: terramesh meshes are written as .ply or .obj, not " + path.string());
  }
}

std::string describe(const mesher::TriangleMesh& mesh) {
  return std::to_string(mesh.vertices.size()) + " vertices, " + std::to_string(mesh.faces.size()) + " faces";
}

void declareOptions(CLI::App& app, ConvertOptions& o) {
  app.add_option("IN", o.input, "input file or directory")->required();
  app.add_option("OUT", o.output, "output file; its extension picks the conversion")->required();
  app.add_option("--to", o.to, "mesh to mesh: pcl (write with PCL) or terramesh (read with PCL, write ours)")->capture_default_str()
      ->check(CLI::IsMember({"pcl", "terramesh"}));
  app.add_option("--resolution-m", o.resolution_m, "STREAM -> .bt: voxel size")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-range-m", o.max_range_m, "STREAM -> .bt: rays cut at this length (<= 0: none)")->capture_default_str();
  app.add_option("--metres-per-unit", o.metres_per_unit,
                 "STREAM -> .bt/.pcd, .bt -> mesh: map scale (default: the stream's, else 1)")
      ->check(CLI::PositiveNumber);
  app.add_option("--min-views", o.min_views,
                 "STREAM -> .pcd: keyframes that must see a point (default: what the stream advises, 1 for LiDAR, "
                 "else 2)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--up", o.up, ".bt -> mesh: map the octree frame back to a map whose up is X Y Z (default: keep the octree's z-up frame)")
      ->expected(3);
  app.add_flag("--quiet", o.quiet, "print nothing but errors");
}

/// The conversion of o.input into o.output their extensions pick; returns what it wrote.
std::string convertOne(const ConvertOptions& o) {
  const std::filesystem::path in = o.input, out = o.output;
  const std::string in_ext = extension(in), out_ext = extension(out);
  if (!std::filesystem::exists(in)) throw InputError(in.string(), "file", "an existing file or directory");
  std::ostringstream summary;
  if (in_ext == ".bt") {
    if (out_ext != ".ply" && out_ext != ".obj") throw UsageError("convert: a .bt converts to a mesh (.ply or .obj)");
    baselines::OctomapFrame frame;
    if (!o.up.empty()) frame.up_W = Eigen::Vector3d(o.up[0], o.up[1], o.up[2]);
    frame.metres_per_unit = o.metres_per_unit.value_or(1.0);
    const mesher::TriangleMesh mesh = baselines::voxelSurfaceFromBt(in, frame);
    writeMeshOurs(out, mesh);
    summary << "voxel surface of " << in.string() << ": " << describe(mesh);
  } else if (isMapDirectory(in)) {
    if (out_ext != ".pcd") throw UsageError("convert: a traversability map converts to .pcd");
    const std::filesystem::path dir = std::filesystem::is_directory(in) ? in : in.parent_path();
    const traversability::MapDirectory loaded = traversability::readMapDirectory(dir);
    baselines::writeTraversabilityPcd(out, loaded.map);
    summary << "face centroids with layers: " << loaded.map.mesh.faces.size() << " points";
  } else if (isMeshExtension(in_ext) && in_ext != ".vtk" && isMeshExtension(out_ext)) {
    if (o.to == "pcl") {
      const mesher::TriangleMesh mesh = mesher::readMesh(in);
      baselines::writeMeshWithPcl(out, mesh);
      summary << "written by PCL: " << describe(mesh);
    } else {
      if (in_ext == ".off") throw UsageError("convert: --to terramesh reads with PCL's readers (.ply, .obj)");
      const mesher::TriangleMesh mesh = baselines::readMeshWithPcl(in);
      writeMeshOurs(out, mesh);
      summary << "read by PCL: " << describe(mesh);
    }
  } else if (out_ext == ".tmstream") {
    // The stream `terramesh mesh IN` meshes: LiDAR input thinned and merged with mesh's defaults.
    const datasets::SlamStream stream = datasets::readAnyStream(in, streamReadOptionsFrom(InputOptions()));
    datasets::writeStreamFile(out, stream);
    summary << "stream: " << stream.events.size() << " events";
  } else if (out_ext == ".pcd" || out_ext == ".bt") {
    const datasets::SlamStream stream = datasets::readAnyStream(in);
    const double metres_per_unit = o.metres_per_unit.value_or(stream.scale_known ? stream.metres_per_unit : 1.0);
    if (out_ext == ".pcd") {
      baselines::SlamPointsConfig config;
      const bool advised = stream.recommended_min_views > 0;
      config.min_views = o.min_views.value_or(advised ? stream.recommended_min_views : 2);
      const baselines::SlamPoints points = baselines::collectSlamPoints(stream, config);
      baselines::writeSlamPointsPcd(out, points);
      summary << "SLAM points with viewpoints (map units): " << points.size() << " points seen by at least "
              << config.min_views << " keyframe(s) ("
              << (o.min_views ? "--min-views" : advised ? "as the input advises; --min-views overrides"
                                                        : "the default; --min-views overrides")
              << ")";
    } else {
      const baselines::OctomapBuild build = baselines::buildOctomap(
          stream, o.resolution_m, o.max_range_m, {baselines::streamUp(stream), metres_per_unit}, out);
      summary << "OctoMap " << o.resolution_m << " m (z up, metres): " << build.occupied_leaves << " occupied leaves from "
              << build.points << " points";
    }
  } else {
    throw UsageError("convert: no conversion from " + in.string() + " to " + out.string() + " (see --help)");
  }
  return summary.str();
}

}  // namespace

int runConvert(const std::vector<std::string>& args) {
  CLI::App app("Converts maps to and from PCL and OctoMap files, by extension:\n"
               "  MESH (.ply/.obj/.off)  -> .ply/.obj/.vtk  through pcl::PolygonMesh and PCL's writers (--to pcl)\n"
               "  PCL mesh (.ply/.obj)   -> .ply/.obj       read by PCL's readers, written by terramesh (--to terramesh)\n"
               "  STREAM                 -> .pcd            SLAM points, each with its observing camera as viewpoint\n"
               "  STREAM                 -> .bt             OctoMap from the camera-to-point rays\n"
               "  STREAM                 -> .tmstream       the same stream in terramesh's own format (any input mesh reads)\n"
               "  .bt                    -> .ply/.obj       the faces of the occupied voxels as a mesh\n"
               "  MAP_DIR or its traversability.ply -> .pcd  face centroids with every layer as a field",
               "terramesh convert");
  ConvertOptions o;
  declareOptions(app, o);
  if (!parseCommandLine(app, args)) return kExitOk;

  const std::string summary = convertOne(o);
  if (!o.quiet) std::cout << summary << " -> " << o.output << '\n';
  return kExitOk;
}

}  // namespace terramesh::cli

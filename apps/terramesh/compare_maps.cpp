#include "compare_maps.h"

#include <chrono>
#include <cstdio>
#include <sstream>

#include "baselines/pcl_io.h"
#include "baselines/slam_points.h"
#include "baselines/voxel_surface.h"
#include "cli_args.h"
#include "compare_runner.h"
#include "mesher/mesh_io.h"
#include "mesher/mesher.h"

namespace terramesh::cli {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string number(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

std::vector<MapSpec> allMethods() {
  using Kind = MapSpec::Kind;
  std::vector<MapSpec> specs;
  for (const mesher::MesherMode mode :
       {mesher::MesherMode::kProposed, mesher::MesherMode::kLitvinov13, mesher::MesherMode::kRomanoni15}) {
    MapSpec spec;
    spec.kind = Kind::kMesher;
    spec.mode = mode;
    spec.slug = mesher::toString(mode);
    spec.name = std::string("mesher ") + mesher::toString(mode);
    specs.push_back(spec);
  }
  for (const double resolution : {0.1, 0.2, 0.5}) {
    MapSpec spec;
    spec.kind = Kind::kOctomap;
    spec.resolution_m = resolution;
    char slug[32];
    std::snprintf(slug, sizeof(slug), "octomap-%.1f", resolution);
    spec.slug = slug;
    std::snprintf(slug, sizeof(slug), "OctoMap %.1f m", resolution);
    spec.name = slug;
    specs.push_back(spec);
  }
  for (const baselines::PclMethod method : {baselines::PclMethod::kGreedyProjection, baselines::PclMethod::kPoisson,
                                            baselines::PclMethod::kMarchingCubesHoppe}) {
    MapSpec spec;
    spec.kind = Kind::kPcl;
    spec.pcl = method;
    spec.slug = baselines::toString(method);
    spec.name = std::string("PCL ") + baselines::toString(method);
    specs.push_back(spec);
  }
  return specs;
}

JobResults buildMesher(const MapSpec& spec, const BuildContext& context, const std::filesystem::path& file) {
  const mesher::MesherConfig config = context.mesher_config(spec.mode);
  const auto started = Clock::now();
  mesher::Mesher mesher(config);
  for (const datasets::StreamEvent& event : context.stream->events) datasets::applyEvent(mesher, event);
  const mesher::TriangleMesh mesh = mesher.extractMesh();
  const double seconds = since(started);
  mesher::writePly(file, mesh);
  return {{"build_s", number(seconds)},
          {"parameters", "mode " + std::string(mesher::toString(spec.mode)) + ", Steiner step " +
                             number(config.steiner_step_m) + " m, min views " + std::to_string(config.min_views) +
                             ", max camera distance " + number(config.max_camera_distance_m) + " m"}};
}

JobResults buildOctomapMap(const MapSpec& spec, const BuildContext& context, const std::filesystem::path& file) {
  const baselines::OctomapFrame frame{context.up_W, context.metres_per_unit};
  const baselines::OctomapBuild build =
      baselines::buildOctomap(*context.stream, spec.resolution_m, context.max_distance_m, frame, file);
  return {{"build_s", number(build.seconds)},
          {"parameters", "resolution " + number(spec.resolution_m) + " m, rays cut at " +
                             number(context.max_distance_m) + " m, OctoMap's default sensor model; " +
                             std::to_string(build.points) + " points from " + std::to_string(build.keyframes) +
                             " keyframe events; " + std::to_string(build.occupied_leaves) +
                             " occupied leaves; OcTree::memoryUsage " +
                             number(static_cast<double>(build.memory_bytes) / 1e6) + " MB"}};
}

JobResults buildPcl(const MapSpec& spec, const BuildContext& context, const std::filesystem::path& native,
                    const std::filesystem::path& surface) {
  const auto started = Clock::now();
  baselines::SlamPointsConfig points_config;
  points_config.min_views = context.min_views;
  points_config.max_camera_distance_units = context.max_distance_m / context.metres_per_unit;
  const baselines::SlamPoints points = baselines::collectSlamPoints(*context.stream, points_config);
  const baselines::PclSurfaceResult result = baselines::reconstructWithPcl(points, spec.pcl, context.pcl);
  const double seconds = since(started);
  baselines::writeMeshWithPcl(native, result.mesh);
  mesher::writePly(surface, result.mesh);
  return {{"build_s", number(seconds)},
          {"parameters", std::to_string(points.size()) + " SLAM points (seen by >= " +
                             std::to_string(context.min_views) + " keyframes); " + result.parameters +
                             " (map units; metres = x " + number(context.metres_per_unit) + ")"}};
}

}  // namespace

std::vector<MapSpec> parseMethods(const std::string& list) {
  const std::vector<MapSpec> all = allMethods();
  if (list == "all") return all;
  std::vector<MapSpec> chosen;
  std::istringstream in(list);
  std::string slug;
  while (std::getline(in, slug, ',')) {
    bool found = false;
    for (const MapSpec& spec : all) {
      if (spec.slug == slug) {
        chosen.push_back(spec);
        found = true;
      }
    }
    if (!found) {
      std::string names;
      for (const MapSpec& spec : all) names += (names.empty() ? "" : ", ") + spec.slug;
      throw UsageError("compare: --methods: unknown method \"" + slug + "\" (expected all or some of " + names + ")");
    }
  }
  if (chosen.empty()) throw UsageError("compare: --methods: empty list");
  return chosen;
}

BuiltMap buildMap(const MapSpec& spec, const BuildContext& context) {
  BuiltMap built;
  const std::filesystem::path dir = context.maps_dir;
  const bool octomap = spec.kind == MapSpec::Kind::kOctomap;
  built.native_file = dir / (spec.slug + (octomap ? ".bt" : spec.kind == MapSpec::Kind::kPcl ? "_pcl.ply" : ".ply"));
  built.surface_file = spec.kind == MapSpec::Kind::kMesher ? built.native_file : dir / (spec.slug + "_surface.ply");
  const IsolatedRun run = runIsolated([&]() -> JobResults {
    switch (spec.kind) {
      case MapSpec::Kind::kMesher: return buildMesher(spec, context, built.native_file);
      case MapSpec::Kind::kOctomap: return buildOctomapMap(spec, context, built.native_file);
      case MapSpec::Kind::kPcl: return buildPcl(spec, context, built.native_file, built.surface_file);
    }
    return {};
  });
  built.peak_rss_mb = run.peak_rss_mb;
  built.extra_peak_mb = run.extraPeakMb();
  if (!run.ok) {
    built.error = run.error;
    return built;
  }
  built.build_s = std::stod(run.results.at("build_s"));
  built.parameters = run.results.count("parameters") ? run.results.at("parameters") : "";
  built.size_bytes = std::filesystem::file_size(built.native_file);
  if (octomap) {
    const auto started = Clock::now();
    built.surface = baselines::voxelSurfaceFromBt(built.native_file, {context.up_W, context.metres_per_unit});
    built.to_surface_s = since(started);
    mesher::writePly(built.surface_file, built.surface);
  } else {
    built.surface = mesher::readMesh(built.surface_file);
  }
  built.ok = true;
  return built;
}

}  // namespace terramesh::cli

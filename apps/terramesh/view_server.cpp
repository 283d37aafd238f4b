#include "view_server.h"

// Eigen (through baselines) before httplib: httplib brings in <resolv.h>, whose `_res` macro
// breaks Eigen's product kernels.
#include "baselines/voxel_surface.h"

#include <httplib.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "common/input_error.h"
#include "traversability/layer_registry.h"

namespace terramesh::cli {
namespace {

namespace fs = std::filesystem;

bool isInside(const fs::path& root, const fs::path& target) {
  auto r = root.begin(), t = target.begin();
  for (; r != root.end(); ++r, ++t) {
    if (r->empty()) continue;  // a trailing separator
    if (t == target.end() || *r != *t) return false;
  }
  return true;
}

std::string readWholeFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  std::ostringstream content;
  content << in.rdbuf();
  return content.str();
}

void appendUint32(std::string& out, std::uint32_t word) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((word >> (8 * i)) & 0xFFu));
}

void appendFloat(std::string& out, float value) {
  std::uint32_t word = 0;
  std::memcpy(&word, &value, 4);
  appendUint32(out, word);
}

/// Files of the run folder's top level whose names match `pattern`, sorted.
std::vector<std::string> topLevelFiles(const fs::path& dir, const std::regex& pattern) {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && std::regex_match(name, pattern)) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

void sendFile(const fs::path& file, httplib::Response& response) {
  response.set_content(readWholeFile(file), contentTypeFor(file).c_str());
  response.set_header("Cache-Control", "no-store");
}

void refuse(httplib::Response& response, int status, const std::string& why) {
  response.status = status;
  response.set_content(why + "\n", "text/plain");
}

}  // namespace

std::optional<fs::path> resolveInside(const fs::path& root, const std::string& request) {
  if (request.empty() || request.front() == '/' || request.find('\\') != std::string::npos ||
      request.find('\0') != std::string::npos) {
    return std::nullopt;
  }
  const fs::path relative(request);
  if (relative.is_absolute() || relative.has_root_name()) return std::nullopt;
  for (const fs::path& part : relative) {
    if (part == ".." || part == ".") return std::nullopt;
  }
  std::error_code error;
  const fs::path canonical_root = fs::canonical(root, error);
  if (error) return std::nullopt;
  const fs::path target = fs::canonical(canonical_root / relative, error);
  if (error || !isInside(canonical_root, target) || !fs::is_regular_file(target, error)) return std::nullopt;
  return target;
}

std::string contentTypeFor(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".csv") return "text/csv; charset=utf-8";
  if (ext == ".txt" || ext == ".yaml" || ext == ".yml") return "text/plain; charset=utf-8";
  if (ext == ".png") return "image/png";
  if (ext == ".svg") return "image/svg+xml";
  return "application/octet-stream";
}

std::string runManifestJson(const fs::path& run_dir, const RunExtras& extras) {
  using nlohmann::json;
  json manifest;
  manifest["run"] = fs::weakly_canonical(run_dir).filename().string();
  const auto optional = [&](const char* key, const char* name) {
    manifest[key] = fs::is_regular_file(run_dir / name) ? json("run/" + std::string(name)) : json(nullptr);
  };
  optional("mesh", "mesh.ply");
  optional("traversability", "traversability.ply");
  optional("keyframes", "keyframes.csv");
  optional("summary", "summary.txt");
  optional("map_frame", "map_frame.yaml");
  optional("trajectory", "trajectory.csv");
  optional("points", "points.ply");
  optional("voxels", "voxels.bin");
  optional("tile_index", "tiles.json");  // a tiled map's folder (docs/tiles.md)
  if (manifest["trajectory"].is_null() && !extras.trajectory_csv.empty()) manifest["trajectory"] = "api/trajectory.csv";
  if (manifest["points"].is_null() && !extras.points_ply.empty()) manifest["points"] = "api/points.ply";
  if (manifest["voxels"].is_null() && !extras.voxels_bin.empty()) manifest["voxels"] = "api/voxels.bin";
  manifest["voxels_source"] = extras.voxels_source;

  json paths = json::array();
  for (const std::string& name : topLevelFiles(run_dir, std::regex(R"(path.*\.csv)"))) paths.push_back("run/" + name);
  manifest["paths"] = paths;

  json snapshots = json::array();
  const std::regex snapshot_name(R"(mesh_(\d+)\.ply)");
  if (fs::is_directory(run_dir / "snapshots")) {
    for (const std::string& name : topLevelFiles(run_dir / "snapshots", snapshot_name)) {
      std::smatch match;
      std::regex_match(name, match, snapshot_name);
      snapshots.push_back({{"keyframe", std::stoul(match[1].str())}, {"url", "run/snapshots/" + name}});
    }
  }
  manifest["snapshots"] = snapshots;

  // The per-face layers traversability.ply may hold: how the viewer labels them and their
  // display range (traversability/layer_registry.h).
  json layers = json::array();
  for (const traversability::LayerInfo& layer : traversability::faceLayerRegistry()) {
    json entry = {{"name", layer.name}, {"unit", layer.unit}, {"description", layer.description}};
    if (layer.display_min <= layer.display_max) entry["range"] = {layer.display_min, layer.display_max};
    layers.push_back(entry);
  }
  manifest["layers"] = layers;
  return manifest.dump(1);
}

std::string octomapToVoxels(const fs::path& file) {
  const std::vector<baselines::OctreeLeaf> leaves = baselines::readOccupiedLeaves(file);
  std::string voxels = "TMVOXEL1";
  appendUint32(voxels, static_cast<std::uint32_t>(leaves.size()));
  appendUint32(voxels, 0);
  for (const baselines::OctreeLeaf& leaf : leaves) {
    appendFloat(voxels, static_cast<float>(leaf.centre_G.x()));
    appendFloat(voxels, static_cast<float>(leaf.centre_G.y()));
    appendFloat(voxels, static_cast<float>(leaf.centre_G.z()));
    appendFloat(voxels, static_cast<float>(leaf.size));
  }
  return voxels;
}

void serveRun(const ViewServerConfig& config, const RunExtras& extras, const std::function<void(int)>& on_listening) {
  httplib::Server server;
  const fs::path run_dir = config.run_dir;
  const fs::path bundle_dir = config.bundle_dir;
  const auto serveFrom = [](const fs::path& root, const std::string& request, httplib::Response& response) {
    if (const auto file = resolveInside(root, request)) {
      sendFile(*file, response);
    } else {
      refuse(response, 404, "not found (or outside the served folder): " + request);
    }
  };
  server.Get("/api/manifest", [&](const httplib::Request&, httplib::Response& response) {
    response.set_content(runManifestJson(run_dir, extras), "application/json");
    response.set_header("Cache-Control", "no-store");
  });
  const auto memory = [&server](const char* route, const std::string& content, const char* type) {
    server.Get(route, [&content, type](const httplib::Request&, httplib::Response& response) {
      if (content.empty()) return refuse(response, 404, "not available for this run");
      response.set_content(content, type);
    });
  };
  memory("/api/trajectory.csv", extras.trajectory_csv, "text/csv; charset=utf-8");
  memory("/api/points.ply", extras.points_ply, "application/octet-stream");
  memory("/api/voxels.bin", extras.voxels_bin, "application/octet-stream");
  server.Get(R"(/run/(.*))", [&](const httplib::Request& request, httplib::Response& response) {
    serveFrom(run_dir, request.matches[1].str(), response);
  });
  server.Get(R"(/(.*))", [&](const httplib::Request& request, httplib::Response& response) {
    const std::string name = request.matches[1].str();
    serveFrom(bundle_dir, name.empty() ? "index.html" : name, response);
  });
  const int port = config.port == 0 ? server.bind_to_any_port("127.0.0.1")
                                    : (server.bind_to_port("127.0.0.1", config.port) ? config.port : -1);
  if (port <= 0) throw std::runtime_error("view: cannot bind 127.0.0.1:" + std::to_string(config.port));
  on_listening(port);
  if (!server.listen_after_bind()) throw std::runtime_error("view: the server stopped with an error");
}

}  // namespace terramesh::cli

#include "baselines/planning_pairs.h"

#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "planning/surface_planner.h"

namespace terramesh::baselines {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The truth's refined faces (a triangle soup) as an indexed mesh with every face kept, and its
/// answers as layers: traversable = free at cost 0, otherwise lethal.
traversability::LayeredMesh truthMap(const evaluation::GroundTruthTraversability& truth) {
  const mesher::TriangleMesh& soup = truth.mesh.mesh;
  traversability::LayeredMesh map;
  std::map<std::array<double, 3>, std::uint32_t> index;
  for (const auto& f : soup.faces) {
    std::array<std::uint32_t, 3> face{};
    for (std::size_t i = 0; i < 3; ++i) {
      const Eigen::Vector3d& p = soup.vertices[f[i]];
      const auto [it, inserted] = index.emplace(std::array<double, 3>{p.x(), p.y(), p.z()},
                                                static_cast<std::uint32_t>(map.mesh.vertices.size()));
      if (inserted) map.mesh.vertices.push_back(p);
      face[i] = it->second;
    }
    map.mesh.faces.push_back(face);
  }
  map.layers.resize(map.mesh.faces.size());
  for (std::size_t f = 0; f < map.layers.size(); ++f) {
    traversability::FaceLayers& l = map.layers[f];
    const bool free = truth.traversable[f] != 0;
    l.face_class = free ? traversability::FaceClass::kFree : traversability::FaceClass::kLethal;
    l.cost = free ? 0.0f : 1.0f;
    l.rays = 1;
  }
  map.up_W = truth.up_W;
  map.metres_per_unit = 1.0;
  return map;
}

}  // namespace

std::vector<PlanningPair> pairsOnTruth(const evaluation::GroundTruthTraversability& truth, std::size_t count,
                                       std::uint64_t seed, double min_distance_m) {
  planning::WalkabilityConfig walkability;
  walkability.min_lethal_distance_m = 0;
  const planning::FaceGraph graph(truthMap(truth), walkability);
  std::vector<PlanningPair> pairs;
  for (const auto& [start, goal] : planning::drawRandomPairs(graph, count, seed, min_distance_m)) {
    const planning::GraphPath path = graph.shortestPath(start, goal);
    pairs.push_back({start.point_W, goal.point_W, path.found ? path.length_m : kNaN});
  }
  return pairs;
}

std::vector<PlanningPair> pairsOnPoints(const std::vector<Eigen::Vector3d>& ground_W, std::size_t count,
                                        std::uint64_t seed, double min_distance_m) {
  std::vector<PlanningPair> pairs;
  if (ground_W.size() < 2) return pairs;
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<std::size_t> pick(0, ground_W.size() - 1);
  for (std::size_t attempt = 0; attempt < 100 * count && pairs.size() < count; ++attempt) {
    const std::size_t a = pick(random), b = pick(random);
    if (a == b || (ground_W[a] - ground_W[b]).norm() < min_distance_m) continue;
    pairs.push_back({ground_W[a], ground_W[b], kNaN});
  }
  return pairs;
}

PlanningScore planPairs(const traversability::LayeredMesh& map, const std::vector<PlanningPair>& pairs,
                        const planning::WalkabilityConfig& walkability, double snap_radius_m) {
  PlanningScore score;
  score.pairs = pairs.size();
  score.mean_length_m = score.mean_cost = score.mean_length_ratio = kNaN;
  if (pairs.empty() || map.mesh.faces.empty()) {
    score.no_start_or_goal = pairs.size();
    return score;
  }
  const planning::FaceGraph graph(map, walkability);
  planning::PlannerConfig config;
  config.planner = "rrtstar";  // not used by the graph baseline; validated all the same
  config.snap_radius_m = snap_radius_m;
  double length = 0, cost = 0, ratio = 0;
  std::size_t ratios = 0;
  for (const PlanningPair& pair : pairs) {
    const planning::PlanResult result = planning::planOnFaceGraph(graph, pair.start_W, pair.goal_W, config);
    switch (result.status) {
      case planning::PlanStatus::kSolved:
        ++score.solved;
        length += result.length_m;
        cost += result.cost;
        if (std::isfinite(pair.truth_length_m) && pair.truth_length_m > 0) {
          ratio += result.length_m / pair.truth_length_m;
          ++ratios;
        }
        break;
      case planning::PlanStatus::kNoStart:
      case planning::PlanStatus::kNoGoal:
        ++score.no_start_or_goal;
        break;
      case planning::PlanStatus::kUnreachable:
        ++score.unreachable;
        break;
      case planning::PlanStatus::kNotFound:
        break;
    }
  }
  if (score.solved > 0) {
    score.mean_length_m = length / static_cast<double>(score.solved);
    score.mean_cost = cost / static_cast<double>(score.solved);
  }
  if (ratios > 0) score.mean_length_ratio = ratio / static_cast<double>(ratios);
  return score;
}

}  // namespace terramesh::baselines

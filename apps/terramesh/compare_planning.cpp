#include "compare_planning.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <random>
#include <sstream>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "evaluation/cell_key.h"
#include "ground_truth_check.h"
#include "planning/surface_planner.h"

namespace terramesh::cli {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using evaluation::CellKey;
using CellHash = evaluation::CellKeyHash;
CellKey keyOf(const Eigen::Vector3d& p, double cell) { return geometry::cellOf(p, cell); }

/// Area-weighted centroids of the traversable truth faces, one per cell.
std::vector<Eigen::Vector3d> traversableSamples(const evaluation::GroundTruthTraversability& labels, double cell) {
  std::unordered_map<CellKey, std::pair<Eigen::Vector3d, double>, CellHash> cells;
  const mesher::TriangleMesh& mesh = labels.mesh.mesh;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!labels.traversable[f]) continue;
    const auto& t = mesh.faces[f];
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    const double area = 0.5 * (b - a).cross(c - a).norm();
    if (!(area > 0)) continue;
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    auto& slot = cells.try_emplace(keyOf(centroid, cell), Eigen::Vector3d::Zero(), 0.0).first->second;
    slot.first += area * centroid;
    slot.second += area;
  }
  std::vector<std::pair<CellKey, Eigen::Vector3d>> sorted;
  sorted.reserve(cells.size());
  for (const auto& [key, sum] : cells) sorted.emplace_back(key, sum.first / sum.second);
  // Deterministic order, whatever the hash table did.
  std::sort(sorted.begin(), sorted.end(), [](const auto& l, const auto& r) {
    return std::tie(l.first.i, l.first.j, l.first.k) < std::tie(r.first.i, r.first.j, r.first.k);
  });
  std::vector<Eigen::Vector3d> samples;
  samples.reserve(sorted.size());
  for (const auto& entry : sorted) samples.push_back(entry.second);
  return samples;
}

bool observed(const Eigen::Vector3d& p, const Eigen::Vector3d& up, const datasets::TriangleBvh& bvh,
              const std::vector<Eigen::Vector3d>& cameras, const TruthPairsConfig& config) {
  std::vector<std::pair<double, std::size_t>> near;
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const double d = (cameras[i] - p).norm();
    if (d <= config.max_view_distance_m) near.emplace_back(d, i);
  }
  if (static_cast<int>(near.size()) < config.min_views) return false;
  std::sort(near.begin(), near.end());
  const Eigen::Vector3d target = p + 0.05 * up;
  int seen = 0;
  for (const auto& [distance, i] : near) {
    if (!bvh.segmentOccluded(cameras[i], target, 0.02) && ++seen >= config.min_views) return true;
  }
  return false;
}

/// Neighbours within the link radius, per sample (only among `active` samples).
std::vector<std::vector<std::pair<std::uint32_t, double>>> linkSamples(const std::vector<Eigen::Vector3d>& samples,
                                                                         const std::vector<std::uint8_t>& active,
                                                                         double radius) {
  std::unordered_map<CellKey, std::vector<std::uint32_t>, CellHash> grid;
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    if (active[i]) grid[keyOf(samples[i], radius)].push_back(i);
  }
  std::vector<std::vector<std::pair<std::uint32_t, double>>> links(samples.size());
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    if (!active[i]) continue;
    const CellKey k = keyOf(samples[i], radius);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({k.i + dx, k.j + dy, k.k + dz});
          if (it == grid.end()) continue;
          for (std::uint32_t j : it->second) {
            const double d = (samples[j] - samples[i]).norm();
            if (j != i && d <= radius) links[i].emplace_back(j, d);
          }
        }
      }
    }
  }
  return links;
}

double dijkstra(const std::vector<std::vector<std::pair<std::uint32_t, double>>>& links, std::uint32_t from,
                std::uint32_t to) {
  std::vector<double> best(links.size(), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  best[from] = 0;
  open.emplace(0.0, from);
  while (!open.empty()) {
    const auto [d, u] = open.top();
    open.pop();
    if (u == to) return d;
    if (d > best[u]) continue;
    for (const auto& [v, w] : links[u]) {
      if (d + w < best[v]) {
        best[v] = d + w;
        open.emplace(best[v], v);
      }
    }
  }
  return kNaN;
}

planning::demo::TruthCheckConfig truthCheckConfig(const PathTruth& truth) {
  planning::demo::TruthCheckConfig config;
  config.footprint_radius_m = truth.footprint_radius_m;
  config.max_step_m = truth.max_step_m;
  config.min_clearance_m = truth.min_clearance_m;
  config.max_slope_deg = truth.max_slope_deg;
  return config;
}

}  // namespace

TruthPairs pairsOnObservedTruth(const evaluation::GroundTruthTraversability& labels, const datasets::TriangleBvh& truth_bvh,
                                const std::vector<Eigen::Vector3d>& cameras_W, const TruthPairsConfig& config) {
  TruthPairs result;
  const std::vector<Eigen::Vector3d> samples = traversableSamples(labels, config.cell_m);
  result.samples = samples.size();
  const Eigen::Vector3d up = labels.up_W.normalized();
  std::vector<std::uint8_t> seen(samples.size(), 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    seen[i] = observed(samples[i], up, truth_bvh, cameras_W, config) ? 1 : 0;
    result.observed += seen[i];
  }
  const auto links = linkSamples(samples, seen, config.link_radius_m);
  // Connected components of the observed samples; the pairs go on the one under the camera path
  // (most keyframes have their nearest observed sample on it: the ground the platform drove on),
  // the largest if there is no keyframe. The largest alone can be terrain seen far off the path
  // (offroad: a meadow 20-40 m beside the track) that no map reconstructs.
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> component(samples.size(), kNone);
  std::vector<std::vector<std::uint32_t>> components;
  for (std::uint32_t s = 0; s < samples.size(); ++s) {
    if (!seen[s] || component[s] != kNone) continue;
    const auto id = static_cast<std::uint32_t>(components.size());
    std::vector<std::uint32_t> members{s}, stack{s};
    component[s] = id;
    while (!stack.empty()) {
      const std::uint32_t u = stack.back();
      stack.pop_back();
      for (const auto& [v, w] : links[u]) {
        if (component[v] != kNone) continue;
        component[v] = id;
        members.push_back(v);
        stack.push_back(v);
      }
    }
    components.push_back(std::move(members));
  }
  if (components.empty()) return result;
  std::vector<std::size_t> votes(components.size(), 0);
  for (const Eigen::Vector3d& camera : cameras_W) {
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t nearest = kNone;
    for (std::uint32_t i = 0; i < samples.size(); ++i) {
      const double d = seen[i] ? (samples[i] - camera).squaredNorm() : best;
      if (d < best) {
        best = d;
        nearest = i;
      }
    }
    if (nearest != kNone) ++votes[component[nearest]];
  }
  std::size_t chosen = 0;
  for (std::size_t c = 1; c < components.size(); ++c) {
    if (std::make_pair(votes[c], components[c].size()) > std::make_pair(votes[chosen], components[chosen].size())) {
      chosen = c;
    }
  }
  result.component_votes = votes[chosen];
  for (const auto& members : components) {
    result.largest_component_samples = std::max(result.largest_component_samples, members.size());
  }
  const std::vector<std::uint32_t>& largest = components[chosen];
  result.component_samples = largest.size();
  for (std::uint32_t i : largest) {
    result.component_extent_m = std::max(result.component_extent_m, (samples[i] - samples[largest.front()]).norm());
  }
  if (largest.size() < 2) return result;
  std::mt19937_64 random(config.seed);
  std::uniform_int_distribution<std::size_t> pick(0, largest.size() - 1);
  for (std::size_t attempt = 0; attempt < 100 * config.count && result.pairs.size() < config.count; ++attempt) {
    const std::uint32_t a = largest[pick(random)], b = largest[pick(random)];
    if ((samples[a] - samples[b]).norm() < config.min_distance_m) continue;
    result.pairs.push_back({samples[a], samples[b], dijkstra(links, a, b)});
  }
  return result;
}

std::vector<ComparePair> pairsOnPoints(const std::vector<Eigen::Vector3d>& ground_W, std::size_t count,
                                       std::uint64_t seed, double min_distance_m) {
  std::vector<ComparePair> pairs;
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

std::string PlanningOutcome::summary() const {
  std::ostringstream out;
  out.precision(4);
  out << solved << "/" << pairs << " solved";
  if (no_start_or_goal > 0) out << "; " << no_start_or_goal << " with no walkable face within the snap radius of an end";
  if (unreachable > 0) out << "; " << unreachable << " with start and goal on different walkable components";
  const std::size_t other = pairs - solved - no_start_or_goal - unreachable;
  if (other > 0) out << "; " << other << " not found";
  if (truth_checked > 0) out << "; " << truth_valid << "/" << truth_checked << " valid on the truth";
  out << " (walkable: " << walkable_faces << " faces, " << walkable_area_m2 << " m^2 in " << walkable_components
      << " components, the largest " << largest_component_m2 << " m^2)";
  return out.str();
}

PlanningOutcome planComparePairs(const traversability::LayeredMesh& map, const std::vector<ComparePair>& pairs,
                                 const planning::WalkabilityConfig& walkability, double snap_radius_m,
                                 const PathTruth& truth) {
  PlanningOutcome outcome;
  outcome.pairs = pairs.size();
  outcome.mean_length_m = outcome.mean_cost = outcome.mean_length_ratio = kNaN;
  if (map.mesh.faces.empty()) {
    outcome.no_start_or_goal = pairs.size();
    outcome.statuses.assign(pairs.size(), "no_start");
    outcome.truth_reasons.assign(pairs.size(), "");
    return outcome;
  }
  const planning::FaceGraph graph(map, walkability);
  const double area_scale = graph.metresPerUnit() * graph.metresPerUnit();
  outcome.walkable_faces = graph.walkableFaceCount();
  outcome.walkable_components = graph.componentCount();
  for (std::uint32_t c = 0; c < graph.componentCount(); ++c) {
    outcome.walkable_area_m2 += graph.componentArea(c) * area_scale;
    outcome.largest_component_m2 = std::max(outcome.largest_component_m2, graph.componentArea(c) * area_scale);
  }
  planning::PlannerConfig config;
  config.planner = "rrtstar";  // not used by the graph baseline; validated all the same
  config.snap_radius_m = snap_radius_m;
  std::optional<planning::demo::TruthChecker> checker;
  if (truth.mesh && truth.bvh) checker.emplace(*truth.mesh, *truth.bvh);
  double length = 0, cost = 0, ratio = 0;
  std::size_t ratios = 0;
  for (const ComparePair& pair : pairs) {
    const planning::PlanResult result = planning::planOnFaceGraph(graph, pair.start_W, pair.goal_W, config);
    outcome.statuses.push_back(planning::toString(result.status));
    outcome.truth_reasons.emplace_back();
    switch (result.status) {
      case planning::PlanStatus::kSolved: {
        ++outcome.solved;
        length += result.length_m;
        cost += result.cost;
        if (std::isfinite(pair.truth_length_m) && pair.truth_length_m > 0) {
          ratio += result.length_m / pair.truth_length_m;
          ++ratios;
        }
        if (checker) {
          std::vector<Eigen::Vector3d> path;
          for (const planning::PathState& state : result.states) path.push_back(state.location.point_W);
          const planning::demo::TruthCheck check =
              checker->check(path, truth.up_W, graph.metresPerUnit(), truthCheckConfig(truth));
          ++outcome.truth_checked;
          outcome.truth_valid += check.valid ? 1 : 0;
          outcome.truth_reasons.back() = check.reason;
        }
        break;
      }
      case planning::PlanStatus::kNoStart:
      case planning::PlanStatus::kNoGoal: ++outcome.no_start_or_goal; break;
      case planning::PlanStatus::kUnreachable: ++outcome.unreachable; break;
      case planning::PlanStatus::kNotFound: break;
    }
  }
  if (outcome.solved > 0) {
    outcome.mean_length_m = length / static_cast<double>(outcome.solved);
    outcome.mean_cost = cost / static_cast<double>(outcome.solved);
  }
  if (ratios > 0) outcome.mean_length_ratio = ratio / static_cast<double>(ratios);
  return outcome;
}

}  // namespace terramesh::cli

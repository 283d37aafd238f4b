#include "evaluation/truth_pairs.h"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "common/graph_search.h"
#include "evaluation/cell_key.h"

namespace terramesh::evaluation {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// Per sample, its neighbours and their distances.
using Links = std::vector<std::vector<std::pair<std::uint32_t, double>>>;

using CellHash = CellKeyHash;
CellKey keyOf(const Eigen::Vector3d& p, double cell) { return geometry::cellOf(p, cell); }

/// Area-weighted centroids of the traversable truth faces, one per cell.
std::vector<Eigen::Vector3d> traversableSamples(const GroundTruthTraversability& labels, double cell) {
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
Links linkSamples(const std::vector<Eigen::Vector3d>& samples, const std::vector<std::uint8_t>& active,
                  double radius) {
  std::unordered_map<CellKey, std::vector<std::uint32_t>, CellHash> grid;
  for (std::uint32_t i = 0; i < samples.size(); ++i) {
    if (active[i]) grid[keyOf(samples[i], radius)].push_back(i);
  }
  Links links(samples.size());
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

/// The shortest length over `links` from `from` to `to` (NaN if they are not joined).
double shortestLength(const Links& links, std::uint32_t from, std::uint32_t to) {
  const graph::SearchResult search = graph::bestFirstSearch(
      links.size(), from, to,
      [&links](std::uint32_t u, const graph::Relax& relax) {
        for (const auto& [v, w] : links[u]) relax(v, w, 0);
      },
      [](std::uint32_t) { return 0.0; });
  return search.reached ? search.cost[to] : kNaN;
}

/// Connected components of the `active` samples over `links`: each sample's component (kNone if
/// inactive) and each component's members, in the order a depth-first walk reaches them.
struct Components {
  std::vector<std::uint32_t> of;
  std::vector<std::vector<std::uint32_t>> members;
};

Components connectedComponents(const Links& links, const std::vector<std::uint8_t>& active) {
  Components result;
  result.of.assign(links.size(), kNone);
  for (std::uint32_t s = 0; s < links.size(); ++s) {
    if (!active[s] || result.of[s] != kNone) continue;
    const auto id = static_cast<std::uint32_t>(result.members.size());
    std::vector<std::uint32_t> members{s}, stack{s};
    result.of[s] = id;
    while (!stack.empty()) {
      const std::uint32_t u = stack.back();
      stack.pop_back();
      for (const auto& [v, w] : links[u]) {
        if (result.of[v] != kNone) continue;
        result.of[v] = id;
        members.push_back(v);
        stack.push_back(v);
      }
    }
    result.members.push_back(std::move(members));
  }
  return result;
}

/// Per component, the keyframes whose nearest `seen` sample lies on it.
std::vector<std::size_t> cameraVotes(const std::vector<Eigen::Vector3d>& samples, const std::vector<std::uint8_t>& seen,
                                     const Components& components, const std::vector<Eigen::Vector3d>& cameras_W) {
  std::vector<std::size_t> votes(components.members.size(), 0);
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
    if (nearest != kNone) ++votes[components.of[nearest]];
  }
  return votes;
}

}  // namespace

TruthPairs pairsOnObservedTruth(const GroundTruthTraversability& labels, const datasets::TriangleBvh& truth_bvh,
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
  const Links links = linkSamples(samples, seen, config.link_radius_m);
  // Connected components of the observed samples; the pairs go on the one under the camera path
  // (most keyframes have their nearest observed sample on it: the ground the platform drove on),
  // the largest if there is no keyframe. The largest alone can be terrain seen far off the path
  // (offroad: a meadow 20-40 m beside the track) that no map reconstructs.
  const Components components = connectedComponents(links, seen);
  if (components.members.empty()) return result;
  const std::vector<std::size_t> votes = cameraVotes(samples, seen, components, cameras_W);
  std::size_t chosen = 0;
  for (std::size_t c = 1; c < components.members.size(); ++c) {
    if (std::make_pair(votes[c], components.members[c].size()) >
        std::make_pair(votes[chosen], components.members[chosen].size())) {
      chosen = c;
    }
  }
  result.component_votes = votes[chosen];
  for (const auto& members : components.members) {
    result.largest_component_samples = std::max(result.largest_component_samples, members.size());
  }
  const std::vector<std::uint32_t>& largest = components.members[chosen];
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
    result.pairs.push_back({samples[a], samples[b], shortestLength(links, a, b)});
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

}  // namespace terramesh::evaluation

// Walkable levels of a layered mesh: region growing with a plan-overlap test (see map_levels.h).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "common/plan_frame.h"
#include "plan_geometry.h"
#include "traversability/layer_registry.h"
#include "traversability/map_levels.h"

namespace terramesh::traversability {
namespace {

using internal::CellKey;
using internal::FacePlan;
using internal::HeightRange;

/// Per level: the height interval of its walkable surface in each overlap cell.
using CellHeights = std::unordered_map<CellKey, HeightRange, internal::CellKeyHash>;

bool fits(const CellHeights& cells, const std::vector<std::pair<CellKey, HeightRange>>& footprint,
          double separation_m) {
  for (const auto& [key, range] : footprint) {
    const auto it = cells.find(key);
    if (it == cells.end()) continue;
    if (std::max(it->second.hi, range.hi) - std::min(it->second.lo, range.lo) > separation_m) return false;
  }
  return true;
}

void addFootprint(CellHeights& cells, const std::vector<std::pair<CellKey, HeightRange>>& footprint) {
  for (const auto& [key, range] : footprint) {
    const auto [it, inserted] = cells.emplace(key, range);
    if (!inserted) it->second = it->second.merged(range);
  }
}

/// Faces sharing an edge, per face (non-manifold edges link every pair).
std::vector<std::vector<std::uint32_t>> faceNeighbours(const mesher::TriangleMesh& mesh) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
  edges.reserve(mesh.faces.size() * 3);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = mesh.faces[f][static_cast<std::size_t>(k)];
      const std::uint64_t b = mesh.faces[f][static_cast<std::size_t>((k + 1) % 3)];
      edges.emplace_back(std::min(a, b) << 32 | std::max(a, b), static_cast<std::uint32_t>(f));
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<std::uint32_t>> neighbours(mesh.faces.size());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    for (std::size_t p = i; p < j; ++p) {
      for (std::size_t q = i; q < j; ++q) {
        if (p != q) neighbours[edges[p].second].push_back(edges[q].second);
      }
    }
    i = j;
  }
  return neighbours;
}

struct Grower {
  const std::vector<FacePlan>& plans;
  const std::vector<std::vector<std::pair<CellKey, HeightRange>>>& footprints;
  const std::vector<std::vector<std::uint32_t>>& neighbours;
  const std::vector<std::uint8_t>& walkable;
  const LevelConfig& config;
  std::vector<std::int32_t>& level_of;
  std::vector<CellHeights>& cells;
  /// Per face: the last level that tested it (levels grow one after the other).
  std::vector<std::int32_t> tried = std::vector<std::int32_t>(plans.size(), Levels::kNone);

  /// Grows level `level` from `seed`, best-first by height difference to the seed.
  void grow(std::uint32_t seed, std::int32_t level) {
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    const double seed_height = plans[seed].centroid_height_m;
    queue.emplace(0.0, seed);
    CellHeights& level_cells = cells[static_cast<std::size_t>(level)];
    while (!queue.empty()) {
      const std::uint32_t f = queue.top().second;
      queue.pop();
      if (level_of[f] != Levels::kNone || tried[f] == level) continue;
      tried[f] = level;
      if (!fits(level_cells, footprints[f], config.level_separation_m)) continue;
      level_of[f] = level;
      addFootprint(level_cells, footprints[f]);
      for (std::uint32_t g : neighbours[f]) {
        // A level climbs at most level_separation_m from its seed: what lies higher seeds a
        // level of its own, which the merge pass joins to the level it fits (a ramp's upper half
        // to the deck it leads to). Otherwise which floor gets a ramp, and the deck beyond it over
        // other floors, would depend on which part of the floor below happened to reach it first.
        const double rise = std::abs(plans[g].centroid_height_m - seed_height);
        if (walkable[g] && level_of[g] == Levels::kNone && tried[g] != level && rise <= config.level_separation_m) {
          queue.emplace(rise, g);
        }
      }
    }
  }
};

}  // namespace

void LevelConfig::validate() const {
  std::string problems;
  const auto require = [&](bool ok, const std::string& what) {
    if (!ok) problems += (problems.empty() ? "" : "; ") + what;
  };
  require(level_separation_m > 0, "level_separation_m must be > 0");
  require(overlap_cell_m > 0, "overlap_cell_m must be > 0");
  require(min_level_area_m2 >= 0, "min_level_area_m2 must be >= 0");
  require(min_level_fraction >= 0 && min_level_fraction <= 1, "min_level_fraction must be in [0, 1]");
  require(attach_radius_m >= 0, "attach_radius_m must be >= 0");
  require(max_downward_deg >= 0 && max_downward_deg <= 90, "max_downward_deg must be in [0, 90]");
  if (!problems.empty()) throw std::invalid_argument("LevelConfig: " + problems);
}

MapPlane MapPlane::fromUp(const Eigen::Vector3d& up_W, double metres_per_unit) {
  if (!up_W.allFinite() || up_W.norm() < 1e-12) throw std::invalid_argument("MapPlane: up vector must be finite and non-zero");
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit)) {
    throw std::invalid_argument("MapPlane: metres_per_unit must be > 0");
  }
  MapPlane plane;
  plane.metres_per_unit = metres_per_unit;
  const geometry::PlanFrame frame = geometry::planFrame(up_W.normalized(), geometry::exportFrameRule());
  plane.x_W = frame.e1;
  plane.y_W = frame.e2;
  plane.z_W = frame.up;
  return plane;
}

Levels segmentLevels(const LayeredMesh& map, const MapPlane& plane, const LevelConfig& config) {
  config.validate();
  const mesher::TriangleMesh& mesh = map.mesh;
  if (map.layers.size() != mesh.faces.size()) throw std::invalid_argument("segmentLevels: one FaceLayers per face needed");
  const std::size_t face_count = mesh.faces.size();
  std::vector<FacePlan> plans(face_count);
  std::vector<std::uint8_t> walkable(face_count, 0);
  std::vector<std::vector<std::pair<CellKey, HeightRange>>> footprints(face_count);
  for (std::size_t f = 0; f < face_count; ++f) {
    plans[f] = internal::planFace(mesh, f, plane);
    // Levels are the surfaces a robot may stand on: free, or uncertain but no guessed wall (a
    // face too steep to stand on that nobody measured: a curtain the mesh keeps between floors).
    const FaceClass c = map.layers[f].face_class;
    const bool guessed_wall = (map.layers[f].reasons & reason::kGuessedWall) != 0;
    walkable[f] = (c == FaceClass::kFree || (c == FaceClass::kUncertain && !guessed_wall)) && plans[f].up_cosine > 0.05;
    if (walkable[f]) footprints[f] = internal::cellHeightRanges(plans[f], config.overlap_cell_m);
  }
  const auto neighbours = faceNeighbours(mesh);

  std::vector<std::int32_t> level_of(face_count, Levels::kNone);
  std::vector<CellHeights> cells;
  std::vector<std::uint32_t> order;
  for (std::uint32_t f = 0; f < face_count; ++f) {
    if (walkable[f]) order.push_back(f);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return plans[a].centroid_height_m < plans[b].centroid_height_m;
  });
  Grower grower{plans, footprints, neighbours, walkable, config, level_of, cells};
  for (std::uint32_t seed : order) {
    if (level_of[seed] != Levels::kNone) continue;
    cells.emplace_back();
    grower.grow(seed, static_cast<std::int32_t>(cells.size() - 1));
  }

  // Merge levels wherever they fit: largest first, each into the first kept level (most shared
  // edges, then largest) that takes all its faces without an overlap conflict. Regions cut
  // apart by lethal faces (a sidewalk behind a curb) thus share one map; only stacked surfaces
  // stay apart. What cannot merge is kept if large enough, else dropped.
  std::vector<double> area(cells.size(), 0.0);
  std::vector<std::vector<std::uint32_t>> members(cells.size());
  for (std::uint32_t f = 0; f < face_count; ++f) {
    if (level_of[f] == Levels::kNone) continue;
    area[static_cast<std::size_t>(level_of[f])] += plans[f].plan_area_m2;
    members[static_cast<std::size_t>(level_of[f])].push_back(f);
  }
  std::vector<std::size_t> by_area(cells.size());
  std::iota(by_area.begin(), by_area.end(), 0);
  std::stable_sort(by_area.begin(), by_area.end(), [&](std::size_t a, std::size_t b) { return area[a] > area[b]; });
  std::vector<std::size_t> kept;
  for (std::size_t level : by_area) {
    std::map<std::size_t, std::size_t> shared_edges;
    for (std::uint32_t f : members[level]) {
      for (std::uint32_t g : neighbours[f]) {
        if (level_of[g] != Levels::kNone && level_of[g] != static_cast<std::int32_t>(level)) {
          ++shared_edges[static_cast<std::size_t>(level_of[g])];
        }
      }
    }
    std::vector<std::size_t> candidates = kept;
    std::stable_sort(candidates.begin(), candidates.end(),
                     [&](std::size_t a, std::size_t b) { return shared_edges[a] > shared_edges[b]; });
    bool merged = false;
    for (std::size_t target : candidates) {
      const bool ok = std::all_of(members[level].begin(), members[level].end(), [&](std::uint32_t f) {
        return fits(cells[target], footprints[f], config.level_separation_m);
      });
      if (!ok) continue;
      for (std::uint32_t f : members[level]) {
        level_of[f] = static_cast<std::int32_t>(target);
        addFootprint(cells[target], footprints[f]);
        members[target].push_back(f);
      }
      area[target] += area[level];
      merged = true;
      break;
    }
    if (merged || area[level] < config.min_level_area_m2) {
      if (!merged) {
        for (std::uint32_t f : members[level]) level_of[f] = Levels::kNone;
      }
      members[level].clear();
      cells[level].clear();
      area[level] = 0;
    } else {
      kept.push_back(level);
    }
  }

  double largest = 0;
  for (std::size_t level : kept) largest = std::max(largest, area[level]);
  for (std::size_t level : kept) {
    if (area[level] >= config.min_level_fraction * largest) continue;
    for (std::uint32_t f : members[level]) level_of[f] = Levels::kNone;
    members[level].clear();
    cells[level].clear();
    area[level] = 0;
  }

  // Renumber the surviving levels by mean height.
  std::vector<double> height_sum(cells.size(), 0.0);
  for (std::size_t f = 0; f < face_count; ++f) {
    if (level_of[f] != Levels::kNone) {
      height_sum[static_cast<std::size_t>(level_of[f])] += plans[f].centroid_height_m * plans[f].plan_area_m2;
    }
  }
  std::vector<std::size_t> alive;
  for (std::size_t l = 0; l < cells.size(); ++l) {
    if (!members[l].empty()) alive.push_back(l);
  }
  const auto mean = [&](std::size_t l) { return area[l] > 0 ? height_sum[l] / area[l] : 0.0; };
  std::stable_sort(alive.begin(), alive.end(), [&](std::size_t a, std::size_t b) { return mean(a) < mean(b); });
  std::vector<std::int32_t> renumber(cells.size(), Levels::kNone);
  Levels levels;
  std::vector<CellHeights> final_cells;
  for (std::size_t i = 0; i < alive.size(); ++i) {
    renumber[alive[i]] = static_cast<std::int32_t>(i);
    levels.mean_height_m.push_back(mean(alive[i]));
    levels.walkable_area_m2.push_back(area[alive[i]]);
    final_cells.push_back(std::move(cells[alive[i]]));
  }
  levels.face_level.assign(face_count, Levels::kNone);
  levels.walkable.assign(face_count, 0);
  for (std::size_t f = 0; f < face_count; ++f) {
    if (level_of[f] == Levels::kNone) continue;
    levels.face_level[f] = renumber[static_cast<std::size_t>(level_of[f])];
    levels.walkable[f] = 1;
  }

  // Attach the other faces to the nearest level in height, near in plan.
  const double min_up_cosine = -std::sin(config.max_downward_deg * M_PI / 180.0);
  const double cell = config.overlap_cell_m;
  const auto reach = static_cast<std::int64_t>(std::ceil(config.attach_radius_m / cell));
  for (std::size_t f = 0; f < face_count; ++f) {
    if (levels.walkable[f] || final_cells.empty()) continue;
    const FacePlan& p = plans[f];
    if (!p.valid || p.up_cosine < min_up_cosine) continue;
    const CellKey lo = geometry::cellOf(p.min_m, cell), hi = geometry::cellOf(p.max_m, cell);
    const std::int64_t span = (hi.i - lo.i + 1 + 2 * reach) * (hi.j - lo.j + 1 + 2 * reach);
    if (span > 4'000'000) continue;  // a closing face of the whole map: no level owns it
    double best_distance = std::numeric_limits<double>::infinity(), best_foot = best_distance;
    std::int32_t best = Levels::kNone;
    for (std::size_t l = 0; l < final_cells.size(); ++l) {
      for (std::int64_t i = lo.i - reach; i <= hi.i + reach; ++i) {
        for (std::int64_t j = lo.j - reach; j <= hi.j + reach; ++j) {
          const auto it = final_cells[l].find({i, j});
          if (it == final_cells[l].end()) continue;
          const HeightRange& range = it->second;
          const double distance = std::max({0.0, range.lo - p.max_height_m, p.min_height_m - range.hi});
          const double foot = std::abs(p.min_height_m - range.lo);
          if (distance < best_distance || (distance == best_distance && foot < best_foot)) {
            best_distance = distance;
            best_foot = foot;
            best = static_cast<std::int32_t>(l);
          }
        }
      }
    }
    if (best != Levels::kNone && best_distance <= config.level_separation_m) levels.face_level[f] = best;
  }
  return levels;
}

}  // namespace terramesh::traversability

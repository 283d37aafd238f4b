// A level rasterised on a regular plan grid (see map_levels.h for the choice of face per cell).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "plan_geometry.h"
#include "traversability/map_levels.h"

namespace terramesh::traversability {
namespace {

// A cell shows its most restrictive face: lethal, then uncertain (never shown as free), then free.
constexpr int kRankNone = 0, kRankOther = 1, kRankWalkable = 2, kRankUncertain = 3, kRankLethal = 4;

}  // namespace

LevelGrid rasterizeLevel(const LayeredMesh& map, const MapPlane& plane, const Levels& levels,
                         std::size_t level, double resolution_m) {
  if (level >= levels.count()) throw std::invalid_argument("rasterizeLevel: level out of range");
  if (!(resolution_m > 0) || !std::isfinite(resolution_m)) {
    throw std::invalid_argument("rasterizeLevel: resolution must be > 0");
  }
  const std::int32_t id = static_cast<std::int32_t>(level);
  const std::size_t face_count = map.mesh.faces.size();
  std::vector<internal::FacePlan> plans(face_count);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (std::size_t f = 0; f < face_count; ++f) {
    if (levels.face_level[f] != id) continue;
    plans[f] = internal::planFace(map.mesh, f, plane);
    if (levels.walkable[f] && plans[f].valid) {
      lo = lo.cwiseMin(plans[f].min_m);
      hi = hi.cwiseMax(plans[f].max_m);
    }
  }
  LevelGrid grid;
  grid.resolution_m = resolution_m;
  if (!(lo.x() <= hi.x())) return grid;
  // The walkable surface's box padded by two cells (attached walls at its rim stay in).
  const double r = resolution_m;
  grid.origin_x_m = (std::floor(lo.x() / r) - 2) * r;
  grid.origin_y_m = (std::floor(lo.y() / r) - 2) * r;
  grid.width = static_cast<std::size_t>(std::ceil((hi.x() - grid.origin_x_m) / r)) + 2;
  grid.height = static_cast<std::size_t>(std::ceil((hi.y() - grid.origin_y_m) / r)) + 2;
  if (grid.width * grid.height > 400'000'000) {
    throw std::invalid_argument("rasterizeLevel: grid of " + std::to_string(grid.width) + " x " +
                                std::to_string(grid.height) + " cells is too large; raise the resolution");
  }
  const std::size_t cells = grid.width * grid.height;
  grid.face.assign(cells, -1);
  grid.cell_class.assign(cells, FaceClass::kUnknown);
  std::vector<std::uint8_t> rank(cells, kRankNone);
  std::vector<double> top(cells, -std::numeric_limits<double>::infinity());

  const auto colOf = [&](double x) { return static_cast<std::int64_t>(std::floor((x - grid.origin_x_m) / r)); };
  const auto rowOf = [&](double y) { return static_cast<std::int64_t>(std::floor((y - grid.origin_y_m) / r)); };
  const auto inside = [&](std::int64_t c, std::int64_t w) {
    return c >= 0 && w >= 0 && c < static_cast<std::int64_t>(grid.width) && w < static_cast<std::int64_t>(grid.height);
  };
  const auto offer = [&](std::int64_t c, std::int64_t w, std::size_t f, int face_rank, double height) {
    const std::size_t i = grid.index(static_cast<std::size_t>(c), static_cast<std::size_t>(w));
    if (face_rank < rank[i] || (face_rank == rank[i] && height <= top[i])) return;
    rank[i] = static_cast<std::uint8_t>(face_rank);
    top[i] = height;
    grid.face[i] = static_cast<std::int64_t>(f);
  };

  for (std::size_t f = 0; f < face_count; ++f) {
    if (levels.face_level[f] != id || !plans[f].valid) continue;
    const internal::FacePlan& p = plans[f];
    const bool lethal = map.layers[f].face_class == FaceClass::kLethal;
    const bool uncertain = map.layers[f].face_class == FaceClass::kUncertain;
    const int face_rank = lethal      ? kRankLethal
                          : uncertain ? kRankUncertain
                          : levels.walkable[f] ? kRankWalkable
                                               : kRankOther;
    const std::int64_t c0 = std::max<std::int64_t>(0, colOf(p.min_m.x()));
    const std::int64_t c1 = std::min<std::int64_t>(static_cast<std::int64_t>(grid.width) - 1, colOf(p.max_m.x()));
    const std::int64_t w0 = std::max<std::int64_t>(0, rowOf(p.min_m.y()));
    const std::int64_t w1 = std::min<std::int64_t>(static_cast<std::int64_t>(grid.height) - 1, rowOf(p.max_m.y()));
    for (std::int64_t w = w0; w <= w1; ++w) {
      for (std::int64_t c = c0; c <= c1; ++c) {
        const Eigen::Vector2d centre(grid.origin_x_m + (static_cast<double>(c) + 0.5) * r,
                                     grid.origin_y_m + (static_cast<double>(w) + 0.5) * r);
        if (p.plan_area_m2 > 0 && internal::triangleContains(p.corners_m, centre)) {
          offer(c, w, f, face_rank, internal::heightAt(p, centre));
        }
      }
    }
    if (!lethal) continue;
    // Walls have (almost) no plan area: mark every cell an edge passes through.
    for (std::size_t k = 0; k < 3; ++k) {
      const Eigen::Vector2d a = p.corners_m[k], b = p.corners_m[(k + 1) % 3];
      const auto steps = static_cast<std::int64_t>(std::ceil((b - a).norm() / (0.25 * r))) + 1;
      if (steps > 10'000'000) continue;
      for (std::int64_t s = 0; s <= steps; ++s) {
        const Eigen::Vector2d q = a + (b - a) * (static_cast<double>(s) / static_cast<double>(steps));
        const std::int64_t c = colOf(q.x()), w = rowOf(q.y());
        if (inside(c, w)) offer(c, w, f, face_rank, p.max_height_m);
      }
    }
  }
  for (std::size_t i = 0; i < cells; ++i) {
    if (grid.face[i] >= 0) grid.cell_class[i] = map.layers[static_cast<std::size_t>(grid.face[i])].face_class;
  }
  return grid;
}

}  // namespace terramesh::traversability

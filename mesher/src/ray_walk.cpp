#include "ray_walk.h"

#include <array>

namespace terramesh::mesher::internal {
namespace {

/// Orientation signs of (q, p, a, b) computed on demand and memoised per walk step.
class LazySigns {
 public:
  void reset() { known_.fill(false); }
  template <class Compute>
  CGAL::Orientation get(int index, Compute compute) {
    if (!known_[static_cast<std::size_t>(index)]) {
      value_[static_cast<std::size_t>(index)] = compute();
      known_[static_cast<std::size_t>(index)] = true;
    }
    return value_[static_cast<std::size_t>(index)];
  }

 private:
  std::array<bool, 6> known_{};
  std::array<CGAL::Orientation, 6> value_{};
};

/// Index 0..5 of the edge (a, b) of a tetrahedron, a != b local vertex indices.
int edgeIndex(int a, int b) {
  static constexpr int kTable[4][4] = {{-1, 0, 1, 2}, {0, -1, 3, 4}, {1, 3, -1, 5}, {2, 4, 5, -1}};
  return kTable[a][b];
}

}  // namespace

std::uint8_t RayWalker::walk(const CameraLocation& camera, VertexHandle target,
                             std::vector<CellHandle>& path, WalkCounters& counters) const {
  path.clear();
  if (camera.type == Delaunay::CELL && walkStraight(camera, target, path, counters)) {
    return kWalkedStraight;
  }
  ++counters.fallbacks;
  // Generic directions (no two alike, none along an axis or a diagonal).
  static constexpr double kDirections[4][3] = {
      {0.5773503, 0.4082483, 0.7071068}, {-0.3015113, 0.9045340, 0.3015113},
      {0.8017837, -0.2672612, 0.5345225}, {0.2182179, 0.4364358, -0.8728716}};
  const Eigen::Vector3d q = toEigen(camera.position);
  const double scale = 1e-7 * (1.0 + q.cwiseAbs().maxCoeff() + (toEigen(target->point()) - q).norm());
  for (int attempt = 0; attempt < 8; ++attempt) {
    const double* u = kDirections[attempt % 4];
    const double amount = scale * (1 + attempt / 4);
    CameraLocation displaced;
    displaced.position = toPoint(q + amount * Eigen::Vector3d(u[0], u[1], u[2]));
    displaced.cell = tri_.locate(displaced.position, displaced.type, displaced.li, displaced.lj,
                                 camera.cell);
    path.clear();
    if (displaced.type == Delaunay::CELL && walkStraight(displaced, target, path, counters)) {
      return static_cast<std::uint8_t>(1 + attempt);
    }
  }
  path.clear();
  ++counters.failures;
  return 255;
}

bool RayWalker::resume(const Point& camera_W, VertexHandle target, std::vector<CellHandle>& path,
                       WalkCounters& counters) const {
  const std::size_t prefix = path.size();
  const CellHandle cell = path.back();
  const int entry = prefix >= 2 ? cell->index(path[prefix - 2]) : -1;
  if (walkFrom(cell, entry, camera_W, target, path, counters)) return true;
  path.resize(prefix);
  return false;
}

bool RayWalker::bridge(const Point& camera_W, VertexHandle target, const std::vector<CellHandle>& path,
                       std::size_t gap, std::vector<CellHandle>& between, WalkCounters& counters) const {
  between.clear();
  const CellHandle& cell = path[gap - 1];
  const CellHandle& tail = path[gap];
  const int entry = gap >= 2 ? cell->index(path[gap - 2]) : -1;
  if (!walkFrom(cell, entry, camera_W, target, between, counters, tail) || between.empty() ||
      between.back() != tail) {
    return false;
  }
  between.pop_back();
  return true;
}

bool RayWalker::walkStraight(const CameraLocation& camera, VertexHandle target,
                             std::vector<CellHandle>& path, WalkCounters& counters) const {
  const CellHandle cell = camera.cell;
  if (tri_.is_infinite(cell)) return false;
  path.push_back(cell);
  if (cell->has_vertex(target)) return true;
  return walkFrom(cell, -1, camera.position, target, path, counters);
}

int RayWalker::exitFromInside(const CellHandle& cell, const Point& q, const Point& p) const {
  // The camera is inside: the segment leaves through the facet whose three edges (wound
  // outwards) all see the line q->p on their positive side.
  const auto orientation = tri_.geom_traits().orientation_3_object();
  LazySigns edge_signs;
  edge_signs.reset();
  auto side = [&](int a, int b) {
    const CGAL::Orientation s = edge_signs.get(edgeIndex(a, b), [&] {
      return orientation(q, p, cell->vertex(a < b ? a : b)->point(), cell->vertex(a < b ? b : a)->point());
    });
    return a < b ? s : -s;
  };
  for (int j = 0; j < 4; ++j) {
    const int a = outwardFacetVertex(j, 0);
    const int b = outwardFacetVertex(j, 1);
    const int c = outwardFacetVertex(j, 2);
    if (side(a, b) == CGAL::POSITIVE && side(b, c) == CGAL::POSITIVE && side(c, a) == CGAL::POSITIVE) {
      return j;
    }
  }
  return -1;
}

int RayWalker::exitAfterEntry(const CellHandle& cell, int entry, const Point& q, const Point& p,
                              WalkCounters& counters) const {
  // Candidate facet j != entry, wound outwards and rotated to (apex, a, b): the segment leaves
  // through it iff orient(q,p,apex,a) > 0 and orient(q,p,apex,b) < 0.
  const auto orientation = tri_.geom_traits().orientation_3_object();
  const Point& apex = cell->vertex(entry)->point();
  std::array<CGAL::Orientation, 4> t{};
  std::array<bool, 4> known{};
  auto sign_to = [&](int local) {
    if (!known[static_cast<std::size_t>(local)]) {
      t[static_cast<std::size_t>(local)] = orientation(q, p, apex, cell->vertex(local)->point());
      known[static_cast<std::size_t>(local)] = true;
    }
    return t[static_cast<std::size_t>(local)];
  };
  auto leaves_through = [&](int j) {
    int a = -1;
    int b = -1;
    for (int k = 0; k < 3; ++k) {
      if (outwardFacetVertex(j, k) == entry) {
        a = outwardFacetVertex(j, (k + 1) % 3);
        b = outwardFacetVertex(j, (k + 2) % 3);
      }
    }
    return sign_to(a) == CGAL::POSITIVE && sign_to(b) == CGAL::NEGATIVE;
  };
  int tested = -1;
  if (use_cache_) {
    const int cached = cell->info().next_facet;
    if (cached < 4 && cached != entry) {
      ++counters.cache_lookups;
      tested = cached;
      if (leaves_through(cached)) {
        ++counters.cache_hits;
        return cached;
      }
    }
  }
  for (int j = 0; j < 4; ++j) {
    if (j != entry && j != tested && leaves_through(j)) return j;
  }
  return -1;
}

bool RayWalker::walkFrom(CellHandle cell, int entry, const Point& q, VertexHandle target,
                         std::vector<CellHandle>& path, WalkCounters& counters, const CellHandle& stop) const {
  const Point& p = target->point();
  int exit = entry < 0 ? exitFromInside(cell, q, p) : exitAfterEntry(cell, entry, q, p, counters);
  // The segment crosses each facet at most once, so no cell is entered twice: a longer walk
  // would mean a corrupt triangulation, and must end rather than loop.
  const std::size_t max_steps = tri_.tds().number_of_cells() + 1;
  std::size_t steps = 0;
  while (exit >= 0) {
    if (use_cache_) cell->info().next_facet = static_cast<std::uint8_t>(exit);
    const CellHandle next = cell->neighbor(exit);
    entry = next->index(cell);
    cell = next;
    path.push_back(cell);
    ++counters.steps;
    if (cell == stop) return true;
    if (++steps > max_steps) {
      ++counters.step_limit_hits;
      return false;
    }
    if (tri_.is_infinite(cell)) return false;
    if (cell->vertex(entry) == target) return true;
    exit = exitAfterEntry(cell, entry, q, p, counters);
  }
  return false;
}

}  // namespace terramesh::mesher::internal

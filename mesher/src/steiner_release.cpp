// Mesher::releaseFarSteiner: the Steiner lattice let go far from the data still in use.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "mesher_impl.h"

namespace terramesh::mesher {
namespace {

using internal::CellHandle;
using internal::VertexHandle;

/// Whether all of `vertices` lie in one plane (fewer than four do).
bool allCoplanar(const std::vector<VertexHandle>& vertices) {
  std::size_t a = 0, b = 1, c = 2;
  // Three that span a plane: the first two and the first one off their line.
  while (c < vertices.size() &&
         CGAL::collinear(vertices[a]->point(), vertices[b]->point(), vertices[c]->point())) {
    ++c;
  }
  if (c >= vertices.size()) return true;
  for (const VertexHandle& w : vertices) {
    if (!CGAL::coplanar(vertices[a]->point(), vertices[b]->point(), vertices[c]->point(), w->point())) {
      return false;
    }
  }
  return true;
}

/// Whether removing Steiner vertex `v` leaves the surface, every ray and every point's star as they
/// are: no cell around it (or beside one) is in O, no ray crosses one, and no point spans one.
bool releasable(const internal::Delaunay& tri, VertexHandle v, std::vector<CellHandle>& scratch) {
  scratch.clear();
  tri.incident_cells(v, std::back_inserter(scratch));
  for (const CellHandle& cell : scratch) {
    if (cell->info().outside() || cell->info().crossings > 0) return false;
    for (int i = 0; i < 4; ++i) {
      const VertexHandle w = cell->vertex(i);
      if (!tri.is_infinite(w) && !w->info().steiner) return false;
      if (cell->neighbor(i)->info().outside()) return false;
    }
  }
  // On the hull, CGAL fills the hole of a vertex whose finite neighbours are coplanar (a node on a
  // flat face of the lattice's hull) with the help of a fake vertex and hands back cells that are
  // not all valid; such a vertex stays.
  bool on_hull = false;
  for (const CellHandle& cell : scratch) on_hull = on_hull || tri.is_infinite(cell);
  if (!on_hull) return true;
  std::vector<VertexHandle> around;
  tri.finite_adjacent_vertices(v, std::back_inserter(around));
  return !allCoplanar(around);
}

}  // namespace

UpdateStats Mesher::Impl::releaseFarSteiner(const std::vector<Eigen::Vector3d>& keep_W,
                                            double reach_m) {
  if (!(std::isfinite(reach_m) && reach_m >= 0)) {
    throw std::invalid_argument("releaseFarSteiner: reach " + std::to_string(reach_m) +
                                " m (expected >= 0)");
  }
  UpdateStats stats;
  if (state_.grid.empty() || !state_.config.incremental_steiner_grid) return stats;
  const auto start = std::chrono::steady_clock::now();
  state_.grid.makeSparse();
  // Data within reach of a kept camera needs the lattice the grid's margin beyond it; two more
  // cells keep every cell around a released vertex away from anything in use.
  const int radius =
      static_cast<int>(std::ceil(reach_m / state_.config.metres_per_unit / state_.grid.step())) +
      state_.config.steiner_margin_cells + 2;
  const auto kept = shrinker_.enclosingKeys(keep_W, radius);
  std::vector<std::pair<std::uint64_t, VertexHandle>> far;
  for (const auto& [key, v] : state_.steiner_nodes) {
    if (kept.count(state_.grid.nodeOf(internal::toEigen(v->point()))) == 0)
      far.emplace_back(key, v);
  }
  // One order whatever the hash map's: the triangulation's cell stamps follow it.
  std::sort(far.begin(), far.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<CellHandle> scratch;
  retrace_.clear();
  for (const auto& [key, v] : far) {
    if (!releasable(state_.tri, v, scratch)) continue;
    const internal::GridKey node = state_.grid.nodeOf(internal::toEigen(v->point()));
    editor_.remove(v, retrace_);
    state_.grid.release(node);
    state_.steiner_nodes.erase(key);
    --state_.steiner_vertices;
    ++stats.steiner_released;
  }
  // No ray crossed a removed cell, so none is walked again.
  stats.time.total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace terramesh::mesher

#include "triangulation_editor.h"

#include <algorithm>
#include <array>
#include <utility>
#include <cassert>
#include <iterator>

namespace terramesh::mesher::internal {

void TriangulationEditor::bootstrap(const std::vector<Eigen::Vector3d>& steiner_points) {
  assert(state_.tri.number_of_vertices() == 0);
  for (const Eigen::Vector3d& p : steiner_points) {
    const VertexHandle v = state_.tri.insert(toPoint(p));
    v->info().steiner = true;
  }
  state_.steiner_vertices += state_.tri.number_of_vertices();
  for (auto cell = state_.tri.all_cells_begin(); cell != state_.tri.all_cells_end(); ++cell) {
    state_.stampNewCell(cell);
    for (int i = 0; i < 4; ++i) ++cell->vertex(i)->info().degree;
  }
  hint_ = state_.tri.infinite_cell();
}

bool TriangulationEditor::conflictsWithOutside(const Eigen::Vector3d& position) {
  Delaunay::Locate_type type;
  int li = 0;
  int lj = 0;
  const Point p = toPoint(position);
  const CellHandle located = state_.tri.locate(p, type, li, lj, hint_);
  if (type == Delaunay::VERTEX) return true;
  conflict_cells_.clear();
  state_.tri.find_conflicts(p, located, CGAL::Emptyset_iterator(),
                            std::back_inserter(conflict_cells_));
  for (const CellHandle& cell : conflict_cells_) {
    if (cell->info().outside()) return true;
  }
  return false;
}

TriangulationEditor::InsertResult TriangulationEditor::insert(const Eigen::Vector3d& position,
                                                              std::uint32_t point_index,
                                                              std::vector<RayId>& retrace,
                                                              VertexHandle& vertex) {
  Delaunay::Locate_type type;
  int li = 0;
  int lj = 0;
  const Point p = toPoint(position);
  const CellHandle located = state_.tri.locate(p, type, li, lj, hint_);
  if (type == Delaunay::VERTEX) return InsertResult::kDuplicate;
  if (point_index != kNone && type == Delaunay::OUTSIDE_CONVEX_HULL) {
    return InsertResult::kOutsideHull;
  }
  conflict_cells_.clear();
  boundary_facets_.clear();
  state_.tri.find_conflicts(p, located, std::back_inserter(boundary_facets_),
                            std::back_inserter(conflict_cells_));
  for (const CellHandle& cell : conflict_cells_) {
    if (cell->info().outside()) return InsertResult::kConflictsWithOutside;
  }
  untraceCrossing(conflict_cells_, retrace);
  forgetCells(conflict_cells_);
  const Facet& facet = boundary_facets_.front();
  vertex = state_.tri.insert_in_hole(p, conflict_cells_.begin(), conflict_cells_.end(),
                                     facet.first, facet.second);
  vertex->info().point = point_index;
  vertex->info().steiner = point_index == kNone;
  new_cells_.clear();
  state_.tri.incident_cells(vertex, std::back_inserter(new_cells_));
  registerNewCells(new_cells_);
  hint_ = new_cells_.front();
  return InsertResult::kInserted;
}

bool TriangulationEditor::starTouchesOutside(VertexHandle v) { return v->info().outside_cells > 0; }

void TriangulationEditor::remove(VertexHandle v, std::vector<RayId>& retrace) {
  assert(v->info().outside_cells == 0);
  conflict_cells_.clear();
  state_.tri.incident_cells(v, std::back_inserter(conflict_cells_));
  untraceCrossing(conflict_cells_, retrace);
  forgetCells(conflict_cells_);
  new_cells_.clear();
  state_.tri.remove_and_give_new_cells(v, std::back_inserter(new_cells_));
  sortByVertexKeys(new_cells_);
  registerNewCells(new_cells_);
  if (!new_cells_.empty()) hint_ = new_cells_.front();
}

void TriangulationEditor::sortByVertexKeys(std::vector<CellHandle>& cells) const {
  // CGAL fills the hole of a removed vertex in an order that follows a hash of vertex addresses.
  // Stamping the new cells in that order would make uids, and every tie-break on them, differ
  // between runs (and after resuming a checkpoint); the cells' vertex keys give one order.
  using CellKey = std::array<std::pair<std::uint8_t, std::uint64_t>, 4>;
  std::vector<std::pair<CellKey, CellHandle>> keyed;
  keyed.reserve(cells.size());
  for (const CellHandle& cell : cells) {
    CellKey key;
    for (int i = 0; i < 4; ++i) {
      const VertexHandle v = cell->vertex(i);
      if (state_.tri.is_infinite(v)) {
        key[i] = {2, 0};
      } else {
        const VertexKey vertex_key = state_.outside.vertexKey(v);
        key[i] = {vertex_key.steiner ? 1 : 0, vertex_key.value};
      }
    }
    std::sort(key.begin(), key.end());
    keyed.emplace_back(key, cell);
  }
  std::sort(keyed.begin(), keyed.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t i = 0; i < keyed.size(); ++i) cells[i] = keyed[i].second;
}

void TriangulationEditor::untraceCrossing(const std::vector<CellHandle>& doomed,
                                          std::vector<RayId>& retrace) {
  crossings_.clear();
  for (const CellHandle& cell : doomed) {
    const std::vector<Crossing>& list = state_.rays.crossing(cell);
    crossings_.insert(crossings_.end(), list.begin(), list.end());
  }
  if (crossings_.empty()) return;
  // Only the stretch of each ray from its first doomed cell to its last is withdrawn and walked
  // again.
  tracer_.truncateAtDoomed(crossings_, batch_);
  for (RayId id : batch_) {
    Ray& ray = state_.rays[id];
    if (ray.flags & kRayNeedsTrace) continue;
    ray.flags |= kRayNeedsTrace;
    retrace.push_back(id);
  }
}

void TriangulationEditor::forgetCells(const std::vector<CellHandle>& doomed) {
  for (const CellHandle& cell : doomed) {
    for (int i = 0; i < 4; ++i) --cell->vertex(i)->info().degree;
  }
}

void TriangulationEditor::registerNewCells(const std::vector<CellHandle>& cells) {
  const std::uint32_t mark = state_.nextMark();
  for (const CellHandle& cell : cells) {
    state_.stampNewCell(cell);
    cell->info().mark = mark;
    for (int i = 0; i < 4; ++i) ++cell->vertex(i)->info().degree;
  }
  // New cells have no crossings; their weights, and those of the cells around the re-triangulated
  // region, depend on the new adjacency. A new cell behind a surface face that survived changes
  // what lies behind that face.
  for (const CellHandle& cell : cells) {
    state_.outside.touchFacesOf(cell);
    state_.weights.recompute(cell, state_.candidates);
    for (int i = 0; i < 4; ++i) {
      const CellHandle n = cell->neighbor(i);
      if (n->info().mark == mark) continue;
      n->info().mark = mark;
      state_.weights.recompute(n, state_.candidates);
    }
  }
}

}  // namespace terramesh::mesher::internal

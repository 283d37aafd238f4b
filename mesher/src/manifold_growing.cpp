#include "manifold_growing.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace terramesh::mesher::internal {

bool Grower::adjacentToOutside(const CellHandle& cell) const {
  for (int i = 0; i < 4; ++i) {
    if (cell->neighbor(i)->info().outside()) return true;
  }
  return false;
}

void Grower::push(const CellHandle& cell) {
  CellInfo& info = cell->info();
  if (info.flags & (kCellOutside | kCellQueued)) return;
  if (!state_.isFree(cell) || state_.tri.is_infinite(cell)) return;
  info.flags |= kCellQueued;
  // MesherConfig::driven_cells_first: cells the robot's body passed through (a ray to a
  // driven-ground sample crosses them) grow before all others, by weight among themselves (a parked
  // car's side points pinched the driven strip's cells between the road and them out of O, issue
  // 22). Weights stay below 2^31, so the offset orders without overlap.
  constexpr std::int64_t kDrivenFirst = std::int64_t{1} << 40;
  const bool first = state_.config.driven_cells_first && info.driven_crossings > 0;
  queue_.push({info.weight + (first ? kDrivenFirst : 0), info.uid, cell});
}

void Grower::pushFreeNeighbours(const CellHandle& cell) {
  for (int i = 0; i < 4; ++i) push(cell->neighbor(i));
}

void Grower::scanVertex(const VertexHandle& v) {
  scratch_.clear();
  state_.tri.incident_cells(v, std::back_inserter(scratch_));
  for (const CellHandle& cell : scratch_) {
    if (!cell->info().outside() && adjacentToOutside(cell)) push(cell);
  }
}

void Grower::grow(const std::unordered_set<GridKey, GridKeyHash>* region, UpdateStats& stats) {
  std::vector<StampedCell> candidates = state_.candidates.take();
  touched_vertices_.clear();
  final_refused_.clear();
  driven_refused_.clear();

  // Bootstrap: an empty O starts from the freest candidate.
  if (state_.outside.size() == 0) {
    CellHandle best;
    for (const StampedCell& c : candidates) {
      if (!state_.alive(c) || state_.tri.is_infinite(c.cell) || !state_.isFree(c.cell)) {
        continue;
      }
      if (best == CellHandle() || c.cell->info().weight > best->info().weight) best = c.cell;
    }
    if (best != CellHandle()) {
      state_.outside.add(best);
      ++stats.cells_grown;
      pushFreeNeighbours(best);
    }
  }
  for (const StampedCell& c : candidates) {
    if (!state_.alive(c)) continue;
    c.cell->info().flags &= static_cast<std::uint8_t>(~kCellCandidate);
    if (adjacentToOutside(c.cell)) push(c.cell);
  }
  if (region != nullptr) {
    stats.boundary_vertices_examined +=
        state_.hash.forEachVertexIn(*region, [this](const VertexHandle& v) { scanVertex(v); });
  } else {
    state_.hash.forEachVertex([this](const VertexHandle& v) { scanVertex(v); });
  }
  drainQueue(stats);
  if (state_.config.edge_growing_pass) edgePass(stats);
  genusPass(stats);
  if (state_.config.edge_growing_pass) ballPass(stats);
  if (state_.config.driven_cells_first) drivenPocketPass(stats);
}

void Grower::edgePass(UpdateStats& stats) {
  std::vector<CellHandle> refused;
  refused.swap(final_refused_);
  std::vector<CellHandle> ring;
  const auto min_weight =
      static_cast<std::int32_t>(std::lround(state_.config.edge_pass_min_weight * WeightField::kFixedPointScale));
  for (std::size_t r = 0; r < refused.size(); ++r) {
    const CellHandle cell = refused[r];
    if (cell->info().outside()) continue;
    if (cell->info().weight < min_weight) continue;
    for (int i = 0; i < 4 && !cell->info().outside(); ++i) {
      for (int j = i + 1; j < 4 && !cell->info().outside(); ++j) {
        ring.clear();
        const auto start = state_.tri.incident_cells(cell, i, j);
        auto c = start;
        do {
          const CellHandle h = c;
          if (!h->info().outside() && !state_.tri.is_infinite(h) && state_.isFree(h)) ring.push_back(h);
        } while (++c != start);
        if (!tryAddSet(ring, stats)) continue;
        refused.insert(refused.end(), final_refused_.begin(), final_refused_.end());
        final_refused_.clear();
      }
    }
  }
  ball_candidates_ = std::move(refused);
}

int Grower::boundaryEulerChange(const std::vector<CellHandle>& set, bool& fills_cavity) {
  const std::uint32_t mark = state_.nextMark();
  for (const CellHandle& cell : set) cell->info().mark = mark;
  fills_cavity = true;
  int change = 0;
  euler_vertices_.clear();
  euler_edges_.clear();
  for (const CellHandle& cell : set) {
    for (int i = 0; i < 4; ++i) {
      // A facet changes only between a cell of the set and one outside it: on dO after iff not
      // before.
      const CellHandle n = cell->neighbor(i);
      if (n->info().mark != mark) {
        change += n->info().outside() ? -1 : 1;
        fills_cavity = fills_cavity && n->info().outside();
      }
      euler_vertices_.push_back(cell->vertex(i));
      for (int j = i + 1; j < 4; ++j) {
        const Delaunay::Vertex* a = &*cell->vertex(i);
        const Delaunay::Vertex* b = &*cell->vertex(j);
        if (b < a) std::swap(a, b);
        euler_edges_.push_back({a, b, cell, i, j});
      }
    }
  }
  // A vertex (edge) is on dO when some of its cells are in O and some are not. The sum does not
  // depend on the (address) order of the sort.
  std::sort(euler_vertices_.begin(), euler_vertices_.end(),
            [](const VertexHandle& x, const VertexHandle& y) { return &*x < &*y; });
  for (std::size_t r = 0; r < euler_vertices_.size();) {
    std::size_t end = r + 1;
    while (end < euler_vertices_.size() && euler_vertices_[end] == euler_vertices_[r]) ++end;
    const VertexInfo& info = euler_vertices_[r]->info();
    const std::size_t before = info.outside_cells;
    const std::size_t after = before + (end - r);
    const bool on_after = after > 0 && after < info.degree;
    const bool on_before = before > 0 && before < info.degree;
    change += static_cast<int>(on_after) - static_cast<int>(on_before);
    r = end;
  }
  std::sort(euler_edges_.begin(), euler_edges_.end(), [](const SetEdge& x, const SetEdge& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  for (std::size_t r = 0; r < euler_edges_.size(); ++r) {
    const SetEdge& e = euler_edges_[r];
    if (r > 0 && euler_edges_[r - 1].a == e.a && euler_edges_[r - 1].b == e.b) continue;
    bool in_before = false, out_before = false, in_after = false, out_after = false;
    const auto start = state_.tri.incident_cells(e.cell, e.i, e.j);
    auto c = start;
    do {
      const bool outside = c->info().outside();
      const bool added = c->info().mark == mark;
      in_before = in_before || outside;
      out_before = out_before || !outside;
      in_after = in_after || outside || added;
      out_after = out_after || !(outside || added);
    } while (++c != start);
    change -= static_cast<int>(in_after && out_after);
    change += static_cast<int>(in_before && out_before);
  }
  return change;
}

bool Grower::handleRuleAllows(const std::vector<CellHandle>& set) {
  const int min_rays = state_.config.handle_min_rays;
  if (min_rays <= 0) return true;
  for (const CellHandle& cell : set) {
    if (cell->info().crossings >= static_cast<std::uint32_t>(min_rays)) return true;
  }
  bool fills_cavity = false;
  return boundaryEulerChange(set, fills_cavity) >= 0 || fills_cavity;
}

bool Grower::tryAddSet(std::vector<CellHandle>& set, UpdateStats& stats) {
  if (set.size() < 2 || !state_.outside.canAddAll(set)) return false;
  return addIfHandleRuleAllows(set, stats);
}

bool Grower::addIfHandleRuleAllows(std::vector<CellHandle>& set, UpdateStats& stats) {
  if (!handleRuleAllows(set)) return false;
  for (const CellHandle& h : set) {
    state_.outside.add(h);
    ++stats.cells_grown;
    ++stats.edge_pass_cells;
  }
  for (const CellHandle& h : set) pushFreeNeighbours(h);
  drainQueue(stats);
  return true;
}

std::uint64_t Grower::neighbourhoodSignature(const CellHandle& cell) const {
  // Changes when the cell's weight or the number of O-cells around one of its vertices changes:
  // the events that can turn a refused ball into an accepted one.
  std::uint64_t signature = static_cast<std::uint32_t>(cell->info().weight);
  for (int i = 0; i < 4; ++i) signature = signature * 0x9E3779B97F4A7C15ull + cell->vertex(i)->info().outside_cells + 1;
  return signature;
}

bool Grower::tryAddBall(const CellHandle& cell, UpdateStats& stats) {
  std::vector<CellHandle>& set = ball_;
  for (int i = 0; i < 4; ++i) {
    const CellHandle n = cell->neighbor(i);
    if (n->info().outside() || state_.tri.is_infinite(n) || !state_.isFree(n)) continue;
    set.assign({cell, n});
    if (tryAddSet(set, stats)) return true;
  }
  const std::uint32_t mark = state_.nextMark();
  set.clear();
  for (int i = 0; i < 4; ++i) {
    scratch_.clear();
    state_.tri.incident_cells(cell->vertex(i), std::back_inserter(scratch_));
    for (const CellHandle& h : scratch_) {
      if (h->info().mark == mark) continue;
      h->info().mark = mark;
      if (!h->info().outside() && !state_.tri.is_infinite(h) && state_.isFree(h)) set.push_back(h);
    }
  }
  return tryAddSet(set, stats);
}

void Grower::ballPass(UpdateStats& stats) {
  std::vector<CellHandle> refused;
  refused.swap(ball_candidates_);
  refused.insert(refused.end(), final_refused_.begin(), final_refused_.end());
  final_refused_.clear();
  const auto min_weight =
      static_cast<std::int32_t>(std::lround(state_.config.edge_pass_min_weight * WeightField::kFixedPointScale));
  std::size_t attempts = 0;
  for (std::size_t r = 0; r < refused.size() && attempts < kMaxBallAttemptsPerGrow; ++r) {
    const CellHandle cell = refused[r];
    if (cell->info().outside() || cell->info().weight < min_weight || !adjacentToOutside(cell)) continue;
    // A ball refused before, in the same neighbourhood, would be refused again.
    const std::uint64_t signature = neighbourhoodSignature(cell);
    const auto [memo, inserted] = ball_refusals_.try_emplace(cell->info().uid, signature);
    if (!inserted && memo->second == signature) continue;
    memo->second = signature;
    ++attempts;
    if (!tryAddBall(cell, stats)) continue;
    refused.insert(refused.end(), final_refused_.begin(), final_refused_.end());
    final_refused_.clear();
  }
  // Stale entries (cells destroyed or carved since) only cost memory: forget them all now and then.
  if (ball_refusals_.size() > kMaxBallRefusalsRemembered) ball_refusals_.clear();
}

void Grower::drainQueue(UpdateStats& stats) {
  OutsideSet& outside = state_.outside;
  // A refused cell's test can only change once O changes around one of its vertices: each pass
  // marks the vertices of the cells it adds, and refused cells touching a marked vertex are tried
  // again (others cannot succeed yet).
  std::vector<CellHandle> refused;
  while (true) {
    const std::uint32_t changed = state_.nextVertexMark();
    while (!queue_.empty()) {
      const CellHandle cell = queue_.top().cell;
      queue_.pop();
      cell->info().flags &= static_cast<std::uint8_t>(~kCellQueued);
      if (cell->info().outside()) continue;
      if (!outside.canAdd(cell)) {
        refused.push_back(cell);
        continue;
      }
      outside.add(cell);
      ++stats.cells_grown;
      for (int i = 0; i < 4; ++i) cell->vertex(i)->info().mark = changed;
      pushFreeNeighbours(cell);
    }
    std::size_t retried = 0;
    std::vector<CellHandle> still_refused;
    for (const CellHandle& cell : refused) {
      if (cell->info().outside()) continue;
      bool touched = false;
      for (int i = 0; i < 4 && !touched; ++i) touched = cell->vertex(i)->info().mark == changed;
      if (touched) {
        push(cell);
        ++retried;
      } else {
        still_refused.push_back(cell);
      }
    }
    refused.swap(still_refused);
    if (retried == 0) break;
  }
  // Cells still refused are where fronts of O meet or pinch: the vertices of their faces shared
  // with O are the candidates of the per-vertex pass.
  if (state_.config.edge_growing_pass) final_refused_.insert(final_refused_.end(), refused.begin(), refused.end());
  for (const CellHandle& cell : refused) {
    if (state_.config.driven_cells_first && cell->info().driven_crossings > 0) driven_refused_.push_back(cell);
    for (int j = 0; j < 4; ++j) {
      if (!cell->neighbor(j)->info().outside()) continue;
      for (int i = 0; i < 4; ++i) {
        if (i != j) touched_vertices_.push_back(cell->vertex(i));
      }
    }
  }
}

void Grower::genusPass(UpdateStats& stats) {
  // For a vertex of dO, add every free cell of its star that is not in O yet, all at once: where
  // two fronts of O meet, no single cell can join them without pinching the surface, but a whole
  // star can, which lets the surface change genus (as in Litvinov & Lhuillier 2013).
  // drainQueue below uses the vertex marks, so visited vertices are remembered here.
  std::unordered_set<const internal::Delaunay::Vertex*> visited;
  std::vector<CellHandle> star;
  std::vector<CellHandle> to_add;
  for (std::size_t i = 0; i < touched_vertices_.size(); ++i) {
    const VertexHandle v = touched_vertices_[i];
    if (v->info().outside_cells == 0 || !visited.insert(&*v).second) continue;
    star.clear();
    state_.tri.incident_cells(v, std::back_inserter(star));
    to_add.clear();
    for (const CellHandle& cell : star) {
      if (!cell->info().outside() && !state_.tri.is_infinite(cell) && state_.isFree(cell)) {
        to_add.push_back(cell);
      }
    }
    if (to_add.size() < 2) continue;  // a single cell was already tried by the queue
    if (!state_.outside.canAddAll(to_add)) continue;
    if (!handleRuleAllows(to_add)) continue;
    for (const CellHandle& cell : to_add) {
      state_.outside.add(cell);
      ++stats.cells_grown;
      ++stats.genus_pass_cells;
    }
    for (const CellHandle& cell : to_add) pushFreeNeighbours(cell);
    drainQueue(stats);
  }
}

void Grower::drivenPocketPass(UpdateStats& stats) {
  std::vector<CellHandle> seeds;
  seeds.swap(driven_refused_);
  std::size_t attempts = 0;
  for (std::size_t r = 0; r < seeds.size() && attempts < kMaxPocketAttemptsPerGrow; ++r) {
    const CellHandle cell = seeds[r];
    if (cell->info().outside() || !adjacentToOutside(cell)) continue;
    ++attempts;
    if (tryAddPocket(cell, stats)) seeds.insert(seeds.end(), driven_refused_.begin(), driven_refused_.end());
    driven_refused_.clear();
  }
}

bool Grower::tryAddPocket(const CellHandle& cell, UpdateStats& stats) {
  std::vector<CellHandle>& pocket = pocket_;
  const std::uint32_t mark = state_.nextMark();
  pocket.assign({cell});
  cell->info().mark = mark;
  for (std::size_t r = 0; r < pocket.size() && pocket.size() < kMaxPocketCells; ++r) {
    for (int i = 0; i < 4 && pocket.size() < kMaxPocketCells; ++i) {
      const CellHandle n = pocket[r]->neighbor(i);
      if (n->info().mark == mark) continue;
      n->info().mark = mark;
      if (!n->info().outside() && !state_.tri.is_infinite(n) && state_.isFree(n)) pocket.push_back(n);
    }
  }
  for (int round = 0; round < kMaxPocketRounds && pocket.size() >= 2; ++round) {
    VertexHandle failed;
    if (state_.outside.canAddAll(pocket, &failed)) return addIfHandleRuleAllows(pocket, stats);
    if (failed == VertexHandle()) return false;
    // The cell around the failed vertex found last (farthest from `cell`) goes first.
    const auto last = std::find_if(pocket.rbegin(), pocket.rend(),
                                   [&failed](const CellHandle& c) { return c->has_vertex(failed); });
    if (last == pocket.rend()) return false;
    pocket.erase(std::next(last).base());
    keepJoinedToOutside(pocket);
  }
  return false;
}

void Grower::keepJoinedToOutside(std::vector<CellHandle>& set) {
  const std::uint32_t member = state_.nextMark();
  for (const CellHandle& c : set) c->info().mark = member;
  const std::uint32_t joined = state_.nextMark();
  std::vector<CellHandle>& front = scratch_;
  front.clear();
  for (const CellHandle& c : set) {
    if (adjacentToOutside(c)) {
      c->info().mark = joined;
      front.push_back(c);
    }
  }
  for (std::size_t r = 0; r < front.size(); ++r) {
    for (int i = 0; i < 4; ++i) {
      const CellHandle n = front[r]->neighbor(i);
      if (n->info().mark != member) continue;
      n->info().mark = joined;
      front.push_back(n);
    }
  }
  // Stable: the set keeps its order (nearest the pocket's seed first).
  set.erase(std::remove_if(set.begin(), set.end(), [joined](const CellHandle& c) { return c->info().mark != joined; }),
            set.end());
}

}  // namespace terramesh::mesher::internal

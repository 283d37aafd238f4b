#pragma once
// The one graph search of terramesh: best-first search (A*, or Dijkstra with a zero heuristic)
// over nodes 0..n-1 whose edges a callback enumerates. The planner's face-graph A* and the
// shortest traversable lengths on the truth use it; its multi-source, bounded form on costs the
// caller keeps (boundedDijkstra) keeps the layers' distance to the nearest lethal face current.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace terramesh::graph {

/// What a search found: per node its best cost from the source (infinite if never reached), the
/// node it was reached from and the label of that edge (kNone for the source and unreached
/// nodes), and whether the target was settled.
struct SearchResult {
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<double> cost;
  std::vector<std::uint32_t> parent;
  std::vector<std::uint32_t> parent_label;
  bool reached = false;
  std::size_t expanded = 0;  ///< nodes settled

  /// The nodes from the source to `node`, in order (empty if `node` was not reached).
  std::vector<std::uint32_t> pathTo(std::uint32_t node) const {
    std::vector<std::uint32_t> nodes;
    if (node >= cost.size() || cost[node] == std::numeric_limits<double>::infinity()) return nodes;
    for (std::uint32_t n = node; n != kNone; n = parent[n]) nodes.push_back(n);
    return {nodes.rbegin(), nodes.rend()};
  }
};

/// Calls relax(neighbour, edge_cost, label) for every edge leaving a node.
using Relax = std::function<void(std::uint32_t, double, std::uint32_t)>;

/// Best-first search from `source` until `target` is settled (or every reachable node is, if
/// `target` is SearchResult::kNone). `expand(u, relax)` enumerates the edges of node u (costs
/// >= 0); `heuristic(v)` is an admissible, consistent estimate of the cost from v to the target
/// (0: Dijkstra). Ties between equal keys go to the lower node id, so a search is deterministic.
/// Each node is settled once; edges into settled nodes are ignored. O((V + E) log V).
template <class Expand, class Heuristic>
SearchResult bestFirstSearch(std::size_t node_count, std::uint32_t source, std::uint32_t target, Expand&& expand,
                             Heuristic&& heuristic) {
  SearchResult result;
  const double inf = std::numeric_limits<double>::infinity();
  result.cost.assign(node_count, inf);
  result.parent.assign(node_count, SearchResult::kNone);
  result.parent_label.assign(node_count, SearchResult::kNone);
  if (source >= node_count) return result;
  std::vector<std::uint8_t> settled(node_count, 0);
  using Entry = std::pair<double, std::uint32_t>;  // (cost + heuristic, node)
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  result.cost[source] = 0;
  open.emplace(heuristic(source), source);
  std::uint32_t u = SearchResult::kNone;
  const Relax relax = [&](std::uint32_t v, double edge_cost, std::uint32_t label) {
    if (v >= node_count || settled[v] || v == u) return;
    const double candidate = result.cost[u] + edge_cost;
    if (candidate < result.cost[v]) {
      result.cost[v] = candidate;
      result.parent[v] = u;
      result.parent_label[v] = label;
      open.emplace(candidate + heuristic(v), v);
    }
  };
  while (!open.empty()) {
    u = open.top().second;
    open.pop();
    if (settled[u]) continue;
    settled[u] = 1;
    ++result.expanded;
    if (u == target) {
      result.reached = true;
      break;
    }
    expand(u, relax);
  }
  return result;
}

/// A min-heap of (cost, node) for boundedDijkstra; its storage may be kept between searches.
using CostHeap = std::vector<std::pair<double, std::uint32_t>>;

/// Adds `node` at `cost` to a CostHeap.
inline void pushCost(CostHeap& heap, double cost, std::uint32_t node) {
  heap.emplace_back(cost, node);
  std::push_heap(heap.begin(), heap.end(), std::greater<>());
}

/// Dijkstra from every entry already in `heap` (the sources, at their costs), on costs the caller
/// keeps: `cost(v)` returns a reference to node v's best cost so far (infinite: not reached), which
/// the search lowers, so a search on part of a large graph touches only that part and allocates
/// nothing once the heap's storage has grown. `expand(u, relax)` enumerates the edges of node u by
/// calling relax(v, edge_cost) (costs >= 0); a cost above `cutoff` is not kept. An entry above its
/// node's cost is stale and skipped. Ties pop the lower node first. Leaves the heap empty (its
/// storage kept). O((V + E) log V) over the nodes reached.
template <class Cost, class Expand>
void boundedDijkstra(CostHeap& heap, Cost&& cost, Expand&& expand, double cutoff) {
  double from_cost = 0;
  const auto relax = [&](std::uint32_t v, double edge_cost) {
    const double candidate = from_cost + edge_cost;
    double& current = cost(v);
    if (candidate <= cutoff && candidate < current) {
      current = candidate;
      pushCost(heap, candidate, v);
    }
  };
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), std::greater<>());
    const auto [key, u] = heap.back();
    heap.pop_back();
    if (key > cost(u)) continue;
    from_cost = key;
    expand(u, relax);
  }
}

}  // namespace terramesh::graph

// graph::bestFirstSearch, the one graph search: Dijkstra and A* on small graphs whose answers are
// known by hand, ties, unreachable targets and a full sweep; and its multi-source bounded form,
// graph::boundedDijkstra, against single-source searches from each source.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "common/graph_search.h"

namespace terramesh::graph {
namespace {

struct Edge {
  std::uint32_t to;
  double cost;
  std::uint32_t label;
};
using Graph = std::vector<std::vector<Edge>>;

SearchResult search(const Graph& g, std::uint32_t from, std::uint32_t to,
                    const std::function<double(std::uint32_t)>& heuristic = [](std::uint32_t) { return 0.0; }) {
  return bestFirstSearch(
      g.size(), from, to,
      [&g](std::uint32_t u, const Relax& relax) {
        for (const Edge& e : g[u]) relax(e.to, e.cost, e.label);
      },
      heuristic);
}

// 0 -> 1 -> 3 costs 1 + 5; 0 -> 2 -> 3 costs 2 + 2: the longer hop count wins.
Graph diamond() { return {{{1, 1, 10}, {2, 2, 20}}, {{3, 5, 13}}, {{3, 2, 23}}, {}}; }

TEST(GraphSearchTest, DijkstraFindsTheCheapestPathWithItsEdgeLabels) {
  const SearchResult r = search(diamond(), 0, 3);
  ASSERT_TRUE(r.reached);
  EXPECT_DOUBLE_EQ(r.cost[3], 4.0);
  EXPECT_EQ(r.pathTo(3), (std::vector<std::uint32_t>{0, 2, 3}));
  EXPECT_EQ(r.parent_label[3], 23u);
  EXPECT_EQ(r.parent_label[2], 20u);
  EXPECT_EQ(r.parent_label[0], SearchResult::kNone);
}

TEST(GraphSearchTest, AStarWithAnAdmissibleHeuristicSettlesFewerNodesForTheSameCost) {
  // A line 0-1-...-9 with unit edges, and a side branch from 0 of 20 cheap nodes leading nowhere.
  Graph g(30);
  for (std::uint32_t i = 0; i < 9; ++i) g[i].push_back({i + 1, 1.0, i});
  g[0].push_back({10, 0.5, 100});
  for (std::uint32_t i = 10; i < 29; ++i) g[i].push_back({i + 1, 0.5, i});
  const SearchResult dijkstra = search(g, 0, 9);
  const SearchResult astar = search(g, 0, 9, [](std::uint32_t v) { return v < 10 ? 9.0 - v : 100.0; });
  ASSERT_TRUE(dijkstra.reached && astar.reached);
  EXPECT_DOUBLE_EQ(dijkstra.cost[9], 9.0);
  EXPECT_DOUBLE_EQ(astar.cost[9], 9.0);
  EXPECT_LT(astar.expanded, dijkstra.expanded);
  EXPECT_EQ(astar.expanded, 10u);  // only the line
}

TEST(GraphSearchTest, UnreachableTargetsAndFullSweeps) {
  Graph g = diamond();
  g.push_back({});  // node 4: isolated
  const SearchResult r = search(g, 0, 4);
  EXPECT_FALSE(r.reached);
  EXPECT_TRUE(std::isinf(r.cost[4]));
  EXPECT_TRUE(r.pathTo(4).empty());
  const SearchResult all = search(g, 0, SearchResult::kNone);
  EXPECT_FALSE(all.reached);
  EXPECT_EQ(all.expanded, 4u);
  EXPECT_DOUBLE_EQ(all.cost[1], 1.0);
  EXPECT_DOUBLE_EQ(all.cost[3], 4.0);
  const SearchResult self = search(g, 2, 2);
  EXPECT_TRUE(self.reached);
  EXPECT_DOUBLE_EQ(self.cost[2], 0.0);
  EXPECT_FALSE(search(g, 7, 0).reached);  // a source outside the graph
}

TEST(GraphSearchTest, EqualCostsGoToTheLowerNodeIdSoSearchesRepeat) {
  // Two equal paths 0 -> 1 -> 3 and 0 -> 2 -> 3: node 1 is settled first and reaches 3 first.
  const Graph g = {{{2, 1, 0}, {1, 1, 0}}, {{3, 1, 1}}, {{3, 1, 2}}, {}};
  const SearchResult r = search(g, 0, 3);
  EXPECT_EQ(r.pathTo(3), (std::vector<std::uint32_t>{0, 1, 3}));
  EXPECT_EQ(r.parent_label[3], 1u);
}

TEST(GraphSearchTest, BoundedDijkstraFromSeveralSourcesIsTheNearestSourcesCostWithinTheCutoff) {
  // A random undirected graph; sources at cost 0 and one at 0.7; the cutoff 2.5 keeps nothing
  // beyond it.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> length(0.1, 1.0);
  constexpr std::uint32_t kNodes = 60;
  Graph g(kNodes);
  for (std::uint32_t e = 0; e < 150; ++e) {
    const std::uint32_t a = rng() % kNodes, b = rng() % kNodes;
    const double c = length(rng);
    g[a].push_back({b, c, e});
    g[b].push_back({a, c, e});
  }
  const std::vector<std::pair<std::uint32_t, double>> sources = {{3, 0.0}, {17, 0.0}, {40, 0.7}};
  const double cutoff = 2.5;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> cost(kNodes, inf);
  CostHeap heap;
  for (const auto& [node, at] : sources) {
    cost[node] = at;
    pushCost(heap, at, node);
  }
  pushCost(heap, 9.0, 3);  // a stale entry: above node 3's cost, skipped
  std::size_t expanded = 0;
  boundedDijkstra(
      heap, [&](std::uint32_t v) -> double& { return cost[v]; },
      [&](std::uint32_t u, const auto& relax) {
        ++expanded;
        for (const Edge& e : g[u]) relax(e.to, e.cost);
      },
      cutoff);
  EXPECT_TRUE(heap.empty());
  std::size_t reached = 0;
  for (std::uint32_t v = 0; v < kNodes; ++v) {
    double expected = inf;
    for (const auto& [node, at] : sources) expected = std::min(expected, at + search(g, node, SearchResult::kNone).cost[v]);
    if (expected > cutoff) expected = inf;
    reached += expected < inf ? 1 : 0;
    EXPECT_DOUBLE_EQ(cost[v], expected) << "node " << v;
  }
  EXPECT_GT(reached, 10u);
  EXPECT_LT(reached, static_cast<std::size_t>(kNodes));  // the cutoff leaves some out
  EXPECT_EQ(expanded, reached);                           // each node expanded once, the stale entry not
  // A cost already below what the search finds stays (faces outside the region searched keep theirs).
  std::uint32_t far = 3;
  for (std::uint32_t v = 0; v < kNodes; ++v) {
    if (cost[v] < inf && cost[v] > cost[far]) far = v;
  }
  ASSERT_GT(cost[far], 1.0);
  std::fill(cost.begin(), cost.end(), inf);
  cost[3] = 0;
  cost[far] = 0.5;
  pushCost(heap, 0.0, 3);
  boundedDijkstra(
      heap, [&](std::uint32_t v) -> double& { return cost[v]; },
      [&](std::uint32_t u, const auto& relax) {
        for (const Edge& e : g[u]) relax(e.to, e.cost);
      },
      inf);
  EXPECT_DOUBLE_EQ(cost[far], 0.5);
}

}  // namespace
}  // namespace terramesh::graph

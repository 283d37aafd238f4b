// graph::bestFirstSearch, the one graph search: Dijkstra and A* on small graphs whose answers are
// known by hand, ties, unreachable targets and a full sweep.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

}  // namespace
}  // namespace terramesh::graph

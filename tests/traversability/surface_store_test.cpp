// The SurfaceStore's indexes against brute-force oracles: its key, adjacency and grid queries
// against scans of every face after random edits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "surface_store.h"

namespace terramesh::traversability::internal {
namespace {

mesher::SurfaceFace randomFace(std::mt19937_64& rng, std::uint64_t first_vertex) {
  std::uniform_real_distribution<double> pos(0.0, 20.0), size(-1.5, 1.5), height(-0.2, 0.2);
  mesher::SurfaceFace f;
  const Eigen::Vector3d c(pos(rng), pos(rng), 0.0);
  for (int i = 0; i < 3; ++i) {
    f.vertices[i] = mesher::VertexKey::point(mesher::PointId{first_vertex + static_cast<std::uint64_t>(i)});
    f.positions_W[i] = c + Eigen::Vector3d(size(rng), size(rng), height(rng));
  }
  f.key = mesher::FaceKey::of(f.vertices[0], f.vertices[1], f.vertices[2]);
  f.rays = 5;
  return f;
}

TEST(SurfaceStoreTest, QueriesMatchScansAfterRandomEdits) {
  std::mt19937_64 rng(11);
  const double cell_m = 1.0;
  SurfaceStore store(Eigen::Matrix3d::Identity(), 1.0, cell_m, 2.0);
  std::map<std::uint64_t, mesher::FaceKey> alive;  // by first vertex id
  std::uint64_t next_vertex = 1;
  // Faces share vertices with earlier ones now and then (adjacency).
  std::vector<mesher::SurfaceFace> added;
  for (int step = 0; step < 3000; ++step) {
    if (!alive.empty() && rng() % 3 == 0) {
      auto it = alive.begin();
      std::advance(it, static_cast<long>(rng() % alive.size()));
      ASSERT_TRUE(store.remove(it->second));
      alive.erase(it);
      continue;
    }
    mesher::SurfaceFace f = randomFace(rng, next_vertex);
    next_vertex += 3;
    if (!added.empty() && rng() % 2 == 0) {
      // Share an edge with an earlier face (its first two vertices).
      const mesher::SurfaceFace& g = added[rng() % added.size()];
      f.vertices[0] = g.vertices[0];
      f.vertices[1] = g.vertices[1];
      f.key = mesher::FaceKey::of(f.vertices[0], f.vertices[1], f.vertices[2]);
    }
    store.add(f);
    added.push_back(f);
    alive[f.vertices[2].value] = f.key;
  }
  ASSERT_EQ(store.size(), alive.size());
  for (const auto& [id, key] : alive) {
    const std::optional<Slot> s = store.find(key);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(store.face(*s).key, key);
  }
  const auto cell = [&](double v) { return static_cast<std::int64_t>(std::floor(v / cell_m)); };
  std::uniform_real_distribution<double> pos(-1.0, 21.0), extent(0.0, 3.0);
  for (int query = 0; query < 300; ++query) {
    const Eigen::Vector2d lo(pos(rng), pos(rng));
    const Eigen::Vector2d hi = lo + Eigen::Vector2d(extent(rng), extent(rng));
    // Oracle: the alive faces whose box's cell range meets the query's cell range, each once,
    // reported in the order of the first query cell (i, then j) they overlap.
    std::set<Slot> expected;
    for (Slot s = 0; s < store.slotCount(); ++s) {
      const StoredFace& f = store.face(s);
      if (!f.alive) continue;
      if (cell(f.box_max.x()) < cell(lo.x()) || cell(f.box_min.x()) > cell(hi.x()) ||
          cell(f.box_max.y()) < cell(lo.y()) || cell(f.box_min.y()) > cell(hi.y())) {
        continue;
      }
      expected.insert(s);
    }
    std::vector<Slot> got;
    store.forEachInBox(lo, hi, [&](Slot s) { got.push_back(s); });
    EXPECT_EQ(std::set<Slot>(got.begin(), got.end()), expected);
    EXPECT_EQ(got.size(), expected.size()) << "a face reported twice";
    std::pair<std::int64_t, std::int64_t> previous{std::numeric_limits<std::int64_t>::min(), 0};
    for (Slot s : got) {
      const StoredFace& f = store.face(s);
      const std::pair<std::int64_t, std::int64_t> first{std::max(cell(f.box_min.x()), cell(lo.x())),
                                                        std::max(cell(f.box_min.y()), cell(lo.y()))};
      EXPECT_LE(previous, first) << "not in first-cell order";
      previous = first;
    }
  }
  // Adjacency: faces sharing an edge, against a scan.
  std::vector<Slot> neighbours;
  for (Slot s = 0; s < store.slotCount(); ++s) {
    if (!store.face(s).alive) continue;
    std::set<Slot> expected;
    const auto& v = store.face(s).vertices;
    for (Slot t = 0; t < store.slotCount(); ++t) {
      if (t == s || !store.face(t).alive) continue;
      const auto& w = store.face(t).vertices;
      int shared = 0;
      for (const auto& a : v) shared += std::count(w.begin(), w.end(), a) > 0 ? 1 : 0;
      if (shared >= 2) expected.insert(t);
    }
    store.neighbours(s, neighbours);
    EXPECT_EQ(std::set<Slot>(neighbours.begin(), neighbours.end()), expected) << "slot " << s;
  }
}

}  // namespace
}  // namespace terramesh::traversability::internal

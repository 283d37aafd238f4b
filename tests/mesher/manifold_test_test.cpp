// canAdd / canRemove / canAddAll against the oracle: the topology of the surface that results.
#include <gtest/gtest.h>

#include <random>

#include "boundary_hash.h"
#include "cgal_types.h"
#include "mesher/triangle_mesh.h"
#include "outside_boundary.h"
#include "outside_set.h"
#include "steiner_grid.h"

namespace terramesh::mesher::internal {
namespace {

using test::boundaryOf;
using test::surfaceIsManifold;

class ManifoldTestOracle : public ::testing::Test {
 protected:
  ManifoldTestOracle() : epochs_(tri_), grid_(2.0), hash_(true), outside_(tri_, grid_, hash_, epochs_) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
    grid_.coverPoint(Eigen::Vector3d::Zero(), 1);
    for (int i = 0; i < 400; ++i) tri_.insert(Point(coordinate(rng), coordinate(rng), coordinate(rng)));
    for (auto cell = tri_.finite_cells_begin(); cell != tri_.finite_cells_end(); ++cell) {
      cells_.push_back(cell);
    }
    // Vertex degrees, which the mesher's editor keeps (the removal rule reads them).
    for (auto cell = tri_.all_cells_begin(); cell != tri_.all_cells_end(); ++cell) {
      for (int i = 0; i < 4; ++i) ++cell->vertex(i)->info().degree;
    }
  }

  /// Flips `cell` without checks and returns whether the result is a closed manifold.
  bool manifoldAfterFlip(const CellHandle& cell) {
    cell->info().flags ^= kCellOutside;
    const bool ok = surfaceIsManifold(tri_);
    cell->info().flags ^= kCellOutside;
    return ok;
  }

  Delaunay tri_;
  MarkEpochs epochs_;
  SteinerGrid grid_;
  BoundaryHash hash_;
  OutsideSet outside_;
  std::vector<CellHandle> cells_;
};

TEST_F(ManifoldTestOracle, CanAddAndCanRemoveAgreeWithTheResultingSurface) {
  std::mt19937 rng(11);
  std::vector<CellHandle> members{cells_[cells_.size() / 2]};
  outside_.add(members.front());
  std::size_t added = 0, refused = 0, removed = 0, kept = 0;
  for (int step = 0; step < 3000; ++step) {
    const CellHandle member = members[rng() % members.size()];
    if (!member->info().outside()) continue;
    if (step % 4 == 3 && outside_.size() > 1) {
      const bool predicted = outside_.canRemove(member);
      ASSERT_EQ(predicted, manifoldAfterFlip(member)) << "step " << step;
      if (predicted) {
        outside_.remove(member);
        ++removed;
      } else {
        ++kept;
      }
    } else {
      const CellHandle cell = member->neighbor(static_cast<int>(rng() % 4));
      if (cell->info().outside() || tri_.is_infinite(cell)) continue;
      const bool predicted = outside_.canAdd(cell);
      ASSERT_EQ(predicted, manifoldAfterFlip(cell)) << "step " << step;
      if (predicted) {
        outside_.add(cell);
        members.push_back(cell);
        ++added;
      } else {
        ++refused;
      }
    }
    ASSERT_TRUE(surfaceIsManifold(tri_));
  }
  EXPECT_GT(added, 300u);
  EXPECT_GT(refused, 20u);
  EXPECT_GT(removed, 20u);
  EXPECT_GT(kept, 20u);

}

TEST_F(ManifoldTestOracle, RemovalsAroundAnInteriorVertexAgreeWithTheResultingSurface) {
  // Fill the whole star of a vertex far from the hull, so it becomes interior to O.
  VertexHandle centre;
  for (auto v = tri_.finite_vertices_begin(); v != tri_.finite_vertices_end(); ++v) {
    if (toEigen(v->point()).norm() < 1.5) {
      centre = v;
      break;
    }
  }
  ASSERT_NE(centre, VertexHandle());
  std::vector<CellHandle> star;
  tri_.incident_cells(centre, std::back_inserter(star));
  outside_.add(star.front());
  bool progress = true;
  while (progress) {
    progress = false;
    for (const CellHandle& cell : star) {
      if (cell->info().outside()) continue;
      const bool predicted = outside_.canAdd(cell);
      ASSERT_EQ(predicted, manifoldAfterFlip(cell));
      if (predicted) {
        outside_.add(cell);
        progress = true;
      }
    }
  }
  ASSERT_EQ(centre->info().outside_cells, centre->info().degree) << "the vertex is interior";
  // Removing any one cell of the star opens a cavity at the centre: check each against the oracle.
  std::size_t allowed = 0;
  for (const CellHandle& cell : star) {
    const bool predicted = outside_.canRemove(cell);
    ASSERT_EQ(predicted, manifoldAfterFlip(cell));
    allowed += predicted;
  }
  EXPECT_GT(allowed, 0u);
}

TEST_F(ManifoldTestOracle, CanAddAllAgreesWithTheResultingSurface) {
  std::mt19937 rng(5);
  outside_.add(cells_[0]);
  for (int step = 0; step < 400; ++step) {
    const CellHandle cell = cells_[rng() % cells_.size()];
    if (!cell->info().outside() && outside_.canAdd(cell)) outside_.add(cell);
  }
  std::size_t agreed = 0;
  for (auto v = tri_.finite_vertices_begin(); v != tri_.finite_vertices_end(); ++v) {
    if (v->info().outside_cells == 0) continue;
    std::vector<CellHandle> star, to_add;
    tri_.incident_cells(v, std::back_inserter(star));
    for (const CellHandle& c : star) {
      if (!c->info().outside() && !tri_.is_infinite(c)) to_add.push_back(c);
    }
    if (to_add.size() < 2) continue;
    const bool predicted = outside_.canAddAll(to_add);
    for (const CellHandle& c : to_add) c->info().flags |= kCellOutside;
    const bool actual = surfaceIsManifold(tri_);
    for (const CellHandle& c : to_add) c->info().flags &= static_cast<std::uint8_t>(~kCellOutside);
    ASSERT_EQ(predicted, actual);
    ++agreed;
  }
  EXPECT_GT(agreed, 20u);
}

TEST_F(ManifoldTestOracle, VertexCountersAndHashFollowO) {
  outside_.add(cells_[1]);
  for (int i = 0; i < 4; ++i) {
    const VertexHandle v = cells_[1]->vertex(i);
    if (tri_.is_infinite(v)) continue;
    EXPECT_EQ(v->info().outside_cells, 1u);
    const auto* bucket = hash_.bucket(outside_.keyOf(v));
    ASSERT_NE(bucket, nullptr);
    EXPECT_EQ((*bucket)[v->info().hash_slot], v);
  }
  outside_.remove(cells_[1]);
  EXPECT_EQ(hash_.size(), 0u);
}

TEST(SteinerGridTest, GrowsByLayersAndCoversWithMargin) {
  SteinerGrid grid(10.0);
  const auto first = grid.coverPoint(Eigen::Vector3d(0, 0, 0), 2);
  EXPECT_EQ(first.size(), 6u * 6u * 6u);  // cells -2..2 need nodes -2..3
  EXPECT_TRUE(grid.coversCell(grid.cellOf(Eigen::Vector3d(0, 0, 0)), 2));
  EXPECT_TRUE(grid.coverPoint(Eigen::Vector3d(1, 1, 1), 2).empty());
  const auto more = grid.coverPoint(Eigen::Vector3d(25, 0, 0), 2);
  EXPECT_EQ(more.size(), 3u * 6u * 6u);  // three new x layers
  EXPECT_EQ(grid.nodeCount(), 9u * 6u * 6u);
  for (const auto& node : more) {
    const GridKey cell = grid.cellOf(node + Eigen::Vector3d::Constant(1e-6));
    EXPECT_GE(cell.i, 3);
  }
}

}  // namespace
}  // namespace terramesh::mesher::internal

// The visibility weights against the papers' formulas computed here, independently of the
// implementation: paths from CGAL's segment traverser (not the mesher's walk), and the votes of
// each ray cast the way the papers describe them (Romanoni & Matteucci 2015's inverse cone: W1 to
// every crossed cell, W2 to the face neighbours and W3 to the neighbours' neighbours of every
// crossed cell but the last; Litvinov & Lhuillier 2013: the number of rays crossing a cell).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <vector>

#include "cgal_types.h"
#include "map_state.h"
#include "visibility_tracer.h"

namespace terramesh::mesher::internal {
namespace {

using Votes = std::map<const Delaunay::Cell*, std::int64_t>;

/// A tiny triangulation (60 random points in a 6 m cube inside a lattice hull), two cameras and
/// rays from them to points, traced by the mesher's tracer.
class WeightFormula : public ::testing::Test {
 protected:
  void build(const MesherConfig& config) {
    state_ = std::make_unique<MapState>(config);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
    for (int i = 0; i < 60; ++i) {
      // One draw per statement: the order in which a call's arguments are evaluated is
      // unspecified (gcc goes right to left, clang left to right), and Point(coordinate(rng), ...)
      // gave each compiler a different scene, in which the first ray of clang's crosses only two
      // cells. z, y, x is the order gcc used, the scene the literal checks below were written on.
      const double z = coordinate(rng);
      const double y = coordinate(rng);
      const double x = coordinate(rng);
      const VertexHandle v = state_->tri.insert(Point(x, y, z));
      const std::uint32_t index = state_->registry.findOrCreatePoint(PointId{static_cast<std::uint64_t>(i)});
      state_->registry.point(index).vertex = v;
      points_.push_back(index);
    }
    for (int i = -1; i <= 1; ++i) {
      for (int j = -1; j <= 1; ++j) {
        for (int k = -1; k <= 1; ++k) state_->tri.insert(Point(6.0 * i, 6.0 * j, 6.0 * k));
      }
    }
    for (const Eigen::Vector3d& centre : {Eigen::Vector3d(-4.1, 0.3, 0.2), Eigen::Vector3d(0.2, -4.3, 1.1)}) {
      bool created = false;
      const std::uint32_t k = state_->registry.findOrCreateKeyframe(KeyframeId{keyframes_.size()}, created);
      state_->registry.keyframe(k).centre_W = centre;
      keyframes_.push_back(k);
    }
    tracer_ = std::make_unique<VisibilityTracer>(*state_);
  }

  /// Rays from both cameras to the first `count` points; several cross the same cells.
  std::vector<RayId> traceRays(std::size_t count) {
    std::vector<RayId> rays;
    for (std::uint32_t k : keyframes_) {
      for (std::size_t p = 0; p < count; ++p) {
        const RayId id = state_->rays.create(points_[p], k);
        state_->rays[id].flags = kRayNeedsTrace | kRayNewSegment;
        rays.push_back(id);
      }
    }
    WalkCounters counters;
    tracer_->trace(rays, counters);
    EXPECT_EQ(counters.fallbacks, 0u) << "the reference paths assume generic rays";
    return rays;
  }

  /// The cells CGAL's segment traverser crosses from the camera to the first cell at the point.
  std::vector<CellHandle> referencePath(RayId id) const {
    const Ray& ray = state_->rays[id];
    const VertexHandle target = state_->registry.point(ray.point).vertex;
    const Point camera = toPoint(state_->registry.keyframe(ray.keyframe).centre_W);
    std::vector<CellHandle> path;
    for (CellHandle cell : state_->tri.segment_traverser_cell_handles(camera, target->point())) {
      path.push_back(cell);
      if (cell->has_vertex(target)) break;
    }
    return path;
  }

  /// Expected weight of every cell, in the weights' units, from the votes of `rays`:
  /// each crossing gives `w1` to its cell; each crossing but the last of its ray (the apex of the
  /// inverse cone, at the point) gives `w2` to each face neighbour n of its cell and `w3` to each
  /// face neighbour of n other than the crossed cell. A cell spreads at most `cap` crossings
  /// (0: all of them).
  Votes handVotes(const std::vector<RayId>& rays, std::int64_t w1, std::int64_t w2, std::int64_t w3,
                  std::int64_t cap) const {
    Votes crossings, spreading, expected;
    std::map<const Delaunay::Cell*, CellHandle> handles;
    for (RayId id : rays) {
      const std::vector<CellHandle> path = referencePath(id);
      for (std::size_t i = 0; i < path.size(); ++i) {
        handles[&*path[i]] = path[i];
        ++crossings[&*path[i]];
        if (i + 1 < path.size()) ++spreading[&*path[i]];
      }
    }
    for (const auto& [cell, k] : crossings) expected[cell] += w1 * k;
    for (const auto& [cell, s] : spreading) {
      const std::int64_t spread = cap == 0 ? s : std::min(s, cap);
      const CellHandle x = handles[cell];
      for (int i = 0; i < 4; ++i) {
        const CellHandle n = x->neighbor(i);
        expected[&*n] += w2 * spread;
        for (int j = 0; j < 4; ++j) {
          if (n->neighbor(j) != x) expected[&*n->neighbor(j)] += w3 * spread;
        }
      }
    }
    return expected;
  }

  /// Cells whose stored weight (fixed point) differs from `expected` (weight units); also
  /// counts the cells with a non-zero expectation in `nonzero`.
  std::size_t mismatches(const Votes& expected, std::size_t& nonzero) const {
    std::size_t wrong = 0;
    nonzero = 0;
    for (auto c = state_->tri.all_cells_begin(); c != state_->tri.all_cells_end(); ++c) {
      const auto it = expected.find(&*c);
      const std::int64_t want = it == expected.end() ? 0 : it->second * WeightField::kFixedPointScale;
      nonzero += want != 0;
      if (c->info().weight != want) ++wrong;
    }
    return wrong;
  }

  std::unique_ptr<MapState> state_;
  std::unique_ptr<VisibilityTracer> tracer_;
  std::vector<std::uint32_t> points_;
  std::vector<std::uint32_t> keyframes_;
};

TEST_F(WeightFormula, InverseConeWeightsWithoutCapMatchTheVotesOfEachRay) {
  MesherConfig config = MesherConfig::forMode(MesherMode::kRomanoni15);
  ASSERT_EQ(config.spread_cap, 0) << "romanoni15 spreads every crossing, as its authors' code";
  config.weight_crossed = 10;  // the documented defaults, spelled out: the votes below use them
  config.weight_neighbour = 2;
  config.weight_second_neighbour = 1;
  build(config);
  const std::vector<RayId> rays = traceRays(20);
  std::size_t nonzero = 0;
  EXPECT_EQ(mismatches(handVotes(rays, 10, 2, 1, 0), nonzero), 0u);
  EXPECT_GT(nonzero, 100u);
  // Several rays cross the same cells, so the cap matters: the capped votes differ somewhere.
  std::size_t unused = 0;
  EXPECT_GT(mismatches(handVotes(rays, 10, 2, 1, 1), unused), 0u);
}

TEST_F(WeightFormula, CappedWeightsMatchTheCappedVotesAndWithdrawExactly) {
  MesherConfig config = MesherConfig::forMode(MesherMode::kProposed);
  ASSERT_EQ(config.spread_cap, 1);
  build(config);
  const std::vector<RayId> rays = traceRays(20);
  std::size_t nonzero = 0;
  EXPECT_EQ(mismatches(handVotes(rays, 10, 2, 1, 1), nonzero), 0u);
  EXPECT_GT(nonzero, 100u);

  // Withdraw every other ray: the weights are those of the remaining rays' votes.
  std::vector<RayId> withdrawn, kept;
  for (std::size_t i = 0; i < rays.size(); ++i) (i % 2 ? withdrawn : kept).push_back(rays[i]);
  tracer_->untrace(withdrawn);
  EXPECT_EQ(mismatches(handVotes(kept, 10, 2, 1, 1), nonzero), 0u);
  EXPECT_GT(nonzero, 50u);
}

TEST_F(WeightFormula, OneRayGivesW1OnItsPathAndW2W3AroundAllButItsApex) {
  MesherConfig config = MesherConfig::forMode(MesherMode::kRomanoni15);
  build(config);
  const std::vector<RayId> rays = traceRays(1);  // one ray from each camera
  const std::vector<RayId> one{rays.front()};
  tracer_->untrace({rays.back()});
  const std::vector<CellHandle> path = referencePath(one.front());
  ASSERT_GE(path.size(), 3u);
  // Literal values on this ray: the apex is crossed once and spreads nothing itself; it receives
  // W2 from its predecessor on the path (a face neighbour) and W3 for each path cell two steps
  // away through a face neighbour.
  const CellHandle apex = path.back();
  const CellHandle before = path[path.size() - 2];
  ASSERT_TRUE(apex->has_neighbor(before));
  std::int64_t second = 0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    for (int a = 0; a < 4; ++a) {
      const CellHandle n = apex->neighbor(a);
      for (int b = 0; b < 4; ++b) second += n->neighbor(b) == path[i] && path[i] != apex;
    }
  }
  std::int64_t first = 0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) first += apex->has_neighbor(path[i]);
  EXPECT_EQ(apex->info().weight, (10 * 1 + 2 * first + 1 * second) * WeightField::kFixedPointScale);
  std::size_t nonzero = 0;
  EXPECT_EQ(mismatches(handVotes(one, 10, 2, 1, 0), nonzero), 0u);
}

TEST_F(WeightFormula, Litvinov13WeightIsTheNumberOfRaysCrossingTheCell) {
  build(MesherConfig::forMode(MesherMode::kLitvinov13));
  const std::vector<RayId> rays = traceRays(20);
  // By hand: count, for every cell, the reference paths that contain it.
  std::map<const Delaunay::Cell*, std::int64_t> count;
  for (RayId id : rays) {
    for (const CellHandle& cell : referencePath(id)) ++count[&*cell];
  }
  std::size_t crossed = 0, wrong = 0, multiple = 0;
  for (auto c = state_->tri.all_cells_begin(); c != state_->tri.all_cells_end(); ++c) {
    const auto it = count.find(&*c);
    const std::int64_t rays_here = it == count.end() ? 0 : it->second;
    crossed += rays_here > 0;
    multiple += rays_here > 1;
    if (c->info().weight != rays_here * WeightField::kFixedPointScale) ++wrong;
    // Free space once any ray crosses it (threshold 0).
    if (state_->weights.isFree(c) != (rays_here > 0)) ++wrong;
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(crossed, 100u);
  EXPECT_GT(multiple, 20u) << "the count must be tested above one";
}

}  // namespace
}  // namespace terramesh::mesher::internal

// Start-goal pairs on the observed, connected part of a labelled truth
// (evaluation::pairsOnObservedTruth).
#include <gtest/gtest.h>

#include "datasets/triangle_bvh.h"
#include "evaluation/truth_pairs.h"
#include "pair_scene.h"

namespace terramesh::evaluation {
namespace {

TEST(TruthPairsTest, PairsLieOnTheObservedConnectedPartOnly) {
  const test::PairScene scene;
  const auto labels = test::labelled(scene);
  const datasets::TriangleBvh bvh(scene.truth.mesh);
  TruthPairsConfig config;
  config.count = 8;
  config.min_distance_m = 6;
  const TruthPairs drawn = pairsOnObservedTruth(labels, bvh, scene.cameras, config);
  ASSERT_EQ(drawn.pairs.size(), 8u);
  EXPECT_LT(drawn.observed, drawn.samples) << "road B is hidden behind the wall";
  EXPECT_EQ(drawn.component_samples, drawn.observed) << "road A is one piece";
  for (const ComparePair& pair : drawn.pairs) {
    for (const Eigen::Vector3d& p : {pair.start_W, pair.goal_W}) {
      EXPECT_LE(p.x(), 20.0) << "an end on the unobserved road B: " << p.transpose();
      EXPECT_NEAR(p.z(), 0.0, 1e-9);
    }
    const double straight = (pair.goal_W - pair.start_W).norm();
    EXPECT_GE(straight, config.min_distance_m);
    // On an open flat road the shortest way is the straight line; the sample graph zig-zags a bit.
    EXPECT_GE(pair.truth_length_m, straight - 1e-9);
    EXPECT_LE(pair.truth_length_m, 1.1 * straight);
  }
  const TruthPairs again = pairsOnObservedTruth(labels, bvh, scene.cameras, config);
  ASSERT_EQ(again.pairs.size(), drawn.pairs.size());
  for (std::size_t i = 0; i < drawn.pairs.size(); ++i) EXPECT_EQ(again.pairs[i].start_W, drawn.pairs[i].start_W);
}

}  // namespace
}  // namespace terramesh::evaluation

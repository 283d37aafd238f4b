// The layer stages: their order follows what they declare they read and write, a broken stage set
// is refused, and every layer of the registry has exactly one stage that writes it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "layer_stages.h"
#include "traversability/layer_registry.h"

namespace terramesh::traversability::internal {
namespace {

StageDeclaration stage(std::string name, std::vector<std::string> reads, std::vector<std::string> writes) {
  return {std::move(name), std::move(reads), std::move(writes), {}};
}

std::vector<std::string> namesInOrder(const std::vector<StageDeclaration>& stages) {
  std::vector<std::string> names;
  for (std::size_t i : stageOrder(stages)) names.push_back(stages[i].name);
  return names;
}

TEST(StageOrder, EachStageRunsAfterTheWritersOfWhatItReads) {
  const std::vector<StageDeclaration> stages = {
      stage("class", {"slope", "distance"}, {"class"}),
      stage("inflation", {"lethal", "geometry"}, {"distance"}),
      stage("footprint", {"evidence", "geometry"}, {"slope", "lethal"}),
      stage("evidence", {"geometry"}, {"evidence"}),
  };
  EXPECT_EQ(namesInOrder(stages), (std::vector<std::string>{"evidence", "footprint", "inflation", "class"}));
}

TEST(StageOrder, IndependentStagesKeepTheirGivenOrder) {
  const std::vector<StageDeclaration> stages = {
      stage("b", {"geometry"}, {"y"}),
      stage("c", {"x", "y"}, {"z"}),
      stage("a", {"geometry"}, {"x"}),
  };
  EXPECT_EQ(namesInOrder(stages), (std::vector<std::string>{"b", "a", "c"}));
}

/// The message of the std::logic_error stageOrder throws for `stages` ("" if it throws none).
std::string refusal(const std::vector<StageDeclaration>& stages) {
  try {
    stageOrder(stages);
  } catch (const std::logic_error& e) {
    return e.what();
  }
  return "";
}

TEST(StageOrder, RefusesTwoWritersOfOneDatum) {
  const std::string message = refusal({stage("a", {}, {"x"}), stage("b", {}, {"x"})});
  EXPECT_NE(message.find("'x' is written by stages 'a' and 'b'"), std::string::npos) << message;
}

TEST(StageOrder, RefusesACycleAndNamesItsStages) {
  const std::string message = refusal({
      stage("free", {"geometry"}, {"w"}),
      stage("a", {"y"}, {"x"}),
      stage("b", {"x"}, {"y"}),
  });
  EXPECT_NE(message.find("'a', 'b' form a cycle"), std::string::npos) << message;
}

TEST(LayerPipeline, TheShippedStagesRunInDependencyOrderAndWriteEveryLayerOnce) {
  RobotProfile profile;  // the defaults: a disc footprint
  profile.name = "default";
  profile.validate();
  LayerComputer computer(profile);
  FootprintStage* footprint = nullptr;
  const LayerPipeline pipeline = makeLayerPipeline(computer, profile, Eigen::Matrix3d::Identity(), 1.0, footprint);
  ASSERT_NE(footprint, nullptr);

  std::vector<std::string> order;
  std::map<std::string, std::string> writer;
  std::set<std::string> written_before;
  // What no stage writes: the mesh's faces and counts, the drive, the unconfirmed points.
  const std::set<std::string> inputs = {"geometry",        "rays",  "front_crossings",   "back_crossings", "back_depth",
                                        "driven_vertices", "underside_vertices", "drive", "unconfirmed_points"};
  for (const auto& s : pipeline.stages()) {
    const StageDeclaration& d = s->declaration();
    order.push_back(d.name);
    for (const std::string& datum : d.reads) {
      EXPECT_TRUE(inputs.count(datum) != 0 || written_before.count(datum) != 0)
          << d.name << " reads " << datum << " before any stage writes it";
    }
    for (const std::string& datum : d.writes) {
      EXPECT_TRUE(writer.emplace(datum, d.name).second) << datum << " is written twice";
      EXPECT_EQ(inputs.count(datum), 0u) << datum;
      written_before.insert(datum);
    }
  }
  EXPECT_EQ(order, (std::vector<std::string>{"evidence", "footprint", "inflation", "class"}));
  for (const LayerInfo& layer : faceLayerRegistry()) {
    const bool from_mesh = inputs.count(layer.name) != 0;
    EXPECT_TRUE(from_mesh || writer.count(layer.name) != 0) << "no stage writes the layer " << layer.name;
  }
  // The declared reach is the one each stage searches: the footprint's reaches its largest
  // faces' obstacles over driven ground, the inflation's the profile's radius.
  EXPECT_DOUBLE_EQ(pipeline.stages()[1]->declaration().reach.metres, std::sqrt(2.0) * computer.maxReachM());
  EXPECT_DOUBLE_EQ(pipeline.stages()[2]->declaration().reach.metres, profile.inflation_radius_m);
  EXPECT_EQ(pipeline.stages()[3]->declaration().reach.kind, StageReach::Kind::kFace);
}

}  // namespace
}  // namespace terramesh::traversability::internal

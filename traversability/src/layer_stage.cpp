#include "layer_stage.h"

#include <map>
#include <stdexcept>

namespace terramesh::traversability::internal {

void StageChanges::clear() {
  added.clear();
  recounted.clear();
  edge_neighbours.clear();
  lid_neighbours.clear();
  shapes.clear();
  lethal_changes.clear();
  reevidenced.clear();
  reobserved.clear();
  rejudged.clear();
  redistanced.clear();
  classified = 0;
}

std::vector<std::size_t> stageOrder(const std::vector<StageDeclaration>& stages) {
  std::map<std::string, std::size_t> writer;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    for (const std::string& datum : stages[i].writes) {
      const auto [it, inserted] = writer.emplace(datum, i);
      if (!inserted) {
        throw std::logic_error("stageOrder: '" + datum + "' is written by stages '" + stages[it->second].name +
                               "' and '" + stages[i].name + "'");
      }
    }
  }
  // Repeatedly take the first stage (in the given order) whose inputs' writers have all run.
  std::vector<char> done(stages.size(), 0);
  std::vector<std::size_t> order;
  while (order.size() < stages.size()) {
    bool progressed = false;
    for (std::size_t i = 0; i < stages.size() && !progressed; ++i) {
      if (done[i]) continue;
      bool ready = true;
      for (const std::string& datum : stages[i].reads) {
        const auto it = writer.find(datum);
        ready = ready && (it == writer.end() || it->second == i || done[it->second]);
      }
      if (!ready) continue;
      done[i] = 1;
      order.push_back(i);
      progressed = true;
    }
    if (!progressed) {
      std::string waiting;
      for (std::size_t i = 0; i < stages.size(); ++i) {
        if (!done[i]) waiting += (waiting.empty() ? "'" : ", '") + stages[i].name + "'";
      }
      throw std::logic_error("stageOrder: the reads of stages " + waiting + " form a cycle");
    }
  }
  return order;
}

LayerPipeline::LayerPipeline(std::vector<std::unique_ptr<LayerStage>> stages) {
  std::vector<StageDeclaration> declarations;
  for (const std::unique_ptr<LayerStage>& stage : stages) declarations.push_back(stage->declaration());
  for (std::size_t i : stageOrder(declarations)) stages_.push_back(std::move(stages[i]));
}

void LayerPipeline::resize(std::size_t slots) {
  for (const std::unique_ptr<LayerStage>& stage : stages_) stage->resize(slots);
}

void LayerPipeline::removing(const SurfaceStore& store, Slot s, StageChanges& changes) {
  for (const std::unique_ptr<LayerStage>& stage : stages_) stage->removing(store, s, changes);
}

void LayerPipeline::computeAll(SurfaceStore& store) {
  for (const std::unique_ptr<LayerStage>& stage : stages_) stage->computeAll(store);
}

void LayerPipeline::update(SurfaceStore& store, StageChanges& changes) {
  for (const std::unique_ptr<LayerStage>& stage : stages_) stage->update(store, changes);
}

}  // namespace terramesh::traversability::internal

// The evidence and class stages, and the pipeline of all four (layer_stages.h). The footprint
// and inflation stages have files of their own.
#include "layer_stages.h"

#include <algorithm>

namespace terramesh::traversability::internal {

void SlotMarks::next() {
  if (++epoch_ == 0) {
    std::fill(mark_.begin(), mark_.end(), 0u);
    epoch_ = 1;
  }
}

EvidenceStage::EvidenceStage(const LayerComputer& computer)
    : computer_(computer),
      declaration_{"evidence",
                   {"geometry", "front_crossings", "back_crossings", "back_depth", "driven_vertices",
                    "underside_vertices"},
                   {"evidence", "height_uncertainty_m"},
                   {StageReach::Kind::kVertexNeighbours, 0.0}} {}

void EvidenceStage::computeAll(SurfaceStore& store) {
  for (Slot s = 0; s < store.slotCount(); ++s) {
    if (store.face(s).alive) computer_.setEvidence(store, s);
  }
}

void EvidenceStage::changed(const SurfaceStore& store, Slot s, StageChanges& changes) const {
  changes.shapes.push_back(changeOf(store, s));
  changes.lethal_changes.push_back(store.centroid(s));
}

void EvidenceStage::update(SurfaceStore& store, StageChanges& changes) {
  // The faces added are changes already; their evidence reads the neighbours they have now.
  for (Slot s : changes.added) computer_.setEvidence(store, s);
  // A face whose evidence changes with its counts (rays now cross the space in front of it, or
  // no longer do) changes what the faces around it may stand on or meet.
  for (Slot s : changes.recounted) {
    if (!store.face(s).alive) continue;
    if (computer_.setEvidence(store, s)) {
      changes.reevidenced.push_back(s);
      changed(store, s, changes);
    } else {
      changes.reobserved.push_back(s);
    }
  }
  // A possible step's relief reads its edge neighbours' vertices.
  for (Slot s : changes.edge_neighbours) {
    if (!store.face(s).alive) continue;
    if (computer_.evidenceReadsNeighbours(store.face(s)) && computer_.setEvidence(store, s)) changed(store, s, changes);
  }
  // A face's relief reads the depth of the lids around its vertices.
  for (Slot s : changes.lid_neighbours) {
    if (store.face(s).alive && computer_.setEvidence(store, s)) changed(store, s, changes);
  }
}

ClassStage::ClassStage(const LayerComputer& computer)
    : computer_(computer),
      declaration_{"class",
                   {"evidence", "height_uncertainty_m", "rays", "slope_deg", "step_m", "roughness_m", "contact",
                    "clearance_m", "heading_fits", "footprint_fits", "lethal_distance_m"},
                   {"class", "cost", "reasons"},
                   {StageReach::Kind::kFace, 0.0}} {}

void ClassStage::computeAll(SurfaceStore& store) {
  for (Slot s = 0; s < store.slotCount(); ++s) {
    if (store.face(s).alive) computer_.classify(store.face(s));
  }
}

void ClassStage::update(SurfaceStore& store, StageChanges& changes) {
  marks_.next();
  for (const std::vector<Slot>* list : {&changes.rejudged, &changes.redistanced}) {
    for (Slot s : *list) {
      if (!store.face(s).alive || !marks_.mark(s)) continue;
      computer_.classify(store.face(s));
      ++changes.classified;
    }
  }
}

LayerPipeline makeLayerPipeline(LayerComputer& computer, const RobotProfile& profile, const Eigen::Matrix3d& R_L_W,
                                double metres_per_unit, FootprintStage*& footprint) {
  auto footprint_stage = std::make_unique<FootprintStage>(computer, profile, R_L_W, metres_per_unit);
  footprint = footprint_stage.get();
  std::vector<std::unique_ptr<LayerStage>> stages;
  stages.push_back(std::make_unique<EvidenceStage>(computer));
  stages.push_back(std::move(footprint_stage));
  stages.push_back(std::make_unique<InflationStage>(profile.inflation_radius_m));
  stages.push_back(std::make_unique<ClassStage>(computer));
  return LayerPipeline(std::move(stages));
}

}  // namespace terramesh::traversability::internal

// The footprint stage (layer_stages.h): the local layers of every face a change may reach.
#include <cmath>

#include "layer_stages.h"

namespace terramesh::traversability::internal {

FootprintStage::FootprintStage(LayerComputer& computer, const RobotProfile& profile, const Eigen::Matrix3d& R_L_W,
                               double metres_per_unit)
    : computer_(computer),
      min_rays_(static_cast<std::uint32_t>(profile.min_rays)),
      // Driven ground is read up to a box of half-side the obstacle reach (readsDrivenGround).
      declaration_{"footprint",
                   {"geometry", "rays", "evidence", "height_uncertainty_m", "drive", "unconfirmed_points"},
                   {"slope_deg", "step_m", "roughness_m", "contact", "contact_best", "clearance_m", "heading_fits",
                    "footprint_fits", "lethal"},
                   {StageReach::Kind::kHorizontal, std::sqrt(2.0) * computer.maxReachM()}},
      unconfirmed_(R_L_W, metres_per_unit, computer.unconfirmedReachM() + 1e-3) {
  computer_.setUnconfirmedPoints(&unconfirmed_);
}

bool FootprintStage::replaceUnconfirmed(const std::vector<mesher::UnconfirmedPoint>& points) {
  const std::size_t before = point_changes_.size();
  unconfirmed_.replace(points, point_changes_);
  return point_changes_.size() != before;
}

bool FootprintStage::applyUnconfirmed(const mesher::UnconfirmedChanges& changes) {
  const std::size_t before = point_changes_.size();
  unconfirmed_.apply(changes, point_changes_);
  return point_changes_.size() != before;
}

void FootprintStage::resize(std::size_t slots) {
  window_.resize(slots);
  marks_.resize(slots);
}

bool FootprintStage::isLethal(const StoredFace& f) const {
  const bool known = !f.steiner && f.rays >= min_rays_;
  return known && computer_.lethal(f);
}

void FootprintStage::judge(SurfaceStore& store, Slot s) const {
  computer_.computeLocal(store, s);
  StoredFace& f = store.face(s);
  f.lethal = isLethal(f);
}

void FootprintStage::computeAll(SurfaceStore& store) {
  point_changes_.clear();
  for (Slot s = 0; s < store.slotCount(); ++s) {
    if (store.face(s).alive) window_[s] = computer_.groundWindow(store.face(s));
  }
  for (Slot s : store.aliveSlotsByLocality()) judge(store, s);
}

void FootprintStage::markNearUnconfirmedChanges(const SurfaceStore& store, std::vector<Slot>& dirty) {
  const double reach = computer_.unconfirmedReachM() * (1 + 1e-9) + 1e-6;
  const Eigen::Vector2d r(reach, reach);
  for (const Eigen::Vector3d& p : point_changes_) {
    store.forEachInBox(p.head<2>() - r, p.head<2>() + r, [&](Slot s) {
      if (marks_.marked(s)) return;
      // The grid's cells reach beyond the box: a face whose own box lies farther than the reach
      // cannot hold the point in its body (the dense bounds first, the face after).
      const FaceBounds& b = store.bounds(s);
      if ((p.head<2>().array() < b.box_min.array() - reach).any() ||
          (p.head<2>().array() > b.box_max.array() + reach).any()) {
        return;
      }
      if (computer_.unconfirmedInBody(store.face(s), p)) markDirty(s, dirty);
    });
  }
  point_changes_.clear();
}

void FootprintStage::update(SurfaceStore& store, StageChanges& changes) {
  for (Slot s : changes.added) window_[s] = computer_.groundWindow(store.face(s));
  const double reach = computer_.maxReachM() * (1 + 1e-9) + 1e-6;
  marks_.next();
  std::vector<Slot>& dirty = changes.rejudged;
  for (Slot s : changes.added) markDirty(s, dirty);
  for (Slot s : changes.reevidenced) markDirty(s, dirty);
  const std::size_t added_dirty = dirty.size();
  for (Slot s : changes.edge_neighbours) {
    if (store.face(s).alive) markDirty(s, dirty);
  }
  // Every face whose footprint disc or clearance column meets a changed face that can be its
  // ground, an obstacle in its footprint or its ceiling.
  for (const Change& change : changes.shapes) {
    const Projection& p = change.projection;
    const double box = change.driven ? std::sqrt(2.0) * reach : reach;  // see readsDrivenGround
    const Eigen::Vector2d r(box, box);
    store.forEachCentroidInBox(p.lo - r, p.hi + r, [&](Slot s) {
      if (marks_.marked(s)) return;
      const Eigen::Vector3d& c = store.centroid(s);
      const double distance = distanceToTriangle(c.head<2>(), p);
      if ((distance <= reach &&
           computer_.mayAffect(c, window_[s], change.bounds, change.sampleable, change.span_m, distance)) ||
          (change.driven && distance <= box &&
           computer_.readsDrivenGround(store.face(s), window_[s], change.bounds, distance)) ||
          computer_.readsColumns(store.face(s), change.sampleable, distance)) {
        markDirty(s, dirty);
      }
    });
  }
  markNearUnconfirmedChanges(store, dirty);
  // Judged in an order that walks the plane: on a dense mesh (LiDAR) the order of the changes
  // scatters over the map, and a face's footprint reads hundreds of nearby faces.
  store.sortByLocality(dirty, 0, added_dirty);
  store.sortByLocality(dirty, added_dirty, dirty.size());
  // The faces added come first; they are changes of the inflation already.
  for (std::size_t i = 0; i < dirty.size(); ++i) {
    const Slot s = dirty[i];
    const bool was_lethal = store.face(s).lethal;
    judge(store, s);
    if (i >= added_dirty && store.face(s).lethal != was_lethal) changes.lethal_changes.push_back(store.centroid(s));
  }
  // Counts alone can make a face known or unknown (min_rays).
  for (Slot s : changes.reobserved) {
    if (marks_.marked(s)) continue;
    StoredFace& f = store.face(s);
    const bool was_lethal = f.lethal;
    f.lethal = isLethal(f);
    if (f.lethal != was_lethal) changes.lethal_changes.push_back(f.centroid_L);
    markDirty(s, dirty);
  }
}

}  // namespace terramesh::traversability::internal

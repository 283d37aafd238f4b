#pragma once
// The four stages of a traversability map's layers (docs/traversability.md, "Stages"):
// evidence -> footprint -> inflation -> class, each re-judging what the changes before it reach.
// Internal.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/graph_search.h"
#include "layer_computer.h"
#include "layer_stage.h"
#include "mesher/mesher.h"
#include "traversability/robot_profile.h"
#include "unconfirmed_points.h"

namespace terramesh::traversability::internal {

/// Per-slot marks with epochs: marking a set costs nothing to clear.
class SlotMarks {
 public:
  void resize(std::size_t slots) { mark_.resize(slots, 0); }
  /// Starts a new set (empty).
  void next();
  /// Marks s; false if it was marked in this set already.
  bool mark(Slot s) {
    if (mark_[s] == epoch_) return false;
    mark_[s] = epoch_;
    return true;
  }
  bool marked(Slot s) const { return mark_[s] == epoch_; }

 private:
  std::vector<std::uint32_t> mark_;
  std::uint32_t epoch_ = 0;
};

/// What supports each face: its evidence and height uncertainty bound (LayerComputer::setEvidence).
/// Reads the face's geometry, its observation and its edge neighbours' vertices (a possible
/// step's rise may be confirmed beyond it).
class EvidenceStage final : public LayerStage {
 public:
  explicit EvidenceStage(const LayerComputer& computer);
  const StageDeclaration& declaration() const override { return declaration_; }
  void computeAll(SurfaceStore& store) override;
  /// Faces added, faces whose observation counts changed, and the edge neighbours of faces added
  /// and removed whose evidence reads them. Appends the faces whose evidence changed.
  void update(SurfaceStore& store, StageChanges& changes) override;

 private:
  void changed(const SurfaceStore& store, Slot s, StageChanges& changes) const;

  const LayerComputer& computer_;
  StageDeclaration declaration_;
};

/// The layers the footprint decides (slope, step, roughness, contact, clearance, the headings
/// that fit) and whether the face is lethal (LayerComputer::computeLocal): reads the ground,
/// obstacles and ceilings within the footprint's reach, with their evidence, and the unconfirmed
/// points (which this stage keeps).
class FootprintStage final : public LayerStage {
 public:
  FootprintStage(LayerComputer& computer, const RobotProfile& profile, const Eigen::Matrix3d& R_L_W,
                 double metres_per_unit);
  const StageDeclaration& declaration() const override { return declaration_; }
  void resize(std::size_t slots) override;
  void computeAll(SurfaceStore& store) override;
  /// Every face whose footprint or clearance column may meet a face added, removed or re-judged
  /// by its evidence (LayerComputer::mayAffect, readsDrivenGround), or whose body holds an
  /// unconfirmed point that changed; the faces whose counts alone changed get their lethal flag
  /// again. Appends them, and the faces whose lethal flag changed.
  void update(SurfaceStore& store, StageChanges& changes) override;

  /// Replaces the unconfirmed points; the faces they reach are judged by the next update (or all
  /// of them by computeAll). Returns whether any point changed.
  bool replaceUnconfirmed(const std::vector<mesher::UnconfirmedPoint>& points);
  /// The same from the changes since the last set (UnconfirmedPoints::apply).
  bool applyUnconfirmed(const mesher::UnconfirmedChanges& changes);
  std::size_t unconfirmedCount() const { return unconfirmed_.size(); }

 private:
  /// Local layers and the lethal flag of face s.
  void judge(SurfaceStore& store, Slot s) const;
  /// Known and lethal, from the face's current local layers.
  bool isLethal(const StoredFace& f) const;
  /// Marks (into `dirty`) every face whose body holds, or held, an unconfirmed point that changed
  /// since the last update (LayerComputer::unconfirmedInBody), and forgets those changes.
  void markNearUnconfirmedChanges(const SurfaceStore& store, std::vector<Slot>& dirty);
  /// Appends s to `dirty` unless this update marked it already.
  void markDirty(Slot s, std::vector<Slot>& dirty) {
    if (marks_.mark(s)) dirty.push_back(s);
  }

  LayerComputer& computer_;
  std::uint32_t min_rays_;
  StageDeclaration declaration_;
  /// Per slot, the height window of the face's ground candidates (LayerComputer::groundWindow).
  std::vector<LayerComputer::GroundWindow> window_;
  SlotMarks marks_;
  /// The mesher's points not in the mesh (possible obstacles), and the positions (L) where they
  /// changed since the last update.
  UnconfirmedPoints unconfirmed_;
  std::vector<Eigen::Vector3d> point_changes_;
};

/// The distance along the surface (between face centroids, across edges) to the nearest lethal
/// face, up to the inflation radius (`lethal_distance_m`; beyond it, infinite).
class InflationStage final : public LayerStage {
 public:
  explicit InflationStage(double inflation_radius_m);
  const StageDeclaration& declaration() const override { return declaration_; }
  void resize(std::size_t slots) override;
  /// A face removed at a finite distance is a change the faces around it must see.
  void removing(const SurfaceStore& store, Slot s, StageChanges& changes) override;
  void computeAll(SurfaceStore& store) override;
  /// The faces within the inflation radius (straight-line, a lower bound of the geodesic one) of
  /// a change, seeded by their lethal faces and the unchanged distances of the faces around them.
  void update(SurfaceStore& store, StageChanges& changes) override;

 private:
  /// Dijkstra from the heap's faces, relaxing only faces for which `inside` holds.
  template <class Inside>
  void dijkstra(const SurfaceStore& store, Inside&& inside);
  double edgeM(const SurfaceStore& store, Slot a, Slot b) const { return (store.centroid(a) - store.centroid(b)).norm(); }

  double radius_m_;
  StageDeclaration declaration_;
  std::vector<double> distance_;  ///< per slot, metres along the surface to the nearest lethal face
  SlotMarks marks_;
  std::vector<Slot> scratch_;
  /// The heap, kept between updates for its storage.
  graph::CostHeap heap_;
};

/// The class, cost and reasons of a face from its own layers (LayerComputer::classify).
class ClassStage final : public LayerStage {
 public:
  explicit ClassStage(const LayerComputer& computer);
  const StageDeclaration& declaration() const override { return declaration_; }
  void resize(std::size_t slots) override { marks_.resize(slots); }
  void computeAll(SurfaceStore& store) override;
  /// The faces judged again or measured again by the stages before it, each once.
  void update(SurfaceStore& store, StageChanges& changes) override;

 private:
  const LayerComputer& computer_;
  StageDeclaration declaration_;
  SlotMarks marks_;
};

/// The stages of `profile`'s layers, in their dependency order. The computer must outlive them;
/// `footprint` receives the footprint stage (for its unconfirmed points).
LayerPipeline makeLayerPipeline(LayerComputer& computer, const RobotProfile& profile, const Eigen::Matrix3d& R_L_W,
                                double metres_per_unit, FootprintStage*& footprint);

}  // namespace terramesh::traversability::internal

#pragma once
// The layer computation as stages: small classes that each declare what they read and write and
// how far a change travels, run in the order of their dependency graph (LayerPipeline). Updates
// travel between the stages as lists of the faces that changed (StageChanges). Internal.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "face_projection.h"
#include "surface_store.h"

namespace terramesh::traversability::internal {

/// How far a change of what a stage reads travels: which faces it must judge again.
struct StageReach {
  enum class Kind : std::uint8_t {
    kFace,            ///< the face itself
    kEdgeNeighbours,  ///< the face and the faces sharing an edge with it
    kVertexNeighbours,  ///< the face and the faces sharing a vertex with it
    kHorizontal,      ///< faces within `metres` in the horizontal plane (a footprint, a column)
    kGeodesic,        ///< faces within `metres` along the surface (an inflation)
  };
  Kind kind = Kind::kFace;
  double metres = 0;
};

/// What a stage declares. Names are the layer registry's where the datum is a layer
/// (`slope_deg`, `evidence`), else the store's (`geometry`, `lethal`, `class`). A name that no
/// stage writes is an input from the mesh (`geometry`, `rays`) or from outside the mesh (`drive`,
/// `unconfirmed_points`).
struct StageDeclaration {
  std::string name;
  std::vector<std::string> reads;   ///< of the face, and of the faces within the reach
  std::vector<std::string> writes;  ///< of the face
  StageReach reach;
};

/// What one update changed, as it travels through the stages: the store update fills the first
/// block, each stage reads what the writers of its inputs appended and appends its own. Kept
/// between updates for the lists' memory.
struct StageChanges {
  // Filled by the store update:
  std::vector<Slot> added;            ///< faces added
  std::vector<Slot> recounted;        ///< faces kept whose observation counts changed
  std::vector<Slot> edge_neighbours;  ///< of the faces added and removed (repeats and dead ones possible)
  /// Faces sharing a vertex with a face whose void (LayerComputer::vertexVoidM: a lid's over a
  /// rim, a fold's) changed: such a face added or removed, or a face kept whose counts made it one
  /// or changed its depth (repeats and dead ones possible).
  std::vector<Slot> lid_neighbours;
  /// Faces added and removed (as they were), and faces whose evidence changed: where footprints
  /// that may stand on, meet or sit under them are.
  std::vector<Change> shapes;
  /// Centroids (L) around which a face's distance to the nearest lethal face may have changed:
  /// faces added, removed at a finite distance, judged lethal or no longer, or whose evidence
  /// changed.
  std::vector<Eigen::Vector3d> lethal_changes;
  // Appended by the stages:
  std::vector<Slot> reevidenced;  ///< recounted faces whose evidence changed
  std::vector<Slot> reobserved;   ///< recounted faces whose evidence did not
  std::vector<Slot> rejudged;     ///< faces whose local layers or lethal flag were judged again
  std::vector<Slot> redistanced;  ///< faces whose distance to the nearest lethal face was measured again
  std::size_t classified = 0;     ///< faces classified again

  void clear();
};

/// One stage of the layer computation. Its declaration is fixed at construction.
class LayerStage {
 public:
  virtual ~LayerStage() = default;
  virtual const StageDeclaration& declaration() const = 0;
  /// The store now has `slots` slots: per-slot state follows.
  virtual void resize(std::size_t slots) { (void)slots; }
  /// Face s is about to leave the store (its data still readable): forget it, and append what its
  /// leaving changes for the stages after this one.
  virtual void removing(const SurfaceStore& store, Slot s, StageChanges& changes) {
    (void)store;
    (void)s;
    (void)changes;
  }
  /// Judges every live face from scratch (the store was just filled).
  virtual void computeAll(SurfaceStore& store) = 0;
  /// Judges again the faces that `changes` reach, and appends what that changed.
  virtual void update(SurfaceStore& store, StageChanges& changes) = 0;
};

/// The order in which stages run: each after the writers of what it reads, stages independent of
/// each other in their given order. @throw std::logic_error if two stages write the same datum
/// or the stages' reads form a cycle.
std::vector<std::size_t> stageOrder(const std::vector<StageDeclaration>& stages);

/// Stages run in their dependency order (stageOrder).
class LayerPipeline {
 public:
  /// @throw std::logic_error as stageOrder.
  explicit LayerPipeline(std::vector<std::unique_ptr<LayerStage>> stages);

  /// The stages, in the order they run.
  const std::vector<std::unique_ptr<LayerStage>>& stages() const { return stages_; }

  void resize(std::size_t slots);
  void removing(const SurfaceStore& store, Slot s, StageChanges& changes);
  void computeAll(SurfaceStore& store);
  void update(SurfaceStore& store, StageChanges& changes);

 private:
  std::vector<std::unique_ptr<LayerStage>> stages_;
};

}  // namespace terramesh::traversability::internal

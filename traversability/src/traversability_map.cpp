#include "traversability/traversability_map.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "common/graph_search.h"
#include "common/plan_frame.h"
#include "face_projection.h"
#include "layer_computer.h"
#include "surface_store.h"
#include "unconfirmed_points.h"

namespace terramesh::traversability {
namespace {

using internal::Change;
using internal::Projection;
using internal::Slot;
using internal::StoredFace;
using internal::SurfaceStore;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Rotation taking map-frame directions into L, where up_W becomes +z.
Eigen::Matrix3d levelRotation(const Eigen::Vector3d& up_W) {
  const geometry::PlanFrame frame = geometry::planFrame(up_W.normalized());
  Eigen::Matrix3d R;
  R.row(0) = frame.e1.transpose();
  R.row(1) = frame.e2.transpose();
  R.row(2) = frame.up.transpose();
  return R;
}

/// Grid cell of the horizontal index: about half the footprint, so a footprint query reads a few
/// cells and a point query a short list.
double gridCellM(const RobotProfile& profile) {
  return std::clamp(profile.footprintCircumradiusM(), 1.0, 4.0);
}

/// Cell of the grid of face centroids (the queries "faces whose centroid is within reach of a
/// change"): small enough that a query reads few faces it must reject, large enough that it reads
/// few cells.
double centroidCellM(const RobotProfile& profile) {
  return std::clamp(profile.footprintCircumradiusM(), 1.0, 4.0);
}

/// Whether a stored face has exactly the vertices (same order), positions and Steiner flag of
/// `face`: then replacing it would change no layer but its own observation count.
bool sameGeometry(const StoredFace& stored, const mesher::SurfaceFace& face) {
  bool steiner = face.touches_steiner;
  for (const mesher::VertexKey& v : face.vertices) steiner = steiner || v.steiner;
  return stored.vertices == face.vertices && stored.positions_W == face.positions_W && stored.steiner == steiner;
}

}  // namespace

class TraversabilityMap::Impl {
 public:
  Impl(const RobotProfile& profile, const MapFrame& frame)
      : profile_(profile),
        frame_(frame),
        computer_(profile),
        store_(levelRotation(frame.up_W), frame.metres_per_unit, gridCellM(profile), centroidCellM(profile)),
        unconfirmed_(levelRotation(frame.up_W), frame.metres_per_unit, computer_.unconfirmedReachM() + 1e-3) {
    computer_.setUnconfirmedPoints(&unconfirmed_);
  }

  /// Replaces the unconfirmed points; the faces they reach are re-judged by the next apply()
  /// (or all of them by reset()). Returns whether any point changed.
  bool replaceUnconfirmed(const std::vector<mesher::UnconfirmedPoint>& points) {
    const std::size_t before = point_changes_.size();
    unconfirmed_.replace(points, point_changes_);
    return point_changes_.size() != before;
  }
  std::size_t unconfirmedCount() const { return unconfirmed_.size(); }
  void setDrivePoses(DrivePoseLookup lookup) { drive_poses_ = std::move(lookup); }

  LayerUpdateStats reset(const std::vector<mesher::SurfaceFace>& faces) {
    const auto start = std::chrono::steady_clock::now();
    point_changes_.clear();
    store_.clear();
    distance_.clear();
    lethal_.clear();
    for (const mesher::SurfaceFace& face : faces) store_.setDrive(store_.add(face), drive_poses_);
    grow();
    std::vector<Slot> all;
    for (Slot s = 0; s < store_.slotCount(); ++s) {
      if (!store_.face(s).alive) continue;
      all.push_back(s);
      computer_.setEvidence(store_, s);
      window_[s] = computer_.groundWindow(store_.face(s));
    }
    for (Slot s : all) computeLocalAndLethal(s);
    fullInflation();
    for (Slot s : all) finish(s);
    LayerUpdateStats stats;
    stats.faces_added = all.size();
    stats.faces_recomputed = all.size();
    stats.faces_total = store_.size();
    stats.full_rebuild = true;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
  }

  /// Face s as a change (added, removed or re-judged).
  Change changeOf(Slot s) const {
    const internal::SampleGeometry& g = store_.geometry(s);
    return {internal::projectionOf(store_.face(s)), store_.bounds(s), g.sampleable, g.sampleable && g.driven};
  }

  /// The first step of apply(): removes and adds the delta's faces and re-reads the observation
  /// counts of churned faces and of `around`. Fills the scratch lists apply() reads: change
  /// points, changed faces, edge neighbours of the faces added and removed, re-observed and
  /// re-evidenced faces, faces added.
  void replaceFaces(const mesher::SurfaceDelta& delta, const std::vector<mesher::SurfaceFace>& around,
                    LayerUpdateStats& stats) {
    // Centroids (L) of the changes the inflation must see: faces added, faces removed that were
    // within the inflation radius of a lethal face (a face at no finite distance lies on no
    // shortest path, so removing it changes no distance), faces re-judged lethal or not.
    std::vector<Eigen::Vector3d>& change_points = change_points_;
    change_points.clear();
    std::vector<Change>& changed = changed_;  // the faces added and removed
    changed.clear();
    std::vector<Slot>& edge_neighbours = edge_neighbours_;  // of the faces added and removed
    edge_neighbours.clear();
    const auto removeKey = [&](const mesher::FaceKey& key) {
      const std::optional<Slot> slot = store_.find(key);
      if (!slot) return false;
      const bool had_distance = std::isfinite(distance_[*slot]);
      changed.push_back(changeOf(*slot));
      if (had_distance) change_points.push_back(store_.centroid(*slot));
      // Its edge neighbours' rise confirmation read its vertices (LayerComputer::riseConfirmed).
      store_.neighbours(*slot, scratch_neighbours_);
      edge_neighbours.insert(edge_neighbours.end(), scratch_neighbours_.begin(), scratch_neighbours_.end());
      lethal_[*slot] = 0;
      distance_[*slot] = kInf;
      store_.removeSlot(*slot);
      return true;
    };
    // Churn: a face removed and re-added with the same vertices and positions changes nothing
    // but (maybe) its observation counts, which are re-read like the counts of `around`. A face
    // whose evidence changes with them (rays now cross the space in front of it, or no longer do)
    // changes what the faces around it may stand on or meet: it counts as a change.
    std::vector<Slot>& reobserved = reobserved_;
    reobserved.clear();
    std::vector<Slot>& reevidenced = reevidenced_;
    reevidenced.clear();
    const auto setRays = [&](Slot s, const mesher::SurfaceFace& face) {
      StoredFace& f = store_.face(s);
      if (f.rays == face.rays && f.front_crossings == face.front_crossings && f.view_sides == face.view_sides) return;
      f.rays = face.rays;
      f.layers.rays = face.rays;
      f.front_crossings = face.front_crossings;
      f.view_sides = face.view_sides;
      if (computer_.setEvidence(store_, s)) {
        reevidenced.push_back(s);
        change_points.push_back(f.centroid_L);
        changed.push_back(changeOf(s));
      } else {
        reobserved.push_back(s);
      }
    };
    std::unordered_set<mesher::FaceKey>& unchanged = unchanged_;
    unchanged.clear();
    for (const mesher::SurfaceFace& face : delta.added) {
      const std::optional<Slot> s = store_.find(face.key);
      if (!s || !sameGeometry(store_.face(*s), face)) continue;
      unchanged.insert(face.key);
      setRays(*s, face);
    }
    stats.faces_readded_unchanged = unchanged.size();
    for (const mesher::FaceKey& key : delta.removed) {
      stats.faces_removed += (!unchanged.empty() && unchanged.count(key) != 0) || removeKey(key) ? 1 : 0;
    }
    std::vector<Slot>& added = added_;
    added.clear();
    for (const mesher::SurfaceFace& face : delta.added) {
      if (!unchanged.empty() && unchanged.count(face.key) != 0) {
        ++stats.faces_added;
        continue;
      }
      removeKey(face.key);  // then add() finds no face with its key
      const Slot s = store_.add(face);
      store_.setDrive(s, drive_poses_);
      grow();
      lethal_[s] = 0;
      distance_[s] = kInf;
      computer_.setEvidence(store_, s);
      const StoredFace& f = store_.face(s);
      window_[s] = computer_.groundWindow(f);
      added.push_back(s);
      change_points.push_back(f.centroid_L);
      changed.push_back(changeOf(s));
    }
    stats.faces_added += added.size();
    for (const mesher::SurfaceFace& face : around) {
      if (const std::optional<Slot> s = store_.find(face.key)) setRays(*s, face);
    }
    stats.faces_reobserved = reobserved.size() + reevidenced.size();
  }

  LayerUpdateStats apply(const mesher::SurfaceDelta& delta, const std::vector<mesher::SurfaceFace>& around) {
    if (!delta.complete) {
      throw std::invalid_argument("TraversabilityMap::apply: incomplete delta (history forgotten); call reset()");
    }
    const auto start = std::chrono::steady_clock::now();
    LayerUpdateStats stats;
    replaceFaces(delta, around, stats);
    std::vector<Eigen::Vector3d>& change_points = change_points_;
    std::vector<Change>& changed = changed_;
    std::vector<Slot>& edge_neighbours = edge_neighbours_;
    const std::vector<Slot>& reobserved = reobserved_;
    const std::vector<Slot>& reevidenced = reevidenced_;
    const std::vector<Slot>& added = added_;

    // Local layers: every face whose footprint disc or clearance column meets a changed face that
    // can be its ground, an obstacle in its footprint or its ceiling (LayerComputer::mayAffect).
    const double reach = computer_.maxReachM() * (1 + 1e-9) + 1e-6;
    const std::uint32_t epoch = nextEpoch();
    std::vector<Slot>& dirty = dirty_;
    dirty.clear();
    const auto markDirty = [&](Slot s) {
      if (mark_[s] == epoch) return;
      mark_[s] = epoch;
      dirty.push_back(s);
    };
    for (Slot s : added) markDirty(s);
    for (Slot s : reevidenced) {
      if (store_.face(s).alive) markDirty(s);
    }
    const std::size_t added_dirty = dirty.size();
    for (Slot s : added) {
      store_.neighbours(s, scratch_neighbours_);
      edge_neighbours.insert(edge_neighbours.end(), scratch_neighbours_.begin(), scratch_neighbours_.end());
    }
    // A possible step's relief reads its edge neighbours' vertices (LayerComputer::setEvidence):
    // set it again now that every face of the delta is in; an edge neighbour whose relief changed
    // changes what the footprints sampling it may meet.
    for (Slot s : added) {
      if (computer_.evidenceReadsNeighbours(store_.face(s))) computer_.setEvidence(store_, s);
    }
    for (Slot s : edge_neighbours) {
      if (!store_.face(s).alive) continue;
      markDirty(s);
      if (computer_.evidenceReadsNeighbours(store_.face(s)) && computer_.setEvidence(store_, s)) {
        changed.push_back(changeOf(s));
        change_points.push_back(store_.centroid(s));
      }
    }
    for (const Change& change : changed) {
      const Projection& p = change.projection;
      const double box = change.driven ? std::sqrt(2.0) * reach : reach;  // see readsDrivenGround
      const Eigen::Vector2d r(box, box);
      store_.forEachCentroidInBox(p.lo - r, p.hi + r, [&](Slot s) {
        if (mark_[s] == epoch) return;
        const Eigen::Vector3d& c = store_.centroid(s);
        const double distance = internal::distanceToTriangle(c.head<2>(), p);
        if ((distance <= reach && computer_.mayAffect(c, window_[s], change.bounds, change.sampleable, distance)) ||
            (change.driven && distance <= box &&
             computer_.readsDrivenGround(store_.face(s), window_[s], change.bounds, distance))) {
          markDirty(s);
        }
      });
    }
    markNearUnconfirmedChanges(epoch, markDirty);
    // The faces added come first in `dirty` (added_dirty of them); they are change points already.
    for (std::size_t i = 0; i < dirty.size(); ++i) {
      const Slot s = dirty[i];
      const char was_lethal = lethal_[s];
      computeLocalAndLethal(s);
      if (i >= added_dirty && lethal_[s] != was_lethal) change_points.push_back(store_.centroid(s));
    }
    for (Slot s : reobserved) {
      if (mark_[s] == epoch) continue;
      const char was_lethal = lethal_[s];
      lethal_[s] = isLethal(s);
      if (lethal_[s] != was_lethal) change_points.push_back(store_.centroid(s));
      markDirty(s);
    }

    // Inflation: every face within the inflation radius of a change may have a new distance.
    const std::vector<Slot>& region = localInflation(change_points);
    const std::uint32_t finish_epoch = nextEpoch();
    std::size_t recomputed = 0;
    for (const std::vector<Slot>* list : {static_cast<const std::vector<Slot>*>(&dirty), &region}) {
      for (Slot s : *list) {
        if (mark_[s] == finish_epoch || !store_.face(s).alive) continue;
        mark_[s] = finish_epoch;
        finish(s);
        ++recomputed;
      }
    }
    stats.faces_recomputed = recomputed;
    stats.faces_total = store_.size();
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
  }

  LayeredMesh snapshot() const {
    std::vector<Slot> slots;
    for (Slot s = 0; s < store_.slotCount(); ++s) {
      if (store_.face(s).alive) slots.push_back(s);
    }
    std::sort(slots.begin(), slots.end(), [&](Slot a, Slot b) { return store_.face(a).key < store_.face(b).key; });
    std::map<mesher::VertexKey, Eigen::Vector3d> vertices;
    for (Slot s : slots) {
      const StoredFace& f = store_.face(s);
      for (int i = 0; i < 3; ++i) vertices.emplace(f.vertices[i], f.positions_W[i]);
    }
    LayeredMesh out;
    out.up_W = frame_.up_W.normalized();
    out.metres_per_unit = frame_.metres_per_unit;
    std::unordered_map<mesher::VertexKey, std::uint32_t> index;
    for (const auto& [key, position] : vertices) {
      index.emplace(key, static_cast<std::uint32_t>(out.mesh.vertices.size()));
      out.mesh.vertices.push_back(position);
      out.mesh.is_steiner.push_back(key.steiner ? 1 : 0);
      out.mesh.vertex_keys.push_back(key);
    }
    for (Slot s : slots) {
      const StoredFace& f = store_.face(s);
      out.mesh.faces.push_back({index.at(f.vertices[0]), index.at(f.vertices[1]), index.at(f.vertices[2])});
      out.mesh.face_rays.push_back(f.rays);
      out.mesh.face_front_crossings.push_back(f.front_crossings);
      out.mesh.face_view_sides.push_back(f.view_sides);
      out.layers.push_back(f.layers);
      out.face_keys.push_back(f.key);
    }
    return out;
  }

  std::size_t faceCount() const { return store_.size(); }
  const RobotProfile& profile() const { return profile_; }
  const MapFrame& frame() const { return frame_; }
  /// Layers of the face with this key (for computeForMesh).
  const FaceLayers* layersOf(const mesher::FaceKey& key) const {
    const std::optional<Slot> s = store_.find(key);
    return s ? &store_.face(*s).layers : nullptr;
  }

 private:
  /// Marks (markDirty) every face whose body holds, or held, an unconfirmed point added, removed
  /// or moved since the last update (LayerComputer::unconfirmedInBody), and forgets those changes.
  template <class Mark>
  void markNearUnconfirmedChanges(std::uint32_t epoch, Mark&& markDirty) {
    const double reach = computer_.unconfirmedReachM() * (1 + 1e-9) + 1e-6;
    const Eigen::Vector2d r(reach, reach);
    for (const Eigen::Vector3d& p : point_changes_) {
      store_.forEachInBox(p.head<2>() - r, p.head<2>() + r, [&](Slot s) {
        if (mark_[s] != epoch && computer_.unconfirmedInBody(store_.face(s), p)) markDirty(s);
      });
    }
    point_changes_.clear();
  }

  void grow() {
    distance_.resize(store_.slotCount(), kInf);
    lethal_.resize(store_.slotCount(), 0);
    mark_.resize(store_.slotCount(), 0);
    window_.resize(store_.slotCount());
  }

  std::uint32_t nextEpoch() {
    if (++epoch_ == 0) {
      std::fill(mark_.begin(), mark_.end(), 0u);
      epoch_ = 1;
    }
    return epoch_;
  }

  void computeLocalAndLethal(Slot s) {
    computer_.computeLocal(store_, s);
    lethal_[s] = isLethal(s);
  }

  /// Known and lethal, from the face's current local layers.
  char isLethal(Slot s) const {
    const StoredFace& f = store_.face(s);
    const bool known = !f.steiner && f.rays >= static_cast<std::uint32_t>(profile_.min_rays);
    return known && computer_.lethal(f) ? 1 : 0;
  }

  void finish(Slot s) {
    StoredFace& f = store_.face(s);
    f.layers.lethal_distance_m = static_cast<float>(distance_[s]);
    computer_.classify(f);
  }

  double edgeM(Slot a, Slot b) const { return (store_.centroid(a) - store_.centroid(b)).norm(); }

  /// Dijkstra from the heap's faces, relaxing only faces for which `inside` holds; distances
  /// beyond the inflation radius are not kept.
  template <class Inside>
  void dijkstra(graph::CostHeap& heap, Inside&& inside) {
    graph::boundedDijkstra(
        heap, [&](Slot s) -> double& { return distance_[s]; },
        [&](Slot s, const auto& relax) {
          store_.neighbours(s, scratch_);
          for (Slot t : scratch_) {
            if (inside(t)) relax(t, edgeM(s, t));
          }
        },
        profile_.inflation_radius_m);
  }

  void fullInflation() {
    graph::CostHeap& heap = heap_;
    for (Slot s = 0; s < store_.slotCount(); ++s) {
      distance_[s] = kInf;
      if (store_.face(s).alive && lethal_[s]) {
        distance_[s] = 0;
        graph::pushCost(heap, 0.0, s);
      }
    }
    dijkstra(heap, [](Slot) { return true; });
  }

  /// Recomputes the distances of the faces within the inflation radius (straight-line, a lower
  /// bound of the geodesic one) of a change, seeded by their lethal faces and by the unchanged
  /// distances of the faces around them. Returns the faces recomputed (a member, valid until the
  /// next call).
  const std::vector<Slot>& localInflation(const std::vector<Eigen::Vector3d>& change_points) {
    const double r = profile_.inflation_radius_m * (1 + 1e-9) + 1e-9;
    const std::uint32_t epoch = nextEpoch();
    std::vector<Slot>& region = region_;
    region.clear();
    for (const Eigen::Vector3d& p : change_points) {
      const Eigen::Vector2d h = p.head<2>(), rr(r, r);
      store_.forEachCentroidInBox(h - rr, h + rr, [&](Slot s) {
        if (mark_[s] == epoch || (store_.centroid(s) - p).norm() > r) return;
        mark_[s] = epoch;
        region.push_back(s);
      });
    }
    graph::CostHeap& heap = heap_;
    for (Slot s : region) distance_[s] = kInf;
    for (Slot s : region) {
      if (lethal_[s]) {
        distance_[s] = 0;
        graph::pushCost(heap, 0.0, s);
        continue;
      }
      store_.neighbours(s, scratch_);
      for (Slot b : scratch_) {
        if (mark_[b] == epoch || !std::isfinite(distance_[b])) continue;
        const double nd = distance_[b] + edgeM(b, s);
        if (nd <= profile_.inflation_radius_m && nd < distance_[s]) distance_[s] = nd;
      }
      if (std::isfinite(distance_[s])) graph::pushCost(heap, distance_[s], s);
    }
    dijkstra(heap, [&](Slot t) { return mark_[t] == epoch; });
    return region;
  }

  RobotProfile profile_;
  MapFrame frame_;
  DrivePoseLookup drive_poses_;
  internal::LayerComputer computer_;
  SurfaceStore store_;
  std::vector<double> distance_;  ///< per slot, geodesic metres to the nearest lethal face
  std::vector<char> lethal_;      ///< per slot
  std::vector<std::uint32_t> mark_;
  std::uint32_t epoch_ = 0;
  /// Per slot, the height window of the face's ground candidates (LayerComputer::groundWindow).
  std::vector<internal::LayerComputer::GroundWindow> window_;
  std::vector<Slot> scratch_;
  // Scratch of apply(), kept to reuse their memory.
  std::vector<Eigen::Vector3d> change_points_;
  std::vector<Change> changed_;
  std::vector<Slot> reobserved_, reevidenced_, added_, dirty_, region_, edge_neighbours_, scratch_neighbours_;
  std::unordered_set<mesher::FaceKey> unchanged_;
  /// The inflation's heap, kept between updates for its storage.
  graph::CostHeap heap_;
  /// The mesher's points not in the mesh (possible obstacles), and the positions (L) where they
  /// changed since the last apply().
  internal::UnconfirmedPoints unconfirmed_;
  std::vector<Eigen::Vector3d> point_changes_;
};

TraversabilityMap::TraversabilityMap(const RobotProfile& profile, const MapFrame& frame) {
  profile.validate();
  frame.validate();
  impl_ = std::make_unique<Impl>(profile, frame);
}

TraversabilityMap::~TraversabilityMap() = default;
TraversabilityMap::TraversabilityMap(TraversabilityMap&&) noexcept = default;
TraversabilityMap& TraversabilityMap::operator=(TraversabilityMap&&) noexcept = default;

LayerUpdateStats TraversabilityMap::update(const mesher::Mesher& mesher, std::uint64_t from_revision) {
  const auto start = std::chrono::steady_clock::now();
  const mesher::SurfaceDelta delta = mesher.changesSince(from_revision);
  LayerUpdateStats stats;
  const bool points_changed = impl_->replaceUnconfirmed(mesher.unconfirmedPoints());
  if (!delta.complete) {
    stats = impl_->reset(mesher.surfaceFaces());
  } else if (!delta.empty() || points_changed) {
    stats = impl_->apply(delta, mesher.facesAround(delta.touched_vertices));
  } else {
    stats.faces_total = impl_->faceCount();
  }
  stats.unconfirmed_points = impl_->unconfirmedCount();
  // The mesher's queries are part of the cost of keeping up.
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

LayerUpdateStats TraversabilityMap::apply(const mesher::SurfaceDelta& delta,
                                          const std::vector<mesher::SurfaceFace>& faces_around_touched) {
  return impl_->apply(delta, faces_around_touched);
}
LayerUpdateStats TraversabilityMap::reset(const std::vector<mesher::SurfaceFace>& faces) { return impl_->reset(faces); }
LayerUpdateStats TraversabilityMap::setUnconfirmedPoints(const std::vector<mesher::UnconfirmedPoint>& points) {
  impl_->replaceUnconfirmed(points);
  LayerUpdateStats stats = impl_->apply(mesher::SurfaceDelta{}, {});
  stats.unconfirmed_points = impl_->unconfirmedCount();
  return stats;
}
LayeredMesh TraversabilityMap::snapshot() const { return impl_->snapshot(); }
void TraversabilityMap::setDrivePoses(DrivePoseLookup lookup) { impl_->setDrivePoses(std::move(lookup)); }
std::size_t TraversabilityMap::faceCount() const { return impl_->faceCount(); }
const RobotProfile& TraversabilityMap::profile() const { return impl_->profile(); }
const MapFrame& TraversabilityMap::frame() const { return impl_->frame(); }

LayeredMesh TraversabilityMap::computeForMesh(const mesher::TriangleMesh& mesh, const RobotProfile& profile,
                                              const MapFrame& frame, std::uint32_t rays_if_unknown) {
  const bool has_keys = mesh.vertex_keys.size() == mesh.vertices.size();
  const bool has_flags = mesh.is_steiner.size() == mesh.vertices.size();
  const auto keyOf = [&](std::uint32_t v) {
    if (has_keys) return mesh.vertex_keys[v];
    return mesher::VertexKey{v, has_flags && mesh.is_steiner[v] != 0};
  };
  std::vector<mesher::SurfaceFace> faces(mesh.faces.size());
  const bool observed =
      mesh.face_rays.size() == mesh.faces.size() && mesh.face_front_crossings.size() == mesh.faces.size();
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& tri = mesh.faces[f];
    mesher::SurfaceFace& face = faces[f];
    bool steiner = false;
    for (int i = 0; i < 3; ++i) {
      if (tri[i] >= mesh.vertices.size()) throw std::invalid_argument("computeForMesh: face index out of range");
      face.vertices[i] = keyOf(tri[i]);
      face.positions_W[i] = mesh.vertices[tri[i]];
      steiner = steiner || (has_flags && mesh.is_steiner[tri[i]] != 0) || face.vertices[i].steiner;
    }
    face.key = mesher::FaceKey::of(face.vertices[0], face.vertices[1], face.vertices[2]);
    face.touches_steiner = steiner;
    if (mesh.is_driven.size() == mesh.vertices.size()) {
      for (int i = 0; i < 3; ++i) face.driven_vertices += mesh.is_driven[tri[i]] != 0 ? 1 : 0;
    }
    if (observed) {
      // terramesh's own meshes keep the observation counts the mesher reported.
      face.rays = mesh.face_rays[f];
      face.front_crossings = mesh.face_front_crossings[f];
    } else {
      // Another program's mesh has no ray paths: its measured faces count as observed in front.
      face.rays = steiner ? 0 : rays_if_unknown;
      face.front_crossings = face.rays;
    }
    // Without the sides (another program's mesh, an older file): seen from in front.
    face.view_sides = mesh.face_view_sides.size() == mesh.faces.size() ? mesh.face_view_sides[f] : mesher::view_side::kFront;
  }
  TraversabilityMap map(profile, frame);
  map.reset(faces);
  LayeredMesh out;
  out.mesh = mesh;
  out.up_W = frame.up_W.normalized();
  out.metres_per_unit = frame.metres_per_unit;
  for (const mesher::SurfaceFace& face : faces) {
    out.face_keys.push_back(face.key);
    out.layers.push_back(*map.impl_->layersOf(face.key));
  }
  return out;
}

}  // namespace terramesh::traversability

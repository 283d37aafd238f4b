#include "traversability/traversability_map.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <optional>
#include <cmath>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "common/plan_frame.h"
#include "face_projection.h"
#include "layer_computer.h"
#include "layer_stages.h"
#include "mesher/keyframe.h"
#include "surface_store.h"

namespace terramesh::traversability {
namespace {

using internal::Slot;
using internal::StoredFace;
using internal::SurfaceStore;

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

/// A delta that replaces at least this share of the map's faces reaches nearly every footprint
/// (KITTI 00's LiDAR scans: 0.6 of the faces replaced per scan, 0.94 re-judged), and a rebuild
/// judges a face for less than an update does (it lays the store out anew in key order, and skips
/// facesAround; docs/benchmarks.md, "Layer updates on LiDAR scans"). Either way the layers are the
/// same.
constexpr double kRebuildChangeShare = 0.5;

bool rebuildIsCheaper(const mesher::SurfaceDelta& delta, std::size_t faces_before) {
  const double changed = static_cast<double>(delta.added.size() + delta.removed.size());
  return faces_before > 0 && changed >= kRebuildChangeShare * static_cast<double>(faces_before);
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
        pipeline_(internal::makeLayerPipeline(computer_, profile, levelRotation(frame.up_W), frame.metres_per_unit,
                                              footprint_)) {}

  /// Replaces the unconfirmed points; the faces they reach are re-judged by the next apply()
  /// (or all of them by reset()). Returns whether any point changed.
  bool replaceUnconfirmed(const std::vector<mesher::UnconfirmedPoint>& points) {
    unconfirmed_cursor_.reset();
    return footprint_->replaceUnconfirmed(points);
  }
  /// Brings the unconfirmed points up to `mesher`'s: the changes since the last time this map read
  /// that mesher's points, else the whole set. Returns whether any point changed.
  bool followUnconfirmed(const mesher::Mesher& mesher) {
    if (unconfirmed_cursor_) {
      const mesher::UnconfirmedChanges changes = mesher.unconfirmedChangesSince(*unconfirmed_cursor_);
      if (changes.complete) {
        unconfirmed_cursor_ = changes.cursor;
        return footprint_->applyUnconfirmed(changes);
      }
    }
    const mesher::UnconfirmedCursor cursor = mesher.unconfirmedCursor();
    const bool changed = footprint_->replaceUnconfirmed(mesher.unconfirmedPoints());
    unconfirmed_cursor_ = cursor;
    return changed;
  }
  std::size_t unconfirmedCount() const { return footprint_->unconfirmedCount(); }
  void setDrivePoses(DrivePoseLookup lookup, std::optional<double> sensor_height_m) {
    drive_poses_ = std::move(lookup);
    computer_.setDriveSensorHeight(sensor_height_m);
  }

  LayerUpdateStats reset(const std::vector<mesher::SurfaceFace>& faces) {
    const auto start = std::chrono::steady_clock::now();
    store_.clear();
    pipeline_.resize(0);
    for (const mesher::SurfaceFace& face : faces) store_.setDrive(store_.add(face), drive_poses_);
    pipeline_.resize(store_.slotCount());
    pipeline_.computeAll(store_);
    LayerUpdateStats stats;
    stats.faces_added = store_.size();
    stats.faces_recomputed = store_.size();
    stats.faces_total = store_.size();
    stats.full_rebuild = true;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
  }

  LayerUpdateStats apply(const mesher::SurfaceDelta& delta, const std::vector<mesher::SurfaceFace>& around) {
    if (!delta.complete) {
      throw std::invalid_argument("TraversabilityMap::apply: incomplete delta (history forgotten); call reset()");
    }
    const auto start = std::chrono::steady_clock::now();
    LayerUpdateStats stats;
    changes_.clear();
    replaceFaces(delta, around, stats);
    pipeline_.update(store_, changes_);
    stats.faces_reobserved = changes_.recounted.size();
    stats.faces_recomputed = changes_.classified;
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
      out.mesh.face_back_crossings.push_back(f.back_crossings);
      out.mesh.face_back_depth.push_back(f.back_depth_W);
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
  /// The store's part of apply(): removes and adds the delta's faces and re-reads the observation
  /// counts of faces kept (the delta's churn and `around`), recording in changes_ what the stages
  /// read: faces added, faces removed (as changes), their edge neighbours, faces recounted.
  void replaceFaces(const mesher::SurfaceDelta& delta, const std::vector<mesher::SurfaceFace>& around,
                    LayerUpdateStats& stats) {
    const auto removeKey = [&](const mesher::FaceKey& key) {
      const std::optional<Slot> slot = store_.find(key);
      if (!slot) return false;
      changes_.shapes.push_back(internal::changeOf(store_, *slot));
      store_.neighbours(*slot, scratch_neighbours_);
      changes_.edge_neighbours.insert(changes_.edge_neighbours.end(), scratch_neighbours_.begin(),
                                      scratch_neighbours_.end());
      if (computer_.vertexVoidM(store_.face(*slot)) > 0) addLidNeighbours(*slot);
      pipeline_.removing(store_, *slot, changes_);
      store_.removeSlot(*slot);
      return true;
    };
    const auto recount = [&](Slot s, const mesher::SurfaceFace& face) {
      StoredFace& f = store_.face(s);
      if (f.rays == face.rays && f.front_crossings == face.front_crossings && f.view_sides == face.view_sides &&
          f.back_crossings == face.back_crossings && f.back_depth_W == face.back_depth) {
        return;
      }
      const double vertex_void = computer_.vertexVoidM(f);
      f.rays = face.rays;
      f.layers.rays = face.rays;
      f.front_crossings = face.front_crossings;
      f.view_sides = face.view_sides;
      f.back_crossings = face.back_crossings;
      f.back_depth_W = face.back_depth;
      f.back_depth_m = face.back_depth * frame_.metres_per_unit;
      changes_.recounted.push_back(s);
      if (computer_.vertexVoidM(f) != vertex_void) addLidNeighbours(s);
    };
    // Churn: a face removed and re-added with the same vertices and positions changes nothing
    // but (maybe) its observation counts.
    std::unordered_set<mesher::FaceKey>& unchanged = unchanged_;
    unchanged.clear();
    for (const mesher::SurfaceFace& face : delta.added) {
      const std::optional<Slot> s = store_.find(face.key);
      if (!s || !sameGeometry(store_.face(*s), face)) continue;
      unchanged.insert(face.key);
      recount(*s, face);
    }
    stats.faces_readded_unchanged = unchanged.size();
    for (const mesher::FaceKey& key : delta.removed) {
      stats.faces_removed += (!unchanged.empty() && unchanged.count(key) != 0) || removeKey(key) ? 1 : 0;
    }
    for (const mesher::SurfaceFace& face : delta.added) {
      if (!unchanged.empty() && unchanged.count(face.key) != 0) {
        ++stats.faces_added;
        continue;
      }
      removeKey(face.key);  // then add() finds no face with its key
      const Slot s = store_.add(face);
      store_.setDrive(s, drive_poses_);
      pipeline_.resize(store_.slotCount());
      changes_.added.push_back(s);
      changes_.shapes.push_back(internal::changeOf(store_, s));
      changes_.lethal_changes.push_back(store_.centroid(s));
    }
    stats.faces_added += changes_.added.size();
    for (Slot s : changes_.added) {
      store_.neighbours(s, scratch_neighbours_);
      changes_.edge_neighbours.insert(changes_.edge_neighbours.end(), scratch_neighbours_.begin(),
                                      scratch_neighbours_.end());
      if (computer_.vertexVoidM(store_.face(s)) > 0) addLidNeighbours(s);
    }
    for (const mesher::SurfaceFace& face : around) {
      if (const std::optional<Slot> s = store_.find(face.key)) recount(*s, face);
    }
  }

  /// The faces around the vertices of s read the void it shows (LayerComputer::vertexVoidM;
  /// changes_.lid_neighbours).
  void addLidNeighbours(Slot s) {
    store_.forEachVertexNeighbour(s, [&](Slot t) { changes_.lid_neighbours.push_back(t); });
  }

  RobotProfile profile_;
  MapFrame frame_;
  DrivePoseLookup drive_poses_;
  internal::LayerComputer computer_;
  SurfaceStore store_;
  /// The footprint stage of pipeline_ (which owns it).
  internal::FootprintStage* footprint_ = nullptr;
  internal::LayerPipeline pipeline_;
  /// What apply() changed, as it travels through the stages; kept to reuse the lists' memory.
  internal::StageChanges changes_;
  std::vector<Slot> scratch_neighbours_;
  std::unordered_set<mesher::FaceKey> unchanged_;
  /// Where the unconfirmed points were last read from a mesher (followUnconfirmed); none after
  /// a set given whole.
  std::optional<mesher::UnconfirmedCursor> unconfirmed_cursor_;
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
  const bool points_changed = impl_->followUnconfirmed(mesher);
  if (!delta.complete || rebuildIsCheaper(delta, impl_->faceCount())) {
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
void TraversabilityMap::setDrivePoses(DrivePoseLookup lookup, std::optional<double> sensor_height_m) {
  impl_->setDrivePoses(std::move(lookup), sensor_height_m);
}
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
    if (mesh.driven_kind.size() == mesh.vertices.size()) {
      for (int i = 0; i < 3; ++i) {
        const auto kind = static_cast<mesher::PointKind>(mesh.driven_kind[tri[i]]);
        face.driven_vertices += kind == mesher::PointKind::kDrivenGround ? 1 : 0;
        face.underside_vertices += kind == mesher::PointKind::kDrivenUnderside ? 1 : 0;
      }
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
    // Rays behind it: none known without them (another program's mesh, an older file).
    if (mesh.face_back_crossings.size() == mesh.faces.size() && mesh.face_back_depth.size() == mesh.faces.size()) {
      face.back_crossings = mesh.face_back_crossings[f];
      face.back_depth = mesh.face_back_depth[f];
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

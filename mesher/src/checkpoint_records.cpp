// Checkpoint of the rays (paths and per-cell ray lists), the point and keyframe registry, the
// surface history and the ball pass's memory of refused balls. Recycled slots and free lists are
// saved as they are, so ids are handed out in the same order after a resume.
#include <algorithm>
#include <utility>

#include "checkpoint_access.h"
#include "manifold_growing.h"

namespace terramesh::mesher::internal {
namespace {

void writePosition(ByteWriter& out, const Eigen::Vector3d& p) {
  out.f64(p.x());
  out.f64(p.y());
  out.f64(p.z());
}

Eigen::Vector3d readPosition(ByteReader& in) {
  Eigen::Vector3d p;
  p.x() = in.f64();
  p.y() = in.f64();
  p.z() = in.f64();
  return p;
}

void writeKey(ByteWriter& out, const VertexKey& key) {
  out.u64(key.value);
  out.u8(key.steiner ? 1 : 0);
}

VertexKey readKey(ByteReader& in) {
  VertexKey key;
  key.value = in.u64();
  key.steiner = in.flag();
  return key;
}

void writeKeys(ByteWriter& out, const std::vector<VertexKey>& keys) {
  out.u64(keys.size());
  for (const VertexKey& key : keys) writeKey(out, key);
}

std::vector<VertexKey> readKeys(ByteReader& in) {
  std::vector<VertexKey> keys(in.count(9));
  for (VertexKey& key : keys) key = readKey(in);
  return keys;
}

void writeFaces(ByteWriter& out, const std::vector<WoundFace>& faces) {
  out.u64(faces.size());
  for (const WoundFace& face : faces) {
    for (const VertexKey& key : face) writeKey(out, key);
  }
}

std::vector<WoundFace> readFaces(ByteReader& in) {
  std::vector<WoundFace> faces(in.count(27));
  for (WoundFace& face : faces) {
    for (VertexKey& key : face) key = readKey(in);
  }
  return faces;
}

/// Checks that every entry of `indices` is below `limit`.
void checkIndices(ByteReader& in, const std::vector<std::uint32_t>& indices, std::size_t limit, const char* what) {
  for (std::uint32_t i : indices) {
    if (i >= limit) in.fail(std::string(what) + " below " + std::to_string(limit) + ", got " + std::to_string(i));
  }
}

}  // namespace

void CheckpointAccess::writeRays(const RayStore& rays, ByteWriter& out, const Numbering& numbering) {
  out.u64(rays.rays_.size());
  for (const Ray& ray : rays.rays_) {
    out.u32(ray.point);
    out.u32(ray.keyframe);
    out.u8(ray.flags);
    out.u8(ray.walk);
    out.u64(ray.path.size());
    for (const CellHandle& cell : ray.path) out.u32(numbering.cell(cell));
    out.vector(ray.slots);
  }
  out.vector(rays.free_rays_);
  out.u64(rays.lists_.size());
  for (const std::vector<Crossing>& list : rays.lists_) {
    out.u64(list.size());
    for (const Crossing& crossing : list) {
      out.u32(crossing.ray);
      out.u32(crossing.step);
    }
  }
  out.vector(rays.free_lists_);
  out.u64(rays.path_entries_);
}

void CheckpointAccess::readRays(RayStore& rays, ByteReader& in, const Handles& handles) {
  in.section("rays");
  rays.rays_.resize(in.count(4 + 4 + 1 + 1 + 8 + 8));
  for (Ray& ray : rays.rays_) {
    ray.point = in.u32();
    ray.keyframe = in.u32();
    ray.flags = in.u8();
    ray.walk = in.u8();
    ray.path.resize(in.count(4));
    for (CellHandle& cell : ray.path) cell = handles.cell(in, "ray path cell");
    ray.slots = in.vector<std::uint32_t>();
    if (ray.slots.size() > ray.path.size()) in.fail("no more list slots than path steps");
  }
  rays.free_rays_ = in.vector<RayId>();
  checkIndices(in, rays.free_rays_, rays.rays_.size(), "a free ray id");
  in.section("per-cell ray lists");
  rays.lists_.resize(in.count(8));
  for (std::vector<Crossing>& list : rays.lists_) {
    list.resize(in.count(8));
    for (Crossing& crossing : list) {
      crossing.ray = in.index(rays.rays_.size(), "crossing ray");
      crossing.step = in.u32();
      if (crossing.step >= rays.rays_[crossing.ray].path.size()) in.fail("a crossing step on its ray's path");
    }
  }
  rays.free_lists_ = in.vector<std::uint32_t>();
  checkIndices(in, rays.free_lists_, rays.lists_.size(), "a free ray-list slot");
  rays.path_entries_ = static_cast<std::size_t>(in.u64());
  for (const Ray& ray : rays.rays_) {
    for (std::size_t step = 0; step < ray.slots.size(); ++step) {
      const std::uint32_t list = ray.path[step]->info().ray_list;
      if (list >= rays.lists_.size() || ray.slots[step] >= rays.lists_[list].size()) {
        in.fail("each ray path step entered in its cell's ray list");
      }
    }
  }
}

void CheckpointAccess::writeRegistry(const PointRegistry& registry, const MapState& state, ByteWriter& out,
                                     const Numbering& numbering) {
  out.u64(registry.points_.size());
  for (const PointRecord& point : registry.points_) {
    out.u64(point.id.value);
    out.u8(point.alive ? 1 : 0);
    out.u8(static_cast<std::uint8_t>(point.kind));
    writePosition(out, point.latest_W);
    writePosition(out, point.inserted_W);
    out.u32(numbering.vertex(point.vertex));
    out.vector(point.keyframes);
    out.vector(point.rays);
  }
  out.vector(registry.free_points_);
  out.u64(registry.keyframes_.size());
  for (const KeyframeRecord& keyframe : registry.keyframes_) {
    out.u64(keyframe.id.value);
    out.u8(keyframe.alive ? 1 : 0);
    writePosition(out, keyframe.centre_W);
    out.f64(keyframe.rotation_W_C.x());
    out.f64(keyframe.rotation_W_C.y());
    out.f64(keyframe.rotation_W_C.z());
    out.f64(keyframe.rotation_W_C.w());
    out.vector(keyframe.points);
    const bool hint = state.alive(keyframe.camera_hint);
    out.u32(hint ? numbering.cell(keyframe.camera_hint.cell) : kNone);
    out.u32(hint ? keyframe.camera_hint.uid : 0);
  }
  out.vector(registry.free_keyframes_);
  out.u64(registry.observation_links_);
}

void CheckpointAccess::readRegistry(PointRegistry& registry, ByteReader& in, const Handles& handles) {
  in.section("points");
  registry.points_.resize(in.count(8 + 1 + 1 + 48 + 4 + 16));
  registry.point_index_.clear();
  for (PointRecord& point : registry.points_) {
    point.id = PointId{in.u64()};
    point.alive = in.flag();
    const std::uint8_t kind = in.u8();
    if (kind > static_cast<std::uint8_t>(PointKind::kDrivenUnderside)) {
      in.fail("a point kind (0 SLAM, 1 driven ground, 2 driven underside)");
    }
    point.kind = static_cast<PointKind>(kind);
    point.latest_W = readPosition(in);
    point.inserted_W = readPosition(in);
    point.vertex = handles.vertex(in, "point vertex", true);
    point.keyframes = in.vector<std::uint32_t>();
    point.rays = in.vector<RayId>();
    if (point.alive && !registry.point_index_.emplace(point.id, static_cast<std::uint32_t>(&point - registry.points_.data())).second) {
      in.fail("distinct point ids");
    }
  }
  registry.free_points_ = in.vector<std::uint32_t>();
  checkIndices(in, registry.free_points_, registry.points_.size(), "a free point slot");
  in.section("keyframes");
  registry.keyframes_.resize(in.count(8 + 1 + 24 + 32 + 8 + 8));
  registry.keyframe_index_.clear();
  for (KeyframeRecord& keyframe : registry.keyframes_) {
    keyframe.id = KeyframeId{in.u64()};
    keyframe.alive = in.flag();
    keyframe.centre_W = readPosition(in);
    const double x = in.f64();
    const double y = in.f64();
    const double z = in.f64();
    const double w = in.f64();
    keyframe.rotation_W_C = Eigen::Quaterniond(w, x, y, z);
    keyframe.points = in.vector<std::uint32_t>();
    checkIndices(in, keyframe.points, registry.points_.size(), "an observed point index");
    keyframe.camera_hint.cell = handles.cell(in, "camera hint", true);
    keyframe.camera_hint.uid = in.u32();
    if (keyframe.alive &&
        !registry.keyframe_index_.emplace(keyframe.id, static_cast<std::uint32_t>(&keyframe - registry.keyframes_.data())).second) {
      in.fail("distinct keyframe ids");
    }
  }
  registry.free_keyframes_ = in.vector<std::uint32_t>();
  checkIndices(in, registry.free_keyframes_, registry.keyframes_.size(), "a free keyframe slot");
  registry.observation_links_ = static_cast<std::size_t>(in.u64());
  for (const PointRecord& point : registry.points_) {
    checkIndices(in, point.keyframes, registry.keyframes_.size(), "an observing keyframe index");
  }
  registry.rebuildWaiting();
}

void CheckpointAccess::writeFreeBoxes(const MapState& state, ByteWriter& out) {
  const std::vector<std::uint32_t> keyframes = state.boxes.keyframes();
  out.u64(keyframes.size());
  for (std::uint32_t k : keyframes) {
    const std::vector<FreeBox> boxes = state.boxes.of(k);
    out.u32(k);
    out.u64(boxes.size());
    for (const FreeBox& box : boxes) {
      writePosition(out, box.centre_W);
      const Eigen::Quaterniond& q = box.rotation_W_B;
      for (double c : {q.x(), q.y(), q.z(), q.w()}) out.f64(c);
      writePosition(out, box.half_extents);
    }
  }
}

void CheckpointAccess::readFreeBoxes(MapState& state, ByteReader& in) {
  in.section("free boxes");
  const std::size_t keyframes = in.count(4 + 8);
  std::uint32_t last = 0;
  for (std::size_t i = 0; i < keyframes; ++i) {
    const std::uint32_t k = in.u32();
    if (k >= state.registry.keyframeSlots() || !state.registry.keyframe(k).alive) {
      in.fail("a live keyframe slot");
    }
    if (i > 0 && k <= last) in.fail("keyframe slots in increasing order");
    last = k;
    std::vector<FreeBox> boxes(in.count(80));
    for (FreeBox& box : boxes) {
      box.centre_W = readPosition(in);
      const double x = in.f64(), y = in.f64(), z = in.f64(), w = in.f64();
      box.rotation_W_B = Eigen::Quaterniond(w, x, y, z);
      box.half_extents = readPosition(in);
      if (!box.centre_W.allFinite() || !box.rotation_W_B.coeffs().allFinite() ||
          !(box.rotation_W_B.norm() > 0) || !box.half_extents.allFinite() ||
          !(box.half_extents.minCoeff() > 0)) {
        in.fail("a free box with a finite centre, a non-zero rotation and positive half extents");
      }
    }
    state.boxes.set(k, boxes);
  }
}

void CheckpointAccess::writeSurfaceLog(const SurfaceLog& log, ByteWriter& out) {
  out.u64(log.kept_revisions_);
  out.u64(log.revision_);
  out.u64(log.bytes_);
  out.u64(log.records_.size());
  for (const SurfaceLog::Record& record : log.records_) {
    writeFaces(out, record.removed);
    writeFaces(out, record.added);
    writeKeys(out, record.touched);
    writeKeys(out, record.moved);
  }
}

void CheckpointAccess::readSurfaceLog(SurfaceLog& log, ByteReader& in) {
  in.section("surface history");
  if (in.u64() != log.kept_revisions_) in.fail("the surface history length of this version");
  log.revision_ = in.u64();
  log.bytes_ = static_cast<std::size_t>(in.u64());
  const std::size_t records = in.count(32);
  if (records > log.kept_revisions_ || records > log.revision_) in.fail("at most as many history records as revisions");
  if (log.bytes_ > log.kept_bytes_ && records > 1) in.fail("a surface history within surface_history_max_bytes");
  log.records_.clear();
  for (std::size_t r = 0; r < records; ++r) {
    SurfaceLog::Record record;
    record.removed = readFaces(in);
    record.added = readFaces(in);
    record.touched = readKeys(in);
    record.moved = readKeys(in);
    log.records_.push_back(std::move(record));
  }
}

void CheckpointAccess::writeBallRefusals(const Grower& grower, ByteWriter& out) {
  // Keyed by cell uid, which checkpoints keep (CellInfo::uid), so no remapping on load. Stale
  // entries (cells destroyed or carved since) are saved too: the grower forgets all entries once
  // there are more than kMaxBallRefusalsRemembered, and a resumed run must forget at the same
  // update. Sorted, so equal maps give equal bytes.
  std::vector<std::pair<std::uint32_t, std::uint64_t>> entries(grower.ball_refusals_.begin(),
                                                                 grower.ball_refusals_.end());
  std::sort(entries.begin(), entries.end());
  out.u64(entries.size());
  for (const auto& [uid, signature] : entries) {
    out.u32(uid);
    out.u64(signature);
  }
}

void CheckpointAccess::readBallRefusals(Grower& grower, ByteReader& in, const MapState& state) {
  in.section("ball pass refusals");
  const std::size_t count = in.count(4 + 8);
  if (count > Grower::kMaxBallRefusalsRemembered) {
    in.fail("at most " + std::to_string(Grower::kMaxBallRefusalsRemembered) +
            " remembered ball refusals, got " + std::to_string(count));
  }
  if (count > 0 && !state.config.edge_growing_pass) {
    in.fail("no ball refusals with the edge and ball passes off");
  }
  grower.ball_refusals_.clear();
  grower.ball_refusals_.reserve(count);
  std::uint32_t previous = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t uid = in.u32();
    if (uid >= state.next_uid) {
      in.fail("a cell uid below " + std::to_string(state.next_uid) + ", got " + std::to_string(uid));
    }
    if (i > 0 && uid <= previous) in.fail("cell uids in increasing order");
    previous = uid;
    grower.ball_refusals_.emplace(uid, in.u64());
  }
}

}  // namespace terramesh::mesher::internal

#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "mesher/surface_delta.h"

namespace terramesh::mesher::internal {

/// A surface face as three vertex keys wound counter-clockwise seen from free space.
using WoundFace = std::array<VertexKey, 3>;

/// The same face rotated to start at its smallest key (winding kept): equal faces compare equal.
WoundFace canonicalRotation(const WoundFace& face);

/// History of the surface, one record per revision: which faces each update removed and added
/// (netted over the update), and which vertices it touched. Fed by OutsideSet (every change of O),
/// the tracer (crossing changes of O-cells) and the update bookkeeping (rays gained or lost,
/// vertices removed); Mesher::changesSince reads it. Memory is bounded by keeping only the last
/// `kept_revisions` records, and dropping the oldest while they hold more than `kept_bytes`
/// (memoryBytes()); the newest record is always kept.
class SurfaceLog {
 public:
  SurfaceLog(std::uint64_t kept_revisions, std::size_t kept_bytes)
      : kept_revisions_(kept_revisions), kept_bytes_(kept_bytes) {}

  void faceAdded(const WoundFace& face) { faceEvent(face, faceHash(face), true); }
  void faceRemoved(const WoundFace& face) { faceEvent(face, faceHash(face), false); }
  /// Same as faceAdded (`added`) or faceRemoved, with `hash` == faceHash(face) computed by the
  /// caller (e.g. from vertexHash values shared by the facets of a cell).
  void faceEvent(const WoundFace& face, std::uint64_t hash, bool added) {
    pending_.push_back({face, hash, added});
  }

  /// Hash of one vertex key; faceHash combines three of them. O(1).
  static std::uint64_t vertexHash(const VertexKey& v) {
    const std::uint64_t x = (v.value ^ (v.steiner ? 0x5bd1e9955bd1e995ull : 0)) * 0x9E3779B97F4A7C15ull;
    return x ^ (x >> 29);
  }
  /// Hash of a face from its vertices' vertexHash values, independent of their order. O(1).
  static std::uint64_t faceHash(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
    std::uint64_t h = (a + b + c) ^ ((a ^ b ^ c) * 0xBF58476D1CE4E5B9ull);
    h ^= h >> 31;
    h *= 0x94D049BB133111EBull;
    return h ^ (h >> 32);
  }
  static std::uint64_t faceHash(const WoundFace& face) {
    return faceHash(vertexHash(face[0]), vertexHash(face[1]), vertexHash(face[2]));
  }
  /// The observation of the faces around `v` may have changed.
  void touch(const VertexKey& v) { pending_touched_.push_back(v); }
  /// The vertex of `v` was removed from the triangulation (it may come back elsewhere).
  void moved(const VertexKey& v) { pending_moved_.push_back(v); }

  /// Ends an update: nets what it recorded (a face removed and re-added unchanged, with no vertex
  /// moved, only touches its vertices) and, if anything is left, stores it as a new revision.
  /// O(changes log changes).
  void commit();

  std::uint64_t revision() const { return revision_; }
  /// Oldest revision whose changes can still be collected.
  std::uint64_t oldestRevision() const { return revision_ - records_.size(); }

  /// Net changes between revision `from` and now.
  struct Changes {
    std::vector<FaceKey> removed;  ///< sorted
    std::vector<WoundFace> added;  ///< as last recorded, in no order
    std::vector<VertexKey> touched;  ///< sorted, unique
  };
  /// @pre oldestRevision() <= from <= revision(). O(changes since `from`).
  Changes since(std::uint64_t from) const;

  /// Estimated bytes held by the records. O(1).
  std::size_t memoryBytes() const { return bytes_; }

 private:
  friend class CheckpointAccess;

  struct Event {
    WoundFace face;
    std::uint64_t hash;  ///< faceHash(face): equal for every winding and rotation
    bool added;
  };
  /// First and last pending event of one face (commit's open-addressing table).
  struct Span {
    std::uint64_t hash;
    std::uint32_t first;
    std::uint32_t last;
  };
  struct Record {
    std::vector<WoundFace> removed;  ///< winding it had before
    std::vector<WoundFace> added;
    std::vector<VertexKey> touched;  ///< sorted, unique; includes every face vertex above
    std::vector<VertexKey> moved;    ///< sorted, unique
  };
  static std::size_t bytesOf(const Record& record);

  std::uint64_t kept_revisions_;
  std::size_t kept_bytes_;
  std::uint64_t revision_ = 0;
  std::deque<Record> records_;  ///< records_.back() leads to revision_
  std::size_t bytes_ = 0;
  std::vector<Event> pending_;
  std::vector<Span> spans_;  ///< scratch of commit, kept for its capacity
  std::vector<std::uint32_t> key_slots_;  ///< scratch of commit's deduplication of vertex keys
  std::vector<VertexKey> unique_keys_;    ///< scratch of the same
  /// Sorts `keys` and drops repeats, hashing out the repeats first (most keys repeat).
  void sortUniqueHashed(std::vector<VertexKey>& keys);
  std::vector<VertexKey> pending_touched_;
  std::vector<VertexKey> pending_moved_;
};

}  // namespace terramesh::mesher::internal

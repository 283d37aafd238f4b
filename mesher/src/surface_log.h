#pragma once

#include <array>
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
/// `kept_revisions` records.
class SurfaceLog {
 public:
  explicit SurfaceLog(std::uint64_t kept_revisions) : kept_revisions_(kept_revisions) {}

  void faceAdded(const WoundFace& face) { pending_.push_back({face, true}); }
  void faceRemoved(const WoundFace& face) { pending_.push_back({face, false}); }
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
  struct Event {
    WoundFace face;
    bool added;
  };
  struct Record {
    std::vector<WoundFace> removed;  ///< winding it had before
    std::vector<WoundFace> added;
    std::vector<VertexKey> touched;  ///< sorted, unique; includes every face vertex above
    std::vector<VertexKey> moved;    ///< sorted, unique
  };
  static std::size_t bytesOf(const Record& record);

  std::uint64_t kept_revisions_;
  std::uint64_t revision_ = 0;
  std::deque<Record> records_;  ///< records_.back() leads to revision_
  std::size_t bytes_ = 0;
  std::vector<Event> pending_;
  std::vector<VertexKey> pending_touched_;
  std::vector<VertexKey> pending_moved_;
};

}  // namespace terramesh::mesher::internal

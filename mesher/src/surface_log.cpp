#include "surface_log.h"

#include <algorithm>
#include <cassert>
#include <unordered_map>
#include <utility>

namespace terramesh::mesher::internal {
namespace {

void sortUnique(std::vector<VertexKey>& keys) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

constexpr std::uint32_t kNoEvent = 0xFFFFFFFFu;

/// True if the faces have the same vertices (each face's three are distinct).
bool sameVertices(const WoundFace& a, const WoundFace& b) {
  return std::all_of(a.begin(), a.end(), [&b](const VertexKey& v) {
    return v == b[0] || v == b[1] || v == b[2];
  });
}

/// A 4096-bit filter of the moved vertices: a clear bit proves a vertex did not move.
constexpr std::size_t kMovedFilterWords = 64;
using MovedFilter = std::array<std::uint64_t, kMovedFilterWords>;
void setBit(MovedFilter& filter, const VertexKey& v) {
  const std::uint64_t bit = SurfaceLog::vertexHash(v) >> 52;
  filter[bit >> 6] |= std::uint64_t{1} << (bit & 63);
}
bool testBit(const MovedFilter& filter, const VertexKey& v) {
  const std::uint64_t bit = SurfaceLog::vertexHash(v) >> 52;
  return (filter[bit >> 6] >> (bit & 63) & 1u) != 0;
}

FaceKey keyOf(const WoundFace& face) { return FaceKey::of(face[0], face[1], face[2]); }

/// True if a vertex of `face` is in `moved` (sorted).
bool touchesMoved(const WoundFace& face, const std::vector<VertexKey>& moved) {
  return std::any_of(face.begin(), face.end(), [&moved](const VertexKey& v) {
    return std::binary_search(moved.begin(), moved.end(), v);
  });
}

}  // namespace

WoundFace canonicalRotation(const WoundFace& face) {
  WoundFace rotated = face;
  std::rotate(rotated.begin(), std::min_element(rotated.begin(), rotated.end()), rotated.end());
  return rotated;
}

std::size_t SurfaceLog::bytesOf(const Record& record) {
  return sizeof(Record) + (record.removed.capacity() + record.added.capacity()) * sizeof(WoundFace) +
         (record.touched.capacity() + record.moved.capacity()) * sizeof(VertexKey);
}

void SurfaceLog::commit() {
  if (pending_.empty() && pending_touched_.empty() && pending_moved_.empty()) return;
  Record record;
  sortUnique(pending_moved_);
  record.moved = pending_moved_;
  std::vector<VertexKey>& touched = pending_touched_;
  touched.insert(touched.end(), record.moved.begin(), record.moved.end());

  // One bit per moved vertex (by hash): a face whose vertices' bits are all clear touches none.
  MovedFilter moved_bits{};
  for (const VertexKey& v : record.moved) setBit(moved_bits, v);
  const auto mayTouchMoved = [&moved_bits](const WoundFace& face) {
    return testBit(moved_bits, face[0]) || testBit(moved_bits, face[1]) || testBit(moved_bits, face[2]);
  };

  // The first event of a face tells whether it existed before the update, the last whether it
  // exists after. An open-addressing table on the events' hashes keeps this linear.
  std::size_t capacity = 16;
  while (capacity < 2 * pending_.size()) capacity *= 2;
  const std::size_t mask = capacity - 1;
  spans_.assign(capacity, Span{0, kNoEvent, kNoEvent});
  // Spans hold (event index << 1 | added), so faces that came and went are skipped without
  // reading their events again.
  assert(pending_.size() < (std::size_t{1} << 31));
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const Event& event = pending_[i];
    const auto tagged = static_cast<std::uint32_t>(i << 1) | (event.added ? 1u : 0u);
    for (std::size_t slot = event.hash & mask;; slot = (slot + 1) & mask) {
      Span& span = spans_[slot];
      if (span.first == kNoEvent) {
        span.hash = event.hash;
        span.first = tagged;
        span.last = tagged;
        break;
      }
      if (span.hash == event.hash && sameVertices(pending_[span.first >> 1].face, event.face)) {
        span.last = tagged;
        break;
      }
    }
  }
  for (const Span& span : spans_) {
    if (span.first == kNoEvent) continue;
    const bool existed = (span.first & 1u) == 0;
    const bool exists = (span.last & 1u) != 0;
    if (!existed && !exists) continue;  // came and went within the update
    const Event& first = pending_[span.first >> 1];
    const Event& last = pending_[span.last >> 1];
    touched.insert(touched.end(), first.face.begin(), first.face.end());
    const WoundFace before = canonicalRotation(first.face);
    const WoundFace after = canonicalRotation(last.face);
    if (existed && exists && before == after &&
        (!mayTouchMoved(before) || !touchesMoved(before, record.moved))) {
      continue;
    }
    if (existed) record.removed.push_back(before);
    if (exists) record.added.push_back(after);
  }
  sortUniqueHashed(touched);
  record.touched = touched;
  pending_.clear();
  pending_touched_.clear();
  pending_moved_.clear();
  if (record.removed.empty() && record.added.empty() && record.touched.empty()) return;

  bytes_ += bytesOf(record);
  records_.push_back(std::move(record));
  ++revision_;
  while (records_.size() > kept_revisions_ || (bytes_ > kept_bytes_ && records_.size() > 1)) {
    bytes_ -= bytesOf(records_.front());
    records_.pop_front();
  }
}

void SurfaceLog::sortUniqueHashed(std::vector<VertexKey>& keys) {
  std::size_t capacity = 16;
  while (capacity < 2 * keys.size()) capacity *= 2;
  const std::size_t mask = capacity - 1;
  key_slots_.assign(capacity, kNoEvent);
  unique_keys_.clear();
  for (const VertexKey& key : keys) {
    for (std::size_t slot = vertexHash(key) & mask;; slot = (slot + 1) & mask) {
      std::uint32_t& index = key_slots_[slot];
      if (index == kNoEvent) {
        index = static_cast<std::uint32_t>(unique_keys_.size());
        unique_keys_.push_back(key);
        break;
      }
      if (unique_keys_[index] == key) break;
    }
  }
  std::sort(unique_keys_.begin(), unique_keys_.end());
  keys.assign(unique_keys_.begin(), unique_keys_.end());
}

SurfaceLog::Changes SurfaceLog::since(std::uint64_t from) const {
  struct Fate {
    WoundFace before;
    WoundFace after;
    bool existed = false;
    bool exists = false;
  };
  std::unordered_map<FaceKey, Fate> faces;
  std::vector<VertexKey> moved;
  Changes changes;
  for (auto record = records_.begin() + static_cast<std::ptrdiff_t>(from - oldestRevision());
       record != records_.end(); ++record) {
    for (const WoundFace& face : record->removed) {
      const auto [it, first_seen] = faces.try_emplace(keyOf(face));
      if (first_seen) {
        it->second.existed = true;
        it->second.before = face;
      }
      it->second.exists = false;
    }
    for (const WoundFace& face : record->added) {
      Fate& fate = faces[keyOf(face)];  // a new entry did not exist at `from`
      fate.exists = true;
      fate.after = face;
    }
    changes.touched.insert(changes.touched.end(), record->touched.begin(), record->touched.end());
    moved.insert(moved.end(), record->moved.begin(), record->moved.end());
  }
  sortUnique(changes.touched);
  sortUnique(moved);
  for (const auto& [key, fate] : faces) {
    if (fate.existed && fate.exists && fate.before == fate.after && !touchesMoved(fate.before, moved)) {
      continue;
    }
    if (fate.existed) changes.removed.push_back(key);
    if (fate.exists) changes.added.push_back(fate.after);
  }
  std::sort(changes.removed.begin(), changes.removed.end());
  return changes;
}

}  // namespace terramesh::mesher::internal

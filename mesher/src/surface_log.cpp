#include "surface_log.h"

#include <algorithm>
#include <unordered_map>
#include <utility>

namespace terramesh::mesher::internal {
namespace {

void sortUnique(std::vector<VertexKey>& keys) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
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

  // The first event of a face tells whether it existed before the update, the last whether it
  // exists after. Hashing keeps this linear in the events.
  std::unordered_map<FaceKey, std::pair<std::uint32_t, std::uint32_t>> span;
  span.reserve(pending_.size());
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const auto index = static_cast<std::uint32_t>(i);
    const auto [it, first_seen] = span.try_emplace(keyOf(pending_[i].face), index, index);
    if (!first_seen) it->second.second = index;
  }
  for (const auto& entry : span) {
    const Event& first = pending_[entry.second.first];
    const Event& last = pending_[entry.second.second];
    const bool existed = !first.added;
    const bool exists = last.added;
    if (!existed && !exists) continue;  // came and went within the update
    touched.insert(touched.end(), first.face.begin(), first.face.end());
    const WoundFace before = canonicalRotation(first.face);
    const WoundFace after = canonicalRotation(last.face);
    if (existed && exists && before == after && !touchesMoved(before, record.moved)) continue;
    if (existed) record.removed.push_back(before);
    if (exists) record.added.push_back(after);
  }
  sortUnique(touched);
  record.touched = touched;
  pending_.clear();
  pending_touched_.clear();
  pending_moved_.clear();
  if (record.removed.empty() && record.added.empty() && record.touched.empty()) return;

  bytes_ += bytesOf(record);
  records_.push_back(std::move(record));
  ++revision_;
  while (records_.size() > kept_revisions_) {
    bytes_ -= bytesOf(records_.front());
    records_.pop_front();
  }
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

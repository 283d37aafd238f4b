#include "point_registry.h"

#include <algorithm>
#include <cassert>

namespace terramesh::mesher::internal {

namespace {

/// The index of the record of `id`, created if absent (`created`: which), in a freed slot first.
template <class Id, class Record>
std::uint32_t findOrCreate(std::unordered_map<Id, std::uint32_t>& index_of, std::vector<std::uint32_t>& free,
                           std::vector<Record>& records, Id id, bool& created) {
  const auto [it, inserted] = index_of.try_emplace(id, kNone);
  created = inserted;
  if (!inserted) return it->second;
  std::uint32_t index;
  if (!free.empty()) {
    index = free.back();
    free.pop_back();
  } else {
    index = static_cast<std::uint32_t>(records.size());
    records.emplace_back();
  }
  records[index] = Record{};
  records[index].id = id;
  records[index].alive = true;
  it->second = index;
  return index;
}

}  // namespace

std::uint32_t PointRegistry::findOrCreatePoint(PointId id) {
  bool created = false;
  return findOrCreate(point_index_, free_points_, points_, id, created);
}

std::uint32_t PointRegistry::findPoint(PointId id) const {
  const auto it = point_index_.find(id);
  return it == point_index_.end() ? kNone : it->second;
}

void PointRegistry::erasePoint(std::uint32_t index) {
  PointRecord& record = points_[index];
  assert(record.alive && !record.inserted() && record.rays.empty());
  point_index_.erase(record.id);
  waiting_.erase(index);
  waiting_journal_.emplace_back(waiting_revision_ + 1, record.id);
  record = PointRecord{};
  free_points_.push_back(index);
}

void PointRegistry::refreshWaiting(std::uint32_t index) {
  const PointRecord& record = points_[index];
  if (record.alive) waiting_journal_.emplace_back(waiting_revision_ + 1, record.id);
  if (record.alive && record.kind == PointKind::kSlam && !record.inserted() && !record.keyframes.empty()) {
    waiting_.insert(index);
  } else {
    waiting_.erase(index);
  }
}

void PointRegistry::rebuildWaiting() {
  waiting_.clear();
  for (std::size_t i = 0; i < points_.size(); ++i) refreshWaiting(static_cast<std::uint32_t>(i));
  waiting_journal_.clear();
  waiting_forgotten_ = waiting_revision_;
}

void PointRegistry::commitWaiting() {
  ++waiting_revision_;
  if (waiting_revision_ <= kWaitingRevisionsKept) return;
  const std::uint64_t oldest_kept = waiting_revision_ - kWaitingRevisionsKept;
  while (!waiting_journal_.empty() && waiting_journal_.front().first <= oldest_kept) waiting_journal_.pop_front();
  waiting_forgotten_ = std::max(waiting_forgotten_, oldest_kept);
}

std::optional<std::vector<PointId>> PointRegistry::waitingChangesSince(std::uint64_t from) const {
  if (from < waiting_forgotten_ || from > waiting_revision_) return std::nullopt;
  // Entries are in revision order: the first after `from` found by binary search.
  const auto first = std::upper_bound(waiting_journal_.begin(), waiting_journal_.end(), from,
                                      [](std::uint64_t r, const std::pair<std::uint64_t, PointId>& e) { return r < e.first; });
  std::vector<PointId> ids;
  ids.reserve(static_cast<std::size_t>(waiting_journal_.end() - first));
  for (auto it = first; it != waiting_journal_.end() && it->first <= waiting_revision_; ++it) ids.push_back(it->second);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

std::uint32_t PointRegistry::findOrCreateKeyframe(KeyframeId id, bool& created) {
  return findOrCreate(keyframe_index_, free_keyframes_, keyframes_, id, created);
}

std::uint32_t PointRegistry::findKeyframe(KeyframeId id) const {
  const auto it = keyframe_index_.find(id);
  return it == keyframe_index_.end() ? kNone : it->second;
}

void PointRegistry::eraseKeyframe(std::uint32_t index) {
  KeyframeRecord& record = keyframes_[index];
  assert(record.alive);
  keyframe_index_.erase(record.id);
  record = KeyframeRecord{};
  free_keyframes_.push_back(index);
}

std::vector<std::uint32_t> PointRegistry::takeKeyframePoints(std::uint32_t keyframe) {
  std::vector<std::uint32_t> points;
  points.swap(keyframes_[keyframe].points);
  observation_links_ -= points.size();
  return points;
}

void PointRegistry::addKeyframePoint(std::uint32_t keyframe, std::uint32_t point) {
  keyframes_[keyframe].points.push_back(point);
  ++observation_links_;
}

void PointRegistry::removeKeyframePoint(std::uint32_t keyframe, std::uint32_t point) {
  std::vector<std::uint32_t>& points = keyframes_[keyframe].points;
  const auto it = std::find(points.begin(), points.end(), point);
  if (it == points.end()) return;
  *it = points.back();
  points.pop_back();
  --observation_links_;
}

std::size_t PointRegistry::pointBytes(std::size_t rays) const {
  // Each observation is listed by its keyframe and by its point; each ray by its point.
  return points_.capacity() * sizeof(PointRecord) + keyframes_.capacity() * sizeof(KeyframeRecord) +
         2 * observation_links_ * sizeof(std::uint32_t) + rays * sizeof(RayId);
}

std::size_t PointRegistry::indexBytes() const {
  // libstdc++ unordered_map: a bucket pointer per bucket and a node (next, key, value, hash).
  const std::size_t node = sizeof(void*) + sizeof(std::uint64_t) * 2 + sizeof(std::size_t);
  const std::size_t waiting_node = sizeof(void*) + sizeof(std::uint64_t);
  return (point_index_.bucket_count() + keyframe_index_.bucket_count() + waiting_.bucket_count()) * sizeof(void*) +
         (point_index_.size() + keyframe_index_.size()) * node + waiting_.size() * waiting_node;
}

}  // namespace terramesh::mesher::internal

#include "tf_buffer.h"

#include <algorithm>
#include <cmath>

namespace terramesh::datasets::internal {
namespace {

std::string inQuotes(std::string_view frame) { return "\"" + std::string(frame) + "\""; }

}  // namespace

std::vector<std::string> TfBufferConfig::problems() const {
  std::vector<std::string> found;
  if (!(max_interval_s >= 0) || !std::isfinite(max_interval_s)) {
    found.push_back("max_interval_s must be a finite number >= 0");
  }
  if (!(tolerance_s >= 0) || !std::isfinite(tolerance_s)) {
    found.push_back("tolerance_s must be a finite number >= 0");
  }
  return found;
}

void TfBufferConfig::validate() const {
  const std::vector<std::string> found = problems();
  if (found.empty()) return;
  std::string message = "TfBufferConfig:";
  for (const std::string& problem : found) message += " " + problem + ";";
  message.pop_back();
  throw std::invalid_argument(message);
}

TimedPose composePoses(const TimedPose& a_T_b, const TimedPose& b_T_c) {
  TimedPose a_T_c;
  a_T_c.time_s = b_T_c.time_s;
  a_T_c.position_W = a_T_b.position_W + a_T_b.rotation_W_S * b_T_c.position_W;
  a_T_c.rotation_W_S = (a_T_b.rotation_W_S * b_T_c.rotation_W_S).normalized();
  return a_T_c;
}

TimedPose invertPose(const TimedPose& a_T_b) {
  TimedPose b_T_a;
  b_T_a.time_s = a_T_b.time_s;
  b_T_a.rotation_W_S = a_T_b.rotation_W_S.conjugate();
  b_T_a.position_W = -(b_T_a.rotation_W_S * a_T_b.position_W);
  return b_T_a;
}

TfBuffer::TfBuffer(TfBufferConfig config) : config_(config) { config_.validate(); }

TfBuffer::Edge& TfBuffer::edgeFor(std::string_view parent_id, std::string_view child_id,
                                  bool is_static) {
  const std::string parent = normalizedFrame(parent_id);
  const std::string child = normalizedFrame(child_id);
  if (parent == child) throw TfProblem("frame " + inQuotes(child) + " is given as its own parent");
  if (const auto it = edges_.find(child); it != edges_.end()) {
    if (it->second.parent != parent) {
      throw TfProblem("frame " + inQuotes(child) + " has two parents: " + inQuotes(it->second.parent) +
                      " and " + inQuotes(parent));
    }
    if (it->second.is_static != is_static) {
      throw TfProblem("the edge " + parent + " -> " + child + " is both static and time-varying");
    }
    return it->second;
  }
  const std::vector<std::string> above = ancestry(parent);
  if (std::find(above.begin(), above.end(), child) != above.end()) {
    throw TfProblem("the edge " + parent + " -> " + child + " closes a cycle: " + inQuotes(child) +
                    " is already an ancestor of " + inQuotes(parent));
  }
  frames_.insert(parent);
  frames_.insert(child);
  Edge& edge = edges_[child];
  edge.parent = parent;
  edge.is_static = is_static;
  return edge;
}

void TfBuffer::addStatic(std::string_view parent, std::string_view child,
                         const TimedPose& transform) {
  Edge& edge = edgeFor(parent, child, true);
  edge.transforms.assign(1, transform);
}

void TfBuffer::addDynamic(std::string_view parent, std::string_view child,
                          const TimedPose& transform) {
  Edge& edge = edgeFor(parent, child, false);
  const auto at = std::upper_bound(
      edge.transforms.begin(), edge.transforms.end(), transform.time_s,
      [](double time, const TimedPose& pose) { return time < pose.time_s; });
  edge.transforms.insert(at, transform);
}

bool TfBuffer::hasFrame(std::string_view frame) const {
  return frames_.count(normalizedFrame(frame)) > 0;
}

std::vector<std::string> TfBuffer::frames() const { return {frames_.begin(), frames_.end()}; }

std::vector<std::string> TfBuffer::ancestry(const std::string& frame) const {
  std::vector<std::string> path{frame};
  for (auto it = edges_.find(frame); it != edges_.end(); it = edges_.find(path.back())) {
    path.push_back(it->second.parent);
  }
  return path;
}

std::string TfBuffer::root(std::string_view frame) const {
  const std::string name = normalizedFrame(frame);
  if (!frames_.count(name)) throw std::out_of_range("TfBuffer::root: unknown frame " + inQuotes(name));
  return ancestry(name).back();
}

std::vector<std::string> TfBuffer::leaves(std::string_view root_frame) const {
  const std::string top = normalizedFrame(root_frame);
  std::set<std::string> parents;
  for (const auto& [child, edge] : edges_) parents.insert(edge.parent);
  std::vector<std::string> found;
  for (const std::string& frame : frames_) {
    if (!parents.count(frame) && ancestry(frame).back() == top) found.push_back(frame);
  }
  return found;
}

std::optional<std::pair<std::size_t, std::size_t>> TfBuffer::meet(
    const std::vector<std::string>& a, const std::vector<std::string>& b) const {
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto it = std::find(b.begin(), b.end(), a[i]);
    if (it != b.end()) return std::make_pair(i, static_cast<std::size_t>(it - b.begin()));
  }
  return std::nullopt;
}

TfLookup TfBuffer::down(const std::vector<std::string>& path, std::size_t count,
                        double time_s) const {
  TfLookup result;
  // From the ancestor's child down to path[0]; the first edge's transform is taken as it is.
  for (std::size_t k = count; k-- > 0;) {
    const Edge& edge = edges_.find(path[k])->second;
    const std::optional<TimedPose> transform =
        edge.is_static ? std::optional<TimedPose>(edge.transforms.front())
                       : poseAt(edge.transforms, time_s, config_.max_interval_s,
                                config_.tolerance_s);
    if (!transform) {
      result.status = TfLookupStatus::kNoTransformAtTime;
      result.detail = edge.parent + " -> " + path[k];
      return result;
    }
    result.pose = k + 1 == count ? *transform : composePoses(result.pose, *transform);
  }
  result.pose.time_s = time_s;
  return result;
}

TfLookup TfBuffer::lookup(std::string_view target_id, std::string_view source_id,
                          double time_s) const {
  const std::string target = normalizedFrame(target_id);
  const std::string source = normalizedFrame(source_id);
  TfLookup result;
  for (const std::string& frame : {target, source}) {
    if (!frames_.count(frame)) {
      result.status = TfLookupStatus::kUnknownFrame;
      result.detail = frame;
      return result;
    }
  }
  const std::vector<std::string> up_source = ancestry(source);
  const std::vector<std::string> up_target = ancestry(target);
  const auto common = meet(up_source, up_target);
  if (!common) {
    result.status = TfLookupStatus::kNotConnected;
    return result;
  }
  const auto [source_steps, target_steps] = *common;
  TfLookup ancestor_T_source = down(up_source, source_steps, time_s);
  if (ancestor_T_source.status != TfLookupStatus::kOk) return ancestor_T_source;
  if (target_steps == 0) return ancestor_T_source;
  TfLookup ancestor_T_target = down(up_target, target_steps, time_s);
  if (ancestor_T_target.status != TfLookupStatus::kOk) return ancestor_T_target;
  result.pose = invertPose(ancestor_T_target.pose);
  if (source_steps > 0) result.pose = composePoses(result.pose, ancestor_T_source.pose);
  result.pose.time_s = time_s;
  return result;
}

std::string TfBuffer::describePath(std::string_view target_id, std::string_view source_id) const {
  const std::string target = normalizedFrame(target_id);
  const std::string source = normalizedFrame(source_id);
  if (!frames_.count(target) || !frames_.count(source)) return "";
  const std::vector<std::string> up_source = ancestry(source);
  const std::vector<std::string> up_target = ancestry(target);
  const auto common = meet(up_source, up_target);
  if (!common) return "";
  std::string path = target;
  std::string statics;
  auto note = [this, &statics](const std::string& child) {
    const Edge& edge = edges_.find(child)->second;
    if (edge.is_static) statics += (statics.empty() ? "" : ", ") + edge.parent + " -> " + child;
  };
  for (std::size_t k = 1; k <= common->second; ++k) {
    path += " <- " + up_target[k];
    note(up_target[k - 1]);
  }
  for (std::size_t k = common->first; k-- > 0;) {
    path += " -> " + up_source[k];
    note(up_source[k]);
  }
  return statics.empty() ? path : path + " (" + statics + " static)";
}

std::size_t TfBuffer::staticEdges() const {
  return static_cast<std::size_t>(std::count_if(
      edges_.begin(), edges_.end(), [](const auto& entry) { return entry.second.is_static; }));
}

std::size_t TfBuffer::dynamicEdges() const { return edges_.size() - staticEdges(); }

std::optional<std::pair<double, double>> TfBuffer::dynamicSpan() const {
  std::optional<std::pair<double, double>> span;
  for (const auto& [child, edge] : edges_) {
    if (edge.is_static || edge.transforms.empty()) continue;
    const double first = edge.transforms.front().time_s, last = edge.transforms.back().time_s;
    span = span ? std::make_pair(std::min(span->first, first), std::max(span->second, last))
                : std::make_pair(first, last);
  }
  return span;
}

}  // namespace terramesh::datasets::internal

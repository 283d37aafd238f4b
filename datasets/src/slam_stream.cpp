#include "datasets/slam_stream.h"

#include <type_traits>

#include "mesher/mesher.h"

namespace terramesh::datasets {

std::size_t SlamStream::keyframeEventCount() const {
  std::size_t count = 0;
  for (const StreamEvent& event : events) {
    if (std::holds_alternative<mesher::Keyframe>(event)) ++count;
  }
  return count;
}

mesher::UpdateStats applyEvent(mesher::Mesher& mesher, const StreamEvent& event) {
  return std::visit(
      [&mesher](const auto& message) -> mesher::UpdateStats {
        using Message = std::decay_t<decltype(message)>;
        if constexpr (std::is_same_v<Message, mesher::Keyframe>) {
          return mesher.integrateKeyframe(message);
        } else if constexpr (std::is_same_v<Message, PointRemoval>) {
          return mesher.removePoints(message.points);
        } else {
          return mesher.removeKeyframe(message.keyframe);
        }
      },
      event);
}

}  // namespace terramesh::datasets

#pragma once
// A stream event applied as `terramesh mesh --robot` applies it (TrajectoryEvidenceRun::apply):
// keyframes and keyframe removals through the trajectory evidence when there is one, everything
// else straight to the mesher. For the tests that mesh generated streams with the evidence.

#include <variant>

#include "datasets/slam_simulation.h"
#include "mesher/mesher.h"
#include "traversability/trajectory_evidence.h"

namespace terramesh::traversability::test_stream {

inline void applyEvent(mesher::Mesher& mesher, const datasets::StreamEvent& event, TrajectoryEvidence* evidence) {
  const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
  const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event);
  if (evidence && keyframe) {
    evidence->integrate(mesher, *keyframe);
  } else if (evidence && removal) {
    evidence->removeKeyframe(mesher, removal->keyframe);
  } else {
    datasets::applyEvent(mesher, event);
  }
}

}  // namespace terramesh::traversability::test_stream

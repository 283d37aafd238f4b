#include "evaluation/traversability_score.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "datasets/triangle_bvh.h"
#include "evaluation/mesh_refinement.h"

namespace terramesh::evaluation {
namespace {

using traversability::FaceClass;

double ratio(double num, double den) { return den > 0 ? num / den : std::numeric_limits<double>::quiet_NaN(); }

/// The known (or only the free) faces of the map, for the coverage queries.
mesher::TriangleMesh knownFaces(const traversability::LayeredMesh& map, bool free_only) {
  mesher::TriangleMesh known;
  known.vertices = map.mesh.vertices;
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    const FaceClass c = map.layers[f].face_class;
    if (free_only ? c == FaceClass::kFree : c != FaceClass::kUnknown) known.faces.push_back(map.mesh.faces[f]);
  }
  return known;
}

/// The traversable truth area with a face of `known` within max_distance_m.
double coveredArea(const GroundTruthTraversability& truth, const mesher::TriangleMesh& known, double max_distance_m) {
  if (known.faces.empty()) return 0.0;
  const datasets::TriangleBvh bvh(known);
  double covered_m2 = 0;
  for (std::size_t f = 0; f < truth.mesh.mesh.faces.size(); ++f) {
    if (!truth.traversable[f]) continue;
    if (bvh.closestPoint(faceCentroid(truth.mesh.mesh, f)).distance <= max_distance_m) {
      covered_m2 += faceArea(truth.mesh.mesh, f);
    }
  }
  return covered_m2;
}

}  // namespace

void ClassAreas::add(FaceClass face_class, double area) {
  switch (face_class) {
    case FaceClass::kFree: free_m2 += area; break;
    case FaceClass::kLethal: lethal_m2 += area; break;
    case FaceClass::kUnknown: unknown_m2 += area; break;
    case FaceClass::kUncertain: uncertain_m2 += area; break;
  }
}

void ScoreConfig::validate() const {
  std::ostringstream problems;
  if (!(max_distance_m > 0) || !std::isfinite(max_distance_m)) {
    problems << "max_distance_m: " << max_distance_m << " (expected > 0)";
  }
  if (!(sample_edge_m >= 0) || !std::isfinite(sample_edge_m)) {
    problems << (problems.tellp() > 0 ? "; " : "") << "sample_edge_m: " << sample_edge_m << " (expected >= 0)";
  }
  if (problems.tellp() > 0) throw std::invalid_argument("ScoreConfig: " + problems.str());
}

TraversabilityScore scoreTraversability(const traversability::LayeredMesh& map,
                                        const GroundTruthTraversability& truth, const ScoreConfig& config,
                                        const std::vector<std::uint8_t>& face_groups) {
  config.validate();
  if (!face_groups.empty() && face_groups.size() != map.mesh.faces.size()) {
    throw std::invalid_argument("scoreTraversability: " + std::to_string(face_groups.size()) + " face groups for " +
                                std::to_string(map.mesh.faces.size()) + " faces");
  }
  if (map.layers.size() != map.mesh.faces.size()) {
    throw std::invalid_argument("scoreTraversability: the map has " + std::to_string(map.layers.size()) +
                                " layer records for " + std::to_string(map.mesh.faces.size()) + " faces");
  }
  if (truth.mesh.mesh.faces.empty()) throw std::invalid_argument("scoreTraversability: the truth has no faces");
  if (truth.traversable.size() != truth.mesh.mesh.faces.size()) {
    throw std::invalid_argument("scoreTraversability: the truth has no answer per face");
  }
  TraversabilityScore score;
  if (!face_groups.empty()) {
    score.by_group.resize(static_cast<std::size_t>(*std::max_element(face_groups.begin(), face_groups.end())) + 1);
  }
  const datasets::TriangleBvh truth_bvh(truth.mesh.mesh);
  const RefinedMesh pieces = refineMesh(map.mesh, config.sample_edge_m);
  for (std::size_t p = 0; p < pieces.mesh.faces.size(); ++p) {
    const double area = faceArea(pieces.mesh, p);
    const datasets::SurfacePoint nearest = truth_bvh.closestPoint(faceCentroid(pieces.mesh, p));
    if (!(nearest.distance <= config.max_distance_m)) {
      score.ignored_far_m2 += area;
      continue;
    }
    const FaceClass predicted = map.layers[pieces.parent_face[p]].face_class;
    const bool traversable = truth.traversable[nearest.face] != 0;
    score.scored_m2 += area;
    score.by_label[static_cast<std::size_t>(truth.mesh.labels[nearest.face])].add(predicted, area);
    score.by_truth[traversable ? 1 : 0].add(predicted, area);
    score.by_label_and_truth[static_cast<std::size_t>(truth.mesh.labels[nearest.face])][traversable ? 1 : 0].add(
        predicted, area);
    score.by_reason[static_cast<std::size_t>(truth.reasons[nearest.face])].add(predicted, area);
    if (!face_groups.empty()) score.by_group[face_groups[pieces.parent_face[p]]][traversable ? 1 : 0].add(predicted, area);
    if (predicted == FaceClass::kUnknown) {
      score.unknown_m2 += area;
    } else if (predicted == FaceClass::kUncertain) {
      score.uncertain_m2 += area;
    } else if (predicted == FaceClass::kFree) {
      (traversable ? score.true_positive_m2 : score.false_positive_m2) += area;
    } else {
      (traversable ? score.false_negative_m2 : score.true_negative_m2) += area;
    }
  }
  score.precision = ratio(score.true_positive_m2, score.true_positive_m2 + score.false_positive_m2);
  score.recall = ratio(score.true_positive_m2, score.true_positive_m2 + score.false_negative_m2);
  score.f1 = ratio(2 * score.true_positive_m2,
                   2 * score.true_positive_m2 + score.false_positive_m2 + score.false_negative_m2);
  score.unknown_fraction = ratio(score.unknown_m2, score.scored_m2);
  score.uncertain_fraction = ratio(score.uncertain_m2, score.scored_m2);

  // Coverage: traversable truth faces with a known (a free) map face within reach.
  for (std::size_t f = 0; f < truth.mesh.mesh.faces.size(); ++f) {
    if (truth.traversable[f]) score.truth_traversable_m2 += faceArea(truth.mesh.mesh, f);
  }
  score.coverage = ratio(coveredArea(truth, knownFaces(map, false), config.max_distance_m), score.truth_traversable_m2);
  score.free_coverage =
      ratio(coveredArea(truth, knownFaces(map, true), config.max_distance_m), score.truth_traversable_m2);
  return score;
}

}  // namespace terramesh::evaluation

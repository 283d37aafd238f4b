#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "datasets/labeled_mesh.h"
#include "evaluation/ground_truth_traversability.h"
#include "traversability/layered_mesh.h"

namespace terramesh::evaluation {

/// Map area (m^2) per predicted class.
struct ClassAreas {
  double free_m2 = 0;
  double lethal_m2 = 0;
  double unknown_m2 = 0;
  double uncertain_m2 = 0;
  double total() const { return free_m2 + lethal_m2 + unknown_m2 + uncertain_m2; }
  /// Adds `area` (m^2) to the total of `face_class`.
  void add(traversability::FaceClass face_class, double area);
};

/// How a map is scored against the ground truth.
struct ScoreConfig {
  /// Map surface farther than this from the ground-truth surface is not scored, in metres.
  double max_distance_m = 0.5;
  /// Map faces are split until no edge is longer than this (metres) and each piece is judged at
  /// its centroid, weighted by its area; 0 judges whole faces at their centroids.
  double sample_edge_m = 0.25;
  /// @throw std::invalid_argument listing every out-of-range field.
  void validate() const;
};

/// Area-weighted agreement of a map's "free" with the ground truth's "traversable".
///
/// Every piece of a map face whose centroid lies within max_distance_m of the truth is scored;
/// its truth is that of the nearest ground-truth face. Free and lethal pieces only enter precision
/// and recall: free = predicted traversable, lethal = predicted not; unknown and uncertain pieces
/// predict neither.
struct TraversabilityScore {
  double true_positive_m2 = 0;   ///< free, truth traversable
  double false_positive_m2 = 0;  ///< free, truth not traversable
  double false_negative_m2 = 0;  ///< lethal, truth traversable
  double true_negative_m2 = 0;   ///< lethal, truth not traversable
  /// TP / (TP + FP), TP / (TP + FN) and their harmonic mean; NaN when the denominator is 0.
  double precision = 0;
  double recall = 0;
  double f1 = 0;
  /// Map area within max_distance_m: known plus unknown.
  double scored_m2 = 0;
  double unknown_m2 = 0;
  /// unknown_m2 / scored_m2 (NaN if nothing is scored).
  double unknown_fraction = 0;
  /// Map area within max_distance_m that is uncertain (measured, the evidence cannot decide).
  double uncertain_m2 = 0;
  double uncertain_fraction = 0;
  /// Map area farther than max_distance_m from the truth (not scored).
  double ignored_far_m2 = 0;
  /// Area of the truth's traversable faces.
  double truth_traversable_m2 = 0;
  /// Fraction of the truth's traversable area (judged per refined face, at its centroid) with a
  /// known map face (free, lethal or uncertain: a measured surface, judged) within
  /// max_distance_m; NaN if the truth has no traversable area.
  double coverage = 0;
  /// ... with a free map face within max_distance_m.
  double free_coverage = 0;
  /// Scored map area by the label of the nearest ground-truth face.
  std::array<ClassAreas, datasets::kSurfaceLabelCount> by_label{};
  /// ... split by the truth's answer: [label][0] not traversable, [label][1] traversable.
  std::array<std::array<ClassAreas, 2>, datasets::kSurfaceLabelCount> by_label_and_truth{};
  /// Scored map area by the truth's answer: [0] not traversable, [1] traversable.
  std::array<ClassAreas, 2> by_truth{};
  /// Scored map area by the reason of the nearest ground-truth face.
  std::array<ClassAreas, kTruthReasonCount> by_reason{};
  /// With face groups given: scored map area by group and truth ([group][0] not traversable,
  /// [group][1] traversable), e.g. groups = the layer that made a face lethal.
  std::vector<std::array<ClassAreas, 2>> by_group;
};

/// Scores `map` against `truth`. The map's mesh must be in the truth's frame and in metres
/// (apply its similarity transform first); its metres_per_unit is not used. `face_groups`, if
/// not empty, gives each map face a group number for TraversabilityScore::by_group.
/// @throw std::invalid_argument if the config does not validate, the map has not one layer per
///        face, `face_groups` is neither empty nor one per face, or the truth has no faces.
TraversabilityScore scoreTraversability(const traversability::LayeredMesh& map,
                                        const GroundTruthTraversability& truth, const ScoreConfig& config,
                                        const std::vector<std::uint8_t>& face_groups = {});

}  // namespace terramesh::evaluation

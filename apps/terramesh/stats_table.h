#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "mesher/mesher.h"
#include "mesher/mesher_config.h"

namespace terramesh::cli {

/// Header of the per-update CSV written by `mesh` and `bench` (see docs/formats.md).
std::string updateCsvHeader();
/// One CSV row: the event index, kind and keyframe id, the update's stats and the map size after.
std::string updateCsvRow(std::size_t event_index, const std::string& kind, std::uint64_t id,
                         const mesher::UpdateStats& stats, const mesher::MapSize& size);

/// Prints the per-step totals of a run, as in the paper's Table II.
void printStepTotals(std::ostream& out, const mesher::UpdateStats& totals, std::size_t keyframes);

/// Prints what the mesher's input filters left out over a run: observations farther than
/// max_camera_distance_m, points never inserted (fewer than min_views keyframes in range, from
/// the final map size), insertions refused as duplicate positions.
void printInputFilters(std::ostream& out, const mesher::UpdateStats& totals,
                       const mesher::MapSize& final_size, const mesher::MesherConfig& config);

/// One warning line (no prefix, no newline) for each input filter that dropped most (> 50%) of
/// its input over a run; empty when none did.
std::vector<std::string> inputFilterWarnings(const mesher::UpdateStats& totals,
                                             const mesher::MapSize& final_size,
                                             const mesher::MesherConfig& config);

}  // namespace terramesh::cli

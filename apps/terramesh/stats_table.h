#pragma once

#include <ostream>
#include <string>

#include "mesher/mesher.h"

namespace terramesh::cli {

/// Header of the per-update CSV written by `mesh` and `bench` (see docs/formats.md).
std::string updateCsvHeader();
/// One CSV row: the event index, kind and keyframe id, the update's stats and the map size after.
std::string updateCsvRow(std::size_t event_index, const std::string& kind, std::uint64_t id,
                         const mesher::UpdateStats& stats, const mesher::MapSize& size);

/// Prints the per-step totals of a run, as in the paper's Table II.
void printStepTotals(std::ostream& out, const mesher::UpdateStats& totals, std::size_t keyframes);

}  // namespace terramesh::cli

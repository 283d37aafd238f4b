// The part of a stream one tile needs (selectTileInput's rule, docs/tiles.md "Tile input").
#include "tiling/tile_input.h"

#include <optional>
#include <stdexcept>
#include <variant>

#include "stream_positions.h"

namespace terramesh::tiling {
namespace internal {

StreamPositions lastStreamPositions(const datasets::SlamStream& stream, const traversability::MapPlane& plane) {
  StreamPositions positions;
  for (const datasets::StreamEvent& event : stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (!keyframe) continue;
    positions.keyframes[keyframe->id.value] = plane.planM(keyframe->position_W_C);
    for (const mesher::PointObservation& observation : keyframe->observations) {
      positions.points[observation.point.value] = plane.planM(observation.position_W);
    }
  }
  return positions;
}

bool keepsObservation(const StreamPositions& positions, const PlanRect& input_bounds, std::uint64_t keyframe,
                      std::uint64_t point) {
  const Eigen::Vector2d& point_xy = positions.points.at(point);
  return input_bounds.contains(point_xy) || input_bounds.meetsSegment(positions.keyframes.at(keyframe), point_xy);
}

TileMembers tileMembers(const datasets::SlamStream& stream, const StreamPositions& positions,
                        const PlanRect& input_bounds) {
  TileMembers members;
  for (const auto& [id, xy] : positions.keyframes) {
    if (input_bounds.contains(xy)) members.keyframes.insert(id);
  }
  for (const datasets::StreamEvent& event : stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (!keyframe) continue;
    for (const mesher::PointObservation& observation : keyframe->observations) {
      if (keepsObservation(positions, input_bounds, keyframe->id.value, observation.point.value)) {
        members.keyframes.insert(keyframe->id.value);
        members.points.insert(observation.point.value);
      }
    }
  }
  // Every view of a member point: the mesher counts them (min_views) as the whole stream would.
  for (const datasets::StreamEvent& event : stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (!keyframe) continue;
    for (const mesher::PointObservation& observation : keyframe->observations) {
      if (members.points.count(observation.point.value)) members.keyframes.insert(keyframe->id.value);
    }
  }
  return members;
}

}  // namespace internal

namespace {

/// The event restricted to the tile's members (a keyframe keeps its views of member points);
/// nullopt when nothing of it is left.
std::optional<datasets::StreamEvent> restrictEvent(const datasets::StreamEvent& event,
                                                   const internal::TileMembers& members) {
  if (const auto* keyframe = std::get_if<mesher::Keyframe>(&event)) {
    if (!members.keyframes.count(keyframe->id.value)) return std::nullopt;
    mesher::Keyframe kept = *keyframe;
    kept.observations.clear();
    for (const mesher::PointObservation& observation : keyframe->observations) {
      if (members.points.count(observation.point.value)) {
        kept.observations.push_back(observation);
      }
    }
    return kept;
  }
  if (const auto* removal = std::get_if<datasets::KeyframeRemoval>(&event)) {
    if (!members.keyframes.count(removal->keyframe.value)) return std::nullopt;
    return event;
  }
  datasets::PointRemoval kept;
  for (const mesher::PointId point : std::get<datasets::PointRemoval>(event).points) {
    if (members.points.count(point.value)) kept.points.push_back(point);
  }
  if (kept.points.empty()) return std::nullopt;
  return kept;
}

}  // namespace

TileInput selectTileInput(const datasets::SlamStream& stream, const TilePlan& plan, std::size_t tile) {
  if (tile >= plan.tiles.size()) {
    throw std::out_of_range("selectTileInput: tile " + std::to_string(tile) + " of a plan of " +
                            std::to_string(plan.tiles.size()) + " tiles");
  }
  const internal::StreamPositions positions = internal::lastStreamPositions(stream, plan.plane());
  const PlanRect input_bounds = plan.inputBounds(tile);
  const internal::TileMembers members = internal::tileMembers(stream, positions, input_bounds);
  TileInput input;
  // Every field but the events (not a copy of the whole stream: a tile's memory is what tiling saves).
  input.stream.metres_per_unit = stream.metres_per_unit;
  input.stream.scale_known = stream.scale_known;
  input.stream.recommended_min_views = stream.recommended_min_views;
  input.stream.recommended_steiner_step_m = stream.recommended_steiner_step_m;
  input.stream.recommend_auto_max_distance = stream.recommend_auto_max_distance;
  input.stream.sensor_up_S = stream.sensor_up_S;
  input.stream.description = stream.description;
  input.stream.keyframe_names = stream.keyframe_names;
  input.stream.reader_notes = stream.reader_notes;
  input.stream.reader_warnings = stream.reader_warnings;
  for (const datasets::StreamEvent& event : stream.events) {
    if (std::optional<datasets::StreamEvent> kept = restrictEvent(event, members)) {
      input.stream.events.push_back(std::move(*kept));
    }
  }
  input.keyframes = members.keyframes.size();
  input.points = members.points.size();
  return input;
}

}  // namespace terramesh::tiling

#include "stats_table.h"

#include <cstdio>
#include <sstream>

namespace terramesh::cli {

std::string updateCsvHeader() {
  return "event,kind,id,new_points,moved_points,removed_points,dropped_points,duplicate_points,"
         "deferred_points,steiner_points,observations,observations_too_far,points_waiting,"
         "points_waiting_too_far,rays_traced,rays_retraced,rays_untraced,rays_skipped,"
         "enclosing_cells,cells_shrunk,steiner_cells_shrunk,cells_grown,genus_pass_cells,"
         "walk_steps,cache_lookups,cache_hits,walk_fallbacks,walk_failures,"
         "time_steiner_s,time_shrink_s,time_insertion_s,time_ray_tracing_s,time_grow_s,time_total_s,"
         "map_points,map_cells,map_outside_cells,map_rays,map_bytes";
}

std::string updateCsvRow(std::size_t event_index, const std::string& kind, std::uint64_t id,
                         const mesher::UpdateStats& s, const mesher::MapSize& size) {
  std::ostringstream row;
  row << event_index << ',' << kind << ',' << id << ',' << s.new_points << ',' << s.moved_points
      << ',' << s.removed_points << ',' << s.dropped_points << ',' << s.duplicate_points << ','
      << s.deferred_points << ',' << s.steiner_points << ',' << s.observations << ','
      << s.observations_too_far << ',' << s.points_waiting << ',' << s.points_waiting_too_far << ','
      << s.rays_traced << ','
      << s.rays_retraced << ',' << s.rays_untraced << ',' << s.rays_skipped << ','
      << s.enclosing_cells << ',' << s.cells_shrunk << ',' << s.steiner_cells_shrunk << ','
      << s.cells_grown << ',' << s.genus_pass_cells << ',' << s.walk_steps << ','
      << s.cache_lookups << ',' << s.cache_hits << ',' << s.walk_fallbacks << ',' << s.walk_failures;
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), ",%.6e,%.6e,%.6e,%.6e,%.6e,%.6e", s.time.steiner_s,
                s.time.shrink_s, s.time.insertion_s, s.time.ray_tracing_s, s.time.grow_s,
                s.time.total_s);
  row << buffer << ',' << size.inserted_points << ',' << size.cells << ',' << size.outside_cells
      << ',' << size.rays << ',' << size.totalBytes();
  return row.str();
}

void printStepTotals(std::ostream& out, const mesher::UpdateStats& t, std::size_t keyframes) {
  char line[512];
  std::snprintf(line, sizeof(line),
                "time (s): steiner %.3f  shrink %.3f  insertion %.3f  ray tracing %.3f  grow %.3f  "
                "total %.3f  (%.2f ms per keyframe)\n",
                t.time.steiner_s, t.time.shrink_s, t.time.insertion_s, t.time.ray_tracing_s,
                t.time.grow_s, t.time.total_s,
                keyframes ? 1e3 * t.time.total_s / static_cast<double>(keyframes) : 0.0);
  out << line;
  std::snprintf(line, sizeof(line),
                "points: %zu new, %zu moved, %zu removed, %zu dropped, %zu duplicate, %zu deferred; "
                "rays: %zu traced, %zu retraced, %zu untraced; cells: %zu shrunk, %zu grown\n",
                t.new_points, t.moved_points, t.removed_points, t.dropped_points, t.duplicate_points,
                t.deferred_points, t.rays_traced, t.rays_retraced, t.rays_untraced, t.cells_shrunk,
                t.cells_grown);
  out << line;
}

namespace {

double percent(std::size_t part, std::size_t whole) {
  return whole ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

/// Points known to the mesher and never inserted (still waiting for views at the end).
std::size_t pointsLeftOut(const mesher::MapSize& size) {
  return size.points > size.inserted_points ? size.points - size.inserted_points : 0;
}

}  // namespace

void printInputFilters(std::ostream& out, const mesher::UpdateStats& t,
                       const mesher::MapSize& size, const mesher::MesherConfig& config) {
  char line[512];
  std::snprintf(line, sizeof(line),
                "filter max_camera_distance_m %.4g: %zu of %zu observations farther (%.1f%%)\n",
                config.max_camera_distance_m, t.observations_too_far, t.observations,
                percent(t.observations_too_far, t.observations));
  out << line;
  std::snprintf(line, sizeof(line),
                "filter min_views %d: %zu of %zu points never inserted (%.1f%%: fewer than %d "
                "keyframes within max_camera_distance_m, or a duplicate position)\n",
                config.min_views, pointsLeftOut(size), size.points,
                percent(pointsLeftOut(size), size.points), config.min_views);
  out << line;
  const std::size_t attempts = t.new_points + t.moved_points + t.duplicate_points + t.dropped_points;
  std::snprintf(line, sizeof(line),
                "filter duplicates: %zu of %zu insertions refused, a vertex already at that "
                "position (%.1f%%)\n",
                t.duplicate_points, attempts, percent(t.duplicate_points, attempts));
  out << line;
}

std::vector<std::string> inputFilterWarnings(const mesher::UpdateStats& t,
                                             const mesher::MapSize& size,
                                             const mesher::MesherConfig& config) {
  std::vector<std::string> warnings;
  char line[512];
  if (2 * t.observations_too_far > t.observations) {
    std::snprintf(line, sizeof(line),
                  "%.0f%% of the observations (%zu of %zu) are farther than %.4g m from their "
                  "camera and were ignored; if the map is not in metres set --metres-per-unit, or "
                  "try --max-distance-m auto (docs/formats.md, \"Choosing --max-distance-m\")",
                  percent(t.observations_too_far, t.observations), t.observations_too_far,
                  t.observations, config.max_camera_distance_m);
    warnings.emplace_back(line);
  }
  if (2 * pointsLeftOut(size) > size.points) {
    std::snprintf(line, sizeof(line),
                  "%.0f%% of the points (%zu of %zu) were never inserted: fewer than %d keyframes "
                  "saw them within %.4g m, or duplicate positions (see --min-views and "
                  "--max-distance-m)",
                  percent(pointsLeftOut(size), size.points), pointsLeftOut(size), size.points,
                  config.min_views, config.max_camera_distance_m);
    warnings.emplace_back(line);
  }
  const std::size_t attempts = t.new_points + t.moved_points + t.duplicate_points + t.dropped_points;
  if (2 * t.duplicate_points > attempts) {
    std::snprintf(line, sizeof(line),
                  "%.0f%% of the insertions (%zu of %zu) were refused as duplicates of a point "
                  "already at that position (the stream repeats points under new ids?)",
                  percent(t.duplicate_points, attempts), t.duplicate_points, attempts);
    warnings.emplace_back(line);
  }
  return warnings;
}

}  // namespace terramesh::cli

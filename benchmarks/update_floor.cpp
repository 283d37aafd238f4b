#include "update_floor.h"

#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <Eigen/Core>
#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>
#include <variant>

#include "bench_streams.h"
#include "cgal_types.h"
#include "ray_walk.h"

namespace terramesh::bench {
namespace {

using mesher::internal::CameraLocation;
using mesher::internal::CellHandle;
using mesher::internal::Delaunay;
using mesher::internal::Point;
using mesher::internal::RayWalker;
using mesher::internal::VertexHandle;
using mesher::internal::WalkCounters;
using SortTraits =
    CGAL::Spatial_sort_traits_adapter_3<mesher::internal::Kernel, CGAL::Pointer_property_map<Point>::type>;

/// A point of the stream: the views in range seen so far (camera positions, until inserted) and
/// its vertex once inserted.
struct FloorPoint {
  std::vector<Eigen::Vector3d> waiting_cameras;
  VertexHandle vertex;
  bool inserted = false;
};

/// Eight corners 10 units beyond everything the first `max_keyframes` keyframes hold.
std::vector<Point> enclosingCorners(const datasets::SlamStream& stream, std::size_t max_keyframes) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  std::size_t keyframes = 0;
  for (const datasets::StreamEvent& event : stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (keyframe == nullptr) continue;
    if (max_keyframes > 0 && keyframes++ == max_keyframes) break;
    lo = lo.cwiseMin(keyframe->position_W_C);
    hi = hi.cwiseMax(keyframe->position_W_C);
    for (const mesher::PointObservation& o : keyframe->observations) {
      lo = lo.cwiseMin(o.position_W);
      hi = hi.cwiseMax(o.position_W);
    }
  }
  if (!(lo.x() <= hi.x())) throw std::invalid_argument("the stream has no keyframe");
  lo.array() -= 10.0;
  hi.array() += 10.0;
  std::vector<Point> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
  }
  return corners;
}

}  // namespace

FloorRun measureFloor(const datasets::SlamStream& stream, const mesher::MesherConfig& config,
                      std::size_t max_keyframes) {
  Delaunay tri;
  const std::vector<Point> corners = enclosingCorners(stream, max_keyframes);
  tri.insert(corners.begin(), corners.end());
  const RayWalker walker(tri, config.next_cell_cache);
  const double max_distance = config.maxCameraDistanceUnits();
  const std::size_t min_views = static_cast<std::size_t>(std::max(1, config.min_views));
  std::unordered_map<std::uint64_t, FloorPoint> points;
  FloorRun run;
  std::vector<Point> batch;
  std::vector<FloorPoint*> batch_points;
  std::vector<std::pair<Eigen::Vector3d, FloorPoint*>> rays;
  std::vector<std::size_t> order;
  std::vector<CellHandle> path;
  WalkCounters counters;
  for (const datasets::StreamEvent& event : stream.events) {
    const auto* keyframe = std::get_if<mesher::Keyframe>(&event);
    if (keyframe == nullptr) continue;
    if (max_keyframes > 0 && run.keyframe_ms.size() == max_keyframes) break;
    const double start = threadCpuSeconds();
    batch.clear();
    batch_points.clear();
    rays.clear();
    const Eigen::Vector3d& camera = keyframe->position_W_C;
    for (const mesher::PointObservation& o : keyframe->observations) {
      if ((o.position_W - camera).norm() > max_distance) continue;
      FloorPoint& p = points[o.point.value];
      if (p.inserted) {
        rays.emplace_back(camera, &p);
        continue;
      }
      p.waiting_cameras.push_back(camera);
      if (p.waiting_cameras.size() < min_views) continue;
      batch.emplace_back(o.position_W.x(), o.position_W.y(), o.position_W.z());
      batch_points.push_back(&p);
    }
    // What CGAL's range insertion does, keeping the handles: a spatial sort, then each point
    // inserted with the previous one's cell as the hint.
    order.resize(batch.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    CGAL::spatial_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(batch)));
    VertexHandle hint;
    for (const std::size_t i : order) {
      FloorPoint& p = *batch_points[i];
      const std::size_t before = tri.number_of_vertices();
      hint = tri.insert(batch[i], hint == VertexHandle() ? CellHandle() : hint->cell());
      if (tri.number_of_vertices() == before) continue;  // a duplicate position: no vertex of its own
      p.vertex = hint;
      p.inserted = true;
      for (const Eigen::Vector3d& c : p.waiting_cameras) rays.emplace_back(c, &p);
      p.waiting_cameras.clear();
      ++run.points_inserted;
    }
    CameraLocation here;
    here.position = Point(camera.x(), camera.y(), camera.z());
    here.cell = tri.locate(here.position, here.type, here.li, here.lj);
    for (const auto& [c, p] : rays) {
      CameraLocation location = here;
      if (c != camera) {  // an earlier view of a point inserted now
        location.position = Point(c.x(), c.y(), c.z());
        location.cell = tri.locate(location.position, location.type, location.li, location.lj, here.cell);
      }
      walker.walk(location, p->vertex, path, counters);
      ++run.rays_walked;
    }
    run.keyframe_ms.push_back(1e3 * (threadCpuSeconds() - start));
  }
  if (run.keyframe_ms.empty()) throw std::invalid_argument("the stream has no keyframe");
  run.walk_failures = counters.failures;
  return run;
}

}  // namespace terramesh::bench

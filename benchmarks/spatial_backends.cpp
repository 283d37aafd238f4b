#include "spatial_backends.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <nanoflann.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#ifdef TERRAMESH_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace terramesh::bench {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 toCgal(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }
Eigen::Vector3d toEigen(const Kernel::Point_3& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = va + vb + vc;
  if (!(std::abs(denominator) > 0)) return a;  // zero-area triangle: its corners were tried above
  return a + ab * (vb / denominator) + ac * (vc / denominator);
}

// ---- CGAL ----------------------------------------------------------------------------------

struct CgalTriangleTree::Impl {
  Triangles triangles;
  Tree tree;
};

CgalTriangleTree::CgalTriangleTree(const mesher::TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(mesh.faces.size());
  for (const auto& face : mesh.faces) {
    impl_->triangles.emplace_back(toCgal(mesh.vertices[face[0]]), toCgal(mesh.vertices[face[1]]),
                                  toCgal(mesh.vertices[face[2]]));
  }
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

CgalTriangleTree::~CgalTriangleTree() = default;

std::optional<datasets::RayHit> CgalTriangleTree::firstHit(const Eigen::Vector3d& origin,
                                                           const Eigen::Vector3d& direction,
                                                           double max_distance) const {
  const Eigen::Vector3d unit = direction.normalized();
  const Kernel::Ray_3 ray(toCgal(origin), Kernel::Vector_3(unit.x(), unit.y(), unit.z()));
  const auto hit = impl_->tree.first_intersection(ray);
  if (!hit) return std::nullopt;
  Eigen::Vector3d point;
  if (const auto* p = boost::get<Kernel::Point_3>(&hit->first)) {
    point = toEigen(*p);
  } else {
    // The ray runs inside a face's plane: the hit is the segment's end nearer the origin.
    const auto& segment = boost::get<Kernel::Segment_3>(hit->first);
    const Eigen::Vector3d s = toEigen(segment.source()), t = toEigen(segment.target());
    point = (s - origin).norm() <= (t - origin).norm() ? s : t;
  }
  const double distance = (point - origin).norm();
  if (distance > max_distance) return std::nullopt;
  datasets::RayHit result;
  result.distance = distance;
  result.point = point;
  result.face = static_cast<std::uint32_t>(hit->second - impl_->triangles.begin());
  return result;
}

datasets::SurfacePoint CgalTriangleTree::closestPoint(const Eigen::Vector3d& query) const {
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(toCgal(query));
  datasets::SurfacePoint result;
  result.point = toEigen(point);
  result.distance = (result.point - query).norm();
  result.face = static_cast<std::uint32_t>(primitive - impl_->triangles.begin());
  return result;
}

// ---- Embree --------------------------------------------------------------------------------

#ifdef TERRAMESH_HAVE_EMBREE
struct EmbreeTriangleScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<Eigen::Vector3d> vertices;  ///< double copies for the exact closest point
  std::vector<std::array<std::uint32_t, 3>> faces;
};

namespace {

struct PointQueryState {
  const std::vector<Eigen::Vector3d>* vertices;
  const std::vector<std::array<std::uint32_t, 3>>* faces;
  Eigen::Vector3d query;
  datasets::SurfacePoint best;
  bool found = false;
};

bool closestPointCallback(RTCPointQueryFunctionArguments* args) {
  auto* state = static_cast<PointQueryState*>(args->userPtr);
  const auto& face = (*state->faces)[args->primID];
  const auto& v = *state->vertices;
  const Eigen::Vector3d point = closestPointOnTriangle(state->query, v[face[0]], v[face[1]], v[face[2]]);
  const double distance = (point - state->query).norm();
  if (!state->found || distance < state->best.distance ||
      (distance == state->best.distance && args->primID < state->best.face)) {
    state->best = {point, distance, args->primID};
    state->found = true;
    // Shrink the search (float radius, rounded up so that the exact best stays inside).
    args->query->radius = std::nextafter(static_cast<float>(distance), std::numeric_limits<float>::infinity());
    return true;
  }
  return false;
}

}  // namespace

EmbreeTriangleScene::EmbreeTriangleScene(const mesher::TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->vertices = mesh.vertices;
  impl_->faces = mesh.faces;
  impl_->device = rtcNewDevice("threads=1");
  if (!impl_->device) throw std::runtime_error("Embree: rtcNewDevice failed");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(mesh.vertices[i][k]);
  }
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.faces.size()));
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) indices[3 * f + static_cast<std::size_t>(k)] = mesh.faces[f][static_cast<std::size_t>(k)];
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
}

EmbreeTriangleScene::~EmbreeTriangleScene() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

std::optional<datasets::RayHit> EmbreeTriangleScene::firstHit(const Eigen::Vector3d& origin,
                                                              const Eigen::Vector3d& direction,
                                                              double max_distance) const {
  const Eigen::Vector3d unit = direction.normalized();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit ray_hit{};
  ray_hit.ray.org_x = static_cast<float>(origin.x());
  ray_hit.ray.org_y = static_cast<float>(origin.y());
  ray_hit.ray.org_z = static_cast<float>(origin.z());
  ray_hit.ray.dir_x = static_cast<float>(unit.x());
  ray_hit.ray.dir_y = static_cast<float>(unit.y());
  ray_hit.ray.dir_z = static_cast<float>(unit.z());
  ray_hit.ray.tnear = 0.0f;
  ray_hit.ray.tfar = std::isfinite(max_distance) ? static_cast<float>(max_distance)
                                                 : std::numeric_limits<float>::infinity();
  ray_hit.ray.mask = 0xFFFFFFFFu;
  ray_hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &ray_hit);
  if (ray_hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  datasets::RayHit result;
  result.distance = ray_hit.ray.tfar;
  result.face = ray_hit.hit.primID;
  result.point = origin + result.distance * unit;
  return result;
}

datasets::SurfacePoint EmbreeTriangleScene::closestPoint(const Eigen::Vector3d& query) const {
  RTCPointQuery point_query;
  point_query.x = static_cast<float>(query.x());
  point_query.y = static_cast<float>(query.y());
  point_query.z = static_cast<float>(query.z());
  point_query.time = 0.0f;
  point_query.radius = std::numeric_limits<float>::infinity();
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  PointQueryState state{&impl_->vertices, &impl_->faces, query, {}, false};
  rtcPointQuery(impl_->scene, &point_query, &context, closestPointCallback, &state);
  if (!state.found) throw std::logic_error("EmbreeTriangleScene: empty scene");
  return state.best;
}
#endif

// ---- nanoflann -----------------------------------------------------------------------------

namespace {

struct CloudAdaptor {
  std::vector<Eigen::Vector3d> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const { return points[index][static_cast<Eigen::Index>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box& /*box*/) const {
    return false;
  }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CloudAdaptor>, CloudAdaptor, 3, std::uint32_t>;

}  // namespace

struct NanoflannCloud::Impl {
  CloudAdaptor cloud;
  std::unique_ptr<KdTree> tree;
};

NanoflannCloud::NanoflannCloud(std::vector<Eigen::Vector3d> points) : impl_(std::make_unique<Impl>()) {
  impl_->cloud.points = std::move(points);
  impl_->tree = std::make_unique<KdTree>(3, impl_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  impl_->tree->buildIndex();
}

NanoflannCloud::~NanoflannCloud() = default;

std::optional<datasets::PointCloudIndex::Nearest> NanoflannCloud::nearest(const Eigen::Vector3d& query,
                                                                          double max_distance_m) const {
  if (impl_->cloud.points.empty()) return std::nullopt;
  std::uint32_t index = 0;
  double squared = 0.0;
  nanoflann::KNNResultSet<double, std::uint32_t> result(1);
  result.init(&index, &squared);
  impl_->tree->findNeighbors(result, query.data(), nanoflann::SearchParams());
  const double distance = (impl_->cloud.points[index] - query).norm();
  if (distance > max_distance_m) return std::nullopt;
  return datasets::PointCloudIndex::Nearest{index, distance};
}

}  // namespace terramesh::bench

#include "datasets/triangle_bvh.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/closest_point.h"

namespace terramesh::datasets {
namespace {

// Embree works in single precision. Its answers are refined in double on the faces it reports;
// it is only trusted to report every face whose double-precision answer could be the best one.
// That holds when its search is widened by this much of the scene's scale (float rounding of
// the vertices, the query and Embree's own arithmetic stay well below it).
constexpr double kFloatSlack = 64.0 * std::numeric_limits<float>::epsilon();

struct Triangle {
  Eigen::Vector3d v0, v1, v2;
};

float roundedUp(double value) {
  if (!std::isfinite(value)) return std::numeric_limits<float>::infinity();
  return std::nextafter(static_cast<float>(value), std::numeric_limits<float>::infinity());
}

float roundedDown(double value) {
  return std::max(0.0f, std::nextafter(static_cast<float>(value), -std::numeric_limits<float>::infinity()));
}

/// Per-ray constants of the watertight test (Woop, Benthin and Wald, JCGT 2013): the dominant
/// axis kz and the shear that maps the direction onto +z.
struct PreparedRay {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
  int kx = 0, ky = 1, kz = 2;
  double shear_x = 0, shear_y = 0, shear_z = 1;

  PreparedRay(const Eigen::Vector3d& o, const Eigen::Vector3d& unit_direction) : origin(o), direction(unit_direction) {
    Eigen::Index axis = 0;
    unit_direction.cwiseAbs().maxCoeff(&axis);
    kz = static_cast<int>(axis);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (unit_direction[kz] < 0) std::swap(kx, ky);  // keeps the winding of the sheared triangle
    shear_x = unit_direction[kx] / unit_direction[kz];
    shear_y = unit_direction[ky] / unit_direction[kz];
    shear_z = 1.0 / unit_direction[kz];
  }

  /// Watertight ray-triangle test in double precision; the ray parameter of the hit, if any.
  std::optional<double> hitTriangle(const Triangle& tri) const {
    const Eigen::Vector3d a = tri.v0 - origin;
    const Eigen::Vector3d b = tri.v1 - origin;
    const Eigen::Vector3d c = tri.v2 - origin;
    const double ax = a[kx] - shear_x * a[kz], ay = a[ky] - shear_y * a[kz];
    const double bx = b[kx] - shear_x * b[kz], by = b[ky] - shear_y * b[kz];
    const double cx = c[kx] - shear_x * c[kz], cy = c[ky] - shear_y * c[kz];
    double u = cx * by - cy * bx;
    double v = ax * cy - ay * cx;
    double w = bx * ay - by * ax;
    if (u == 0.0 || v == 0.0 || w == 0.0) {
      // On an edge in double precision: decide it in extended precision, as the paper does.
      using Long = long double;
      u = static_cast<double>(Long(cx) * Long(by) - Long(cy) * Long(bx));
      v = static_cast<double>(Long(ax) * Long(cy) - Long(ay) * Long(cx));
      w = static_cast<double>(Long(bx) * Long(ay) - Long(by) * Long(ax));
    }
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return std::nullopt;
    const double det = u + v + w;
    if (det == 0.0) return std::nullopt;
    return (u * shear_z * a[kz] + v * shear_z * b[kz] + w * shear_z * c[kz]) / det;
  }

  /// Where the ray meets the plane of `tri`, for a face Embree hits but the double test misses
  /// by a rounding error (a ray through an edge or vertex); nothing for a degenerate face or a
  /// ray in its plane.
  std::optional<double> hitPlane(const Triangle& tri) const {
    const Eigen::Vector3d normal = (tri.v1 - tri.v0).cross(tri.v2 - tri.v0);
    const double along = normal.dot(direction);
    if (!(std::abs(along) > 1e-12 * normal.norm())) return std::nullopt;
    return normal.dot(tri.v0 - origin) / along;
  }
};

/// A first-hit or occlusion query in flight: the ray in double precision and the best faces
/// found so far. Embree's context comes first so that the filters can find the query from it.
struct RayQuery {
  RTCIntersectContext context;
  const std::vector<Triangle>* triangles = nullptr;
  PreparedRay ray;
  double t_min = 0.0;       ///< mesh units along `ray`
  double t_max = 0.0;       ///< mesh units along `ray`
  bool open_ends = false;   ///< occlusion: hits must lie strictly inside (t_min, t_max)
  double slack_m = 0.0;     ///< widening of Embree's search, mesh units
  double shift_m = 0.0;     ///< Embree's origin lies this far behind `ray.origin`
  float embree_t_far = 0;   ///< Embree's current far limit
  // Best hit passing the double-precision test, and best hit Embree alone reports.
  double strict_t = std::numeric_limits<double>::infinity();
  std::uint32_t strict_face = 0;
  double near_t = std::numeric_limits<double>::infinity();
  std::uint32_t near_face = 0;

  RayQuery(const std::vector<Triangle>& tris, const PreparedRay& r) : triangles(&tris), ray(r) {
    rtcInitIntersectContext(&context);
  }

  /// The double-precision distance of face `face`, which Embree hit at `embree_t` along its ray,
  /// if it counts: the watertight test first; otherwise (Embree's hit grazes an edge within
  /// float rounding) the ray's crossing with the face's plane, unless that disagrees with
  /// Embree's distance (a ray almost in the plane: no hit, as in double precision).
  std::optional<double> refine(std::uint32_t face, float embree_t, bool& strict) const {
    const Triangle& tri = (*triangles)[face];
    std::optional<double> t = ray.hitTriangle(tri);
    strict = t.has_value();
    if (!t) {
      const double float_t = static_cast<double>(embree_t) - shift_m;
      t = ray.hitPlane(tri);
      if (!t || std::abs(*t - float_t) > slack_m) return std::nullopt;
    }
    const bool inside = open_ends ? (*t > t_min && *t < t_max) : (*t >= t_min && *t <= t_max);
    if (!inside) return std::nullopt;
    return t;
  }

  static bool better(double t, std::uint32_t face, double best_t, std::uint32_t best_face) {
    return t < best_t || (t == best_t && face < best_face);
  }
};

RayQuery& queryOf(const RTCFilterFunctionNArguments* args) {
  // Standard layout with the Embree context as first member: this is the query Embree was given.
  return *reinterpret_cast<RayQuery*>(args->context);
}

/// Intersection filter: records every face Embree reports that improves the double-precision
/// answer, and keeps Embree searching slightly beyond it (rather than stopping at its float
/// distance) so that faces tied or nearly tied in double precision are all examined.
void firstHitFilter(const RTCFilterFunctionNArguments* args) {
  RayQuery& query = queryOf(args);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const std::uint32_t face = RTCHitN_primID(args->hit, args->N, i);
    bool strict = false;
    const std::optional<double> t = query.refine(face, RTCRayN_tfar(args->ray, args->N, i), strict);
    bool improved = false;
    if (t && strict && RayQuery::better(*t, face, query.strict_t, query.strict_face)) {
      query.strict_t = *t;
      query.strict_face = face;
      improved = true;
    } else if (t && !strict && RayQuery::better(*t, face, query.near_t, query.near_face)) {
      query.near_t = *t;
      query.near_face = face;
      improved = true;
    }
    if (!improved) {
      args->valid[i] = 0;  // Embree restores its previous far limit
      continue;
    }
    const double best = std::min(query.strict_t, query.near_t);
    query.embree_t_far = std::min(query.embree_t_far, roundedUp(best + query.shift_m + query.slack_m));
    RTCRayN_tfar(args->ray, args->N, i) = query.embree_t_far;
  }
}

/// Occlusion filter: a face occludes when its double-precision distance lies inside the segment.
void occlusionFilter(const RTCFilterFunctionNArguments* args) {
  RayQuery& query = queryOf(args);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    bool strict = false;
    if (!query.refine(RTCHitN_primID(args->hit, args->N, i), RTCRayN_tfar(args->ray, args->N, i), strict)) {
      args->valid[i] = 0;
    }
  }
}

/// A closest-point query in flight.
struct PointQuery {
  const std::vector<Triangle>* triangles = nullptr;
  Eigen::Vector3d query;
  double slack_m = 0.0;
  double best_d2 = std::numeric_limits<double>::infinity();
  SurfacePoint best;
};

/// Point-query callback: the exact double-precision distance to each face Embree offers; the
/// search radius shrinks to the best distance plus the float slack.
bool closestPointCallback(RTCPointQueryFunctionArguments* args) {
  auto& state = *static_cast<PointQuery*>(args->userPtr);
  const Triangle& tri = (*state.triangles)[args->primID];
  const Eigen::Vector3d point = geometry::closestPointOnTriangle(state.query, tri.v0, tri.v1, tri.v2);
  const double d2 = (point - state.query).squaredNorm();
  if (!(d2 < state.best_d2 || (d2 == state.best_d2 && args->primID < state.best.face))) return false;
  state.best_d2 = d2;
  state.best.point = point;
  state.best.face = args->primID;
  args->query->radius = roundedUp(std::sqrt(d2) + state.slack_m);
  return true;
}

/// A faces-within query in flight: the radius stays fixed (widened by the float slack for
/// Embree); each face offered is measured in double.
struct RangeQuery {
  const std::vector<Triangle>* triangles = nullptr;
  Eigen::Vector3d centre;
  double radius_sq = 0.0;
  std::vector<std::uint32_t> faces;
};

bool rangeCallback(RTCPointQueryFunctionArguments* args) {
  auto& state = *static_cast<RangeQuery*>(args->userPtr);
  const Triangle& tri = (*state.triangles)[args->primID];
  const Eigen::Vector3d point = geometry::closestPointOnTriangle(state.centre, tri.v0, tri.v1, tri.v2);
  if ((point - state.centre).squaredNorm() <= state.radius_sq) state.faces.push_back(args->primID);
  return false;
}

}  // namespace

struct TriangleBvh::Impl {
  std::vector<Triangle> triangles;  ///< by face index, in double precision
  Eigen::AlignedBox3d bounds;
  /// Embree sees the mesh moved by -centre (smaller coordinates, smaller float rounding).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double extent_m = 0.0;  ///< largest |coordinate - centre| of the mesh
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  void build(const mesher::TriangleMesh& mesh) {
    device = rtcNewDevice("threads=1");
    if (!device) throw std::runtime_error("TriangleBvh: Embree could not create a device");
    scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.vertices.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.faces.size()));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      throw std::runtime_error("TriangleBvh: Embree could not allocate the geometry");
    }
    // Shared vertices stay shared in float, so Embree's robust mode keeps closed meshes closed.
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      const Eigen::Vector3d local = mesh.vertices[i] - centre;
      for (Eigen::Index axis = 0; axis < 3; ++axis) {
        vertices[3 * i + static_cast<std::size_t>(axis)] = static_cast<float>(local[axis]);
      }
    }
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      for (std::size_t k = 0; k < 3; ++k) indices[3 * f + k] = mesh.faces[f][k];
    }
    rtcSetGeometryIntersectFilterFunction(geometry, firstHitFilter);
    rtcSetGeometryOccludedFilterFunction(geometry, occlusionFilter);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE) throw std::runtime_error("TriangleBvh: Embree failed to build");
  }

  /// The float slack of a query whose points lie within `reach_m` of the centre.
  double slackFor(double reach_m) const { return kFloatSlack * (extent_m + reach_m) + 1e-30; }

  /// An Embree ray for `ray` covering [t_begin, t_end] (and the slack around it).
  RTCRay embreeRay(RayQuery& query, double t_begin, double t_end) const {
    const Eigen::Vector3d local = query.ray.origin - centre;
    const double reach = local.cwiseAbs().maxCoeff() + (std::isfinite(t_end) ? t_end : 0.0);
    query.slack_m = slackFor(reach);
    query.shift_m = query.slack_m;
    const Eigen::Vector3d start = local - query.shift_m * query.ray.direction;
    RTCRay ray{};
    ray.org_x = static_cast<float>(start.x());
    ray.org_y = static_cast<float>(start.y());
    ray.org_z = static_cast<float>(start.z());
    ray.dir_x = static_cast<float>(query.ray.direction.x());
    ray.dir_y = static_cast<float>(query.ray.direction.y());
    ray.dir_z = static_cast<float>(query.ray.direction.z());
    ray.tnear = roundedDown(t_begin + query.shift_m - query.slack_m);
    ray.tfar = roundedUp(t_end + query.shift_m + query.slack_m);
    ray.mask = 0xFFFFFFFFu;
    ray.flags = 0;
    query.embree_t_far = ray.tfar;
    return ray;
  }
};

TriangleBvh::TriangleBvh(const mesher::TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->triangles.reserve(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    Triangle tri;
    Eigen::Vector3d* corners[3] = {&tri.v0, &tri.v1, &tri.v2};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t vertex = mesh.faces[f][k];
      if (vertex >= mesh.vertices.size()) {
        throw std::invalid_argument("TriangleBvh: face " + std::to_string(f) + " uses vertex " +
                                    std::to_string(vertex) + " of " + std::to_string(mesh.vertices.size()));
      }
      if (!mesh.vertices[vertex].allFinite()) {
        throw std::invalid_argument("TriangleBvh: vertex " + std::to_string(vertex) + " is not finite");
      }
      *corners[k] = mesh.vertices[vertex];
      impl_->bounds.extend(*corners[k]);
    }
    impl_->triangles.push_back(tri);
  }
  if (impl_->triangles.empty()) return;
  impl_->centre = impl_->bounds.center();
  impl_->extent_m = (impl_->bounds.max() - impl_->centre).cwiseAbs().maxCoeff();
  impl_->build(mesh);
}

TriangleBvh::~TriangleBvh() = default;
TriangleBvh::TriangleBvh(TriangleBvh&&) noexcept = default;
TriangleBvh& TriangleBvh::operator=(TriangleBvh&&) noexcept = default;

std::size_t TriangleBvh::faceCount() const { return impl_->triangles.size(); }

Eigen::AlignedBox3d TriangleBvh::bounds() const { return impl_->bounds; }

std::optional<RayHit> TriangleBvh::firstHit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                            double max_distance) const {
  const double length = direction.norm();
  if (!origin.allFinite() || !direction.allFinite() || length == 0.0) {
    throw std::invalid_argument("TriangleBvh::firstHit: origin and direction must be finite, direction non-zero");
  }
  if (!impl_->scene || !(max_distance >= 0.0)) return std::nullopt;
  const Eigen::Vector3d unit = direction / length;
  RayQuery query(impl_->triangles, PreparedRay(origin, unit));
  query.t_min = 0.0;
  query.t_max = max_distance;
  RTCRayHit ray_hit{};
  ray_hit.ray = impl_->embreeRay(query, 0.0, max_distance);
  ray_hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &query.context, &ray_hit);
  // A face Embree hits but the double test misses stands only where no face passing the double
  // test lies at (practically) the same distance.
  const bool strict = std::isfinite(query.strict_t) &&
                      !(query.near_t + query.slack_m < query.strict_t);
  if (strict) return RayHit{query.strict_t, query.strict_face, origin + query.strict_t * unit};
  if (std::isfinite(query.near_t)) return RayHit{query.near_t, query.near_face, origin + query.near_t * unit};
  return std::nullopt;
}

bool TriangleBvh::segmentOccluded(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tolerance) const {
  if (!a.allFinite() || !b.allFinite() || !(tolerance >= 0.0)) {
    throw std::invalid_argument("TriangleBvh::segmentOccluded: ends must be finite and tolerance >= 0");
  }
  const double length = (b - a).norm();
  if (length <= 2.0 * tolerance || !impl_->scene) return false;
  RayQuery query(impl_->triangles, PreparedRay(a, (b - a) / length));
  query.t_min = tolerance;
  query.t_max = length - tolerance;
  query.open_ends = true;
  RTCRay ray = impl_->embreeRay(query, query.t_min, query.t_max);
  rtcOccluded1(impl_->scene, &query.context, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();  // Embree's mark of an occluded ray
}

SurfacePoint TriangleBvh::closestPoint(const Eigen::Vector3d& query) const {
  if (!impl_->scene) throw std::logic_error("TriangleBvh::closestPoint: the tree is empty");
  if (!query.allFinite()) throw std::invalid_argument("TriangleBvh::closestPoint: query not finite");
  const Eigen::Vector3d local = query - impl_->centre;
  PointQuery state;
  state.triangles = &impl_->triangles;
  state.query = query;
  state.slack_m = impl_->slackFor(local.cwiseAbs().maxCoeff());
  RTCPointQuery point_query{};
  point_query.x = static_cast<float>(local.x());
  point_query.y = static_cast<float>(local.y());
  point_query.z = static_cast<float>(local.z());
  point_query.time = 0.0f;
  point_query.radius = std::numeric_limits<float>::infinity();
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &point_query, &context, closestPointCallback, &state);
  if (!std::isfinite(state.best_d2)) throw std::logic_error("TriangleBvh::closestPoint: Embree offered no face");
  state.best.distance = std::sqrt(state.best_d2);
  return state.best;
}

std::vector<std::uint32_t> TriangleBvh::facesWithin(const Eigen::Vector3d& centre, double radius) const {
  if (!centre.allFinite() || !std::isfinite(radius)) {
    throw std::invalid_argument("TriangleBvh::facesWithin: centre and radius must be finite");
  }
  if (!impl_->scene || radius < 0.0) return {};
  const Eigen::Vector3d local = centre - impl_->centre;
  RangeQuery state;
  state.triangles = &impl_->triangles;
  state.centre = centre;
  state.radius_sq = radius * radius;
  RTCPointQuery point_query{};
  point_query.x = static_cast<float>(local.x());
  point_query.y = static_cast<float>(local.y());
  point_query.z = static_cast<float>(local.z());
  point_query.time = 0.0f;
  point_query.radius = roundedUp(radius + impl_->slackFor(local.cwiseAbs().maxCoeff() + radius));
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &point_query, &context, rangeCallback, &state);
  std::sort(state.faces.begin(), state.faces.end());
  state.faces.erase(std::unique(state.faces.begin(), state.faces.end()), state.faces.end());
  return state.faces;
}

}  // namespace terramesh::datasets

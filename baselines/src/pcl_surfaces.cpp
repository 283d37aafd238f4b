#include "baselines/pcl_surfaces.h"

#include <pcl/PolygonMesh.h>
#include <pcl/common/common.h>
#include <pcl/conversions.h>
#include <pcl/features/normal_3d.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/gp3.h>
#include <pcl/surface/marching_cubes_hoppe.h>
#include <pcl/surface/poisson.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "baselines/weld_vertices.h"
#include "pcl_mesh_conversion.h"

namespace terramesh::baselines {

const char* toString(PclMethod method) {
  switch (method) {
    case PclMethod::kGreedyProjection: return "greedy";
    case PclMethod::kPoisson: return "poisson";
    case PclMethod::kMarchingCubesHoppe: return "marching-cubes";
  }
  return "unknown";
}

void PclSurfaceConfig::validate() const {
  std::ostringstream problems;
  auto positive = [&problems](const char* name, double value) {
    if (!(value > 0) || !std::isfinite(value)) problems << ' ' << name << ": " << value << " (expected > 0);";
  };
  if (normal_neighbours < 3) problems << " normal_neighbours: " << normal_neighbours << " (expected >= 3);";
  positive("greedy_radius_spacings", greedy_radius_spacings);
  positive("greedy_mu", greedy_mu);
  if (greedy_max_neighbours < 3) problems << " greedy_max_neighbours: " << greedy_max_neighbours << " (expected >= 3);";
  if (!(greedy_max_surface_angle_deg > 0 && greedy_max_surface_angle_deg <= 180)) {
    problems << " greedy_max_surface_angle_deg: " << greedy_max_surface_angle_deg << " (expected (0, 180]);";
  }
  if (!(greedy_min_angle_deg > 0 && greedy_min_angle_deg < greedy_max_angle_deg && greedy_max_angle_deg < 180)) {
    problems << " greedy_min_angle_deg, greedy_max_angle_deg: " << greedy_min_angle_deg << ", " << greedy_max_angle_deg
             << " (expected 0 < min < max < 180);";
  }
  if (poisson_depth < 2 || poisson_depth > 14) problems << " poisson_depth: " << poisson_depth << " (expected [2, 14]);";
  positive("poisson_samples_per_node", poisson_samples_per_node);
  positive("mc_cell_spacings", mc_cell_spacings);
  if (mc_max_cells_per_axis < 2 || mc_max_cells_per_axis > 1024) {
    problems << " mc_max_cells_per_axis: " << mc_max_cells_per_axis << " (expected [2, 1024]);";
  }
  positive("mc_ignore_spacings", mc_ignore_spacings);
  positive("support_spacings", support_spacings);
  const std::string text = problems.str();
  if (!text.empty()) throw std::invalid_argument("PclSurfaceConfig:" + text);
}

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// Points relative to `origin` (float precision is kept near the data), as a PCL cloud.
pcl::PointCloud<pcl::PointXYZ>::Ptr toCloud(const std::vector<Eigen::Vector3d>& points_W, const Eigen::Vector3d& origin) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(points_W.size());
  for (const Eigen::Vector3d& p : points_W) {
    const Eigen::Vector3f q = (p - origin).cast<float>();
    cloud->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
  }
  return cloud;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

/// Flips whole connected components (through shared vertices) whose faces mostly disagree,
/// area-weighted, with the normal of the input point nearest to each face's centroid. The methods'
/// own winding conventions differ; the input normals point towards the cameras.
void orientLikeInput(mesher::TriangleMesh& mesh, const pcl::PointCloud<pcl::PointNormal>& input,
                     const pcl::search::KdTree<pcl::PointNormal>& tree, const Eigen::Vector3d& origin) {
  const std::size_t n = mesh.vertices.size();
  std::vector<std::uint32_t> parent(n);
  for (std::uint32_t i = 0; i < n; ++i) parent[i] = i;
  auto find = [&parent](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto& f : mesh.faces) {
    parent[find(f[1])] = find(f[0]);
    parent[find(f[2])] = find(f[0]);
  }
  std::vector<double> vote(n, 0.0);
  pcl::Indices nearest(1);
  std::vector<float> distances(1);
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d& a = mesh.vertices[f[0]];
    const Eigen::Vector3d cross = (mesh.vertices[f[1]] - a).cross(mesh.vertices[f[2]] - a);
    const Eigen::Vector3f centroid =
        ((a + mesh.vertices[f[1]] + mesh.vertices[f[2]]) / 3.0 - origin).cast<float>();
    pcl::PointNormal query;
    query.x = centroid.x();
    query.y = centroid.y();
    query.z = centroid.z();
    if (tree.nearestKSearch(query, 1, nearest, distances) < 1) continue;
    const Eigen::Vector3d normal = input[static_cast<std::size_t>(nearest[0])].getNormalVector3fMap().cast<double>();
    vote[find(f[0])] += cross.dot(normal);
  }
  for (auto& f : mesh.faces) {
    if (vote[find(f[0])] < 0) std::swap(f[1], f[2]);
  }
}

/// Flags the vertices farther than `radius` from every input point (is_steiner = 1).
void flagUnsupported(mesher::TriangleMesh& mesh, const pcl::search::KdTree<pcl::PointNormal>& tree,
                     const Eigen::Vector3d& origin, double radius) {
  mesh.is_steiner.assign(mesh.vertices.size(), 0);
  pcl::Indices nearest(1);
  std::vector<float> squared(1);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Eigen::Vector3f p = (mesh.vertices[v] - origin).cast<float>();
    pcl::PointNormal query;
    query.x = p.x();
    query.y = p.y();
    query.z = p.z();
    const bool found = tree.nearestKSearch(query, 1, nearest, squared) > 0;
    mesh.is_steiner[v] = !found || std::sqrt(static_cast<double>(squared[0])) > radius;
  }
}

}  // namespace

double medianPointSpacing(const std::vector<Eigen::Vector3d>& points_W) {
  if (points_W.size() < 2) return 0;
  const Eigen::Vector3d origin = points_W.front();
  const pcl::PointCloud<pcl::PointXYZ>::Ptr cloud = toCloud(points_W, origin);
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  std::vector<double> nearest;
  nearest.reserve(cloud->size());
  pcl::Indices indices(2);
  std::vector<float> squared(2);
  for (const pcl::PointXYZ& p : *cloud) {
    if (tree.nearestKSearch(p, 2, indices, squared) == 2) nearest.push_back(std::sqrt(static_cast<double>(squared[1])));
  }
  return median(std::move(nearest));
}

PclSurfaceResult reconstructWithPcl(const SlamPoints& points, PclMethod method, const PclSurfaceConfig& config) {
  config.validate();
  if (points.size() < static_cast<std::size_t>(config.normal_neighbours) + 1) {
    throw std::invalid_argument("reconstructWithPcl: " + std::to_string(points.size()) + " points, at least " +
                                std::to_string(config.normal_neighbours + 1) + " needed");
  }
  PclSurfaceResult result;
  const auto started = Clock::now();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points.positions_W) origin += p;
  origin /= static_cast<double>(points.size());
  const pcl::PointCloud<pcl::PointXYZ>::Ptr cloud = toCloud(points.positions_W, origin);
  result.spacing_units = medianPointSpacing(points.positions_W);
  const double s = result.spacing_units > 0 ? result.spacing_units : 1.0;

  // Normals from the k nearest neighbours, each turned towards its own point's camera.
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  pcl::search::KdTree<pcl::PointXYZ>::Ptr xyz_tree(new pcl::search::KdTree<pcl::PointXYZ>);
  estimation.setInputCloud(cloud);
  estimation.setSearchMethod(xyz_tree);
  estimation.setKSearch(config.normal_neighbours);
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  pcl::PointCloud<pcl::PointNormal>::Ptr oriented(new pcl::PointCloud<pcl::PointNormal>);
  oriented->reserve(cloud->size());
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    pcl::PointNormal p;
    p.x = (*cloud)[i].x;
    p.y = (*cloud)[i].y;
    p.z = (*cloud)[i].z;
    p.normal_x = normals[i].normal_x;
    p.normal_y = normals[i].normal_y;
    p.normal_z = normals[i].normal_z;
    if (!std::isfinite(p.normal_x) || !std::isfinite(p.normal_y) || !std::isfinite(p.normal_z)) continue;
    const Eigen::Vector3f vp = (points.viewpoints_W[i] - origin).cast<float>();
    pcl::flipNormalTowardsViewpoint((*cloud)[i], vp.x(), vp.y(), vp.z(), p.normal_x, p.normal_y, p.normal_z);
    p.curvature = normals[i].curvature;
    oriented->push_back(p);
  }
  pcl::search::KdTree<pcl::PointNormal>::Ptr tree(new pcl::search::KdTree<pcl::PointNormal>);
  tree->setInputCloud(oriented);
  result.normals_seconds = since(started);

  const auto surface_started = Clock::now();
  pcl::PolygonMesh polygons;
  std::ostringstream parameters;
  parameters << "spacing_s " << s << "; normals k " << config.normal_neighbours
             << " nearest, each flipped towards its point's nearest observing camera";
  if (method == PclMethod::kGreedyProjection) {
    pcl::GreedyProjectionTriangulation<pcl::PointNormal> greedy;
    greedy.setSearchRadius(config.greedy_radius_spacings * s);
    greedy.setMu(config.greedy_mu);
    greedy.setMaximumNearestNeighbors(config.greedy_max_neighbours);
    greedy.setMaximumSurfaceAngle(config.greedy_max_surface_angle_deg * M_PI / 180.0);
    greedy.setMinimumAngle(config.greedy_min_angle_deg * M_PI / 180.0);
    greedy.setMaximumAngle(config.greedy_max_angle_deg * M_PI / 180.0);
    greedy.setNormalConsistency(true);
    greedy.setConsistentVertexOrdering(true);
    greedy.setInputCloud(oriented);
    greedy.setSearchMethod(tree);
    greedy.reconstruct(polygons);
    parameters << "; search radius " << config.greedy_radius_spacings * s << " (" << config.greedy_radius_spacings
               << " s), mu " << config.greedy_mu << ", max neighbours " << config.greedy_max_neighbours
               << ", max surface angle " << config.greedy_max_surface_angle_deg << " deg, triangle angles "
               << config.greedy_min_angle_deg << "-" << config.greedy_max_angle_deg << " deg";
  } else if (method == PclMethod::kPoisson) {
    pcl::Poisson<pcl::PointNormal> poisson;
    poisson.setDepth(config.poisson_depth);
    poisson.setSamplesPerNode(static_cast<float>(config.poisson_samples_per_node));
    poisson.setInputCloud(oriented);
    poisson.reconstruct(polygons);
    parameters << "; depth " << config.poisson_depth << ", samples per node " << config.poisson_samples_per_node;
  } else {
    Eigen::Vector4f min_p, max_p;
    pcl::getMinMax3D(*oriented, min_p, max_p);
    const Eigen::Vector3d extent = (max_p - min_p).head<3>().cast<double>();
    const double cell = std::max(config.mc_cell_spacings * s, extent.maxCoeff() / config.mc_max_cells_per_axis);
    const auto cells = [&](double length) { return std::max(2, static_cast<int>(std::ceil(length / cell))); };
    pcl::MarchingCubesHoppe<pcl::PointNormal> cubes;
    cubes.setIsoLevel(0.0f);
    cubes.setGridResolution(cells(extent.x()), cells(extent.y()), cells(extent.z()));
    cubes.setPercentageExtendGrid(0.0f);
    // PCL compares the squared nearest distance with this value.
    const double ignore = config.mc_ignore_spacings * s;
    cubes.setDistanceIgnore(static_cast<float>(ignore * ignore));
    cubes.setInputCloud(oriented);
    cubes.setSearchMethod(tree);
    cubes.reconstruct(polygons);
    parameters << "; cell " << cell << " (grid " << cells(extent.x()) << " x " << cells(extent.y()) << " x "
               << cells(extent.z()) << "), field ignored beyond " << ignore << " (" << config.mc_ignore_spacings
               << " s) of every point";
  }
  result.surface_seconds = since(surface_started);
  mesher::TriangleMesh mesh = fromPolygonMesh(polygons, "reconstruction");
  for (Eigen::Vector3d& v : mesh.vertices) v += origin;
  if (method == PclMethod::kMarchingCubesHoppe) mesh = weldVertices(mesh, 1e-4 * s);
  orientLikeInput(mesh, *oriented, *tree, origin);
  flagUnsupported(mesh, *tree, origin, config.support_spacings * s);
  parameters << "; vertices farther than " << config.support_spacings * s << " (" << config.support_spacings
             << " s) from every point flagged unsupported";
  result.mesh = std::move(mesh);
  result.parameters = parameters.str();
  return result;
}

}  // namespace terramesh::baselines

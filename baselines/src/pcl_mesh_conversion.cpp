#include "pcl_mesh_conversion.h"

#include <pcl/PCLPointField.h>
#include <pcl/conversions.h>
#include <pcl/point_types.h>

#include <cstring>

#include "common/input_error.h"

namespace terramesh::baselines {

double readFieldValue(const std::uint8_t* data, const pcl::PCLPointField& f) {
  switch (f.datatype) {
    case pcl::PCLPointField::INT8: { std::int8_t v; std::memcpy(&v, data + f.offset, 1); return v; }
    case pcl::PCLPointField::UINT8: { std::uint8_t v; std::memcpy(&v, data + f.offset, 1); return v; }
    case pcl::PCLPointField::INT16: { std::int16_t v; std::memcpy(&v, data + f.offset, 2); return v; }
    case pcl::PCLPointField::UINT16: { std::uint16_t v; std::memcpy(&v, data + f.offset, 2); return v; }
    case pcl::PCLPointField::INT32: { std::int32_t v; std::memcpy(&v, data + f.offset, 4); return v; }
    case pcl::PCLPointField::UINT32: { std::uint32_t v; std::memcpy(&v, data + f.offset, 4); return v; }
    case pcl::PCLPointField::FLOAT32: { float v; std::memcpy(&v, data + f.offset, 4); return v; }
    case pcl::PCLPointField::FLOAT64: { double v; std::memcpy(&v, data + f.offset, 8); return v; }
    default: return 0;
  }
}

namespace {

const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& cloud, const std::string& name) {
  for (const pcl::PCLPointField& f : cloud.fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

}  // namespace

pcl::PolygonMesh toPolygonMesh(const mesher::TriangleMesh& mesh) {
  pcl::PolygonMesh polygons;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices) {
    cloud.push_back(pcl::PointXYZ(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())));
  }
  pcl::toPCLPointCloud2(cloud, polygons.cloud);
  polygons.polygons.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    pcl::Vertices corners;
    corners.vertices = {static_cast<pcl::index_t>(f[0]), static_cast<pcl::index_t>(f[1]), static_cast<pcl::index_t>(f[2])};
    polygons.polygons.push_back(std::move(corners));
  }
  return polygons;
}

mesher::TriangleMesh fromPolygonMesh(const pcl::PolygonMesh& polygons, const std::string& source) {
  const pcl::PCLPointCloud2& cloud = polygons.cloud;
  const pcl::PCLPointField* axes[3] = {findField(cloud, "x"), findField(cloud, "y"), findField(cloud, "z")};
  mesher::TriangleMesh mesh;
  const std::size_t count = static_cast<std::size_t>(cloud.width) * cloud.height;
  if (count > 0 && (!axes[0] || !axes[1] || !axes[2])) throw InputError(source, "vertex", "fields x, y and z");
  const pcl::PCLPointField* steiner = findField(cloud, "steiner");
  mesh.vertices.resize(count);
  if (steiner) mesh.is_steiner.resize(count);
  for (std::size_t v = 0; v < count; ++v) {
    const std::uint8_t* data = cloud.data.data() + v * cloud.point_step;
    for (int a = 0; a < 3; ++a) mesh.vertices[v][a] = readFieldValue(data, *axes[a]);
    if (steiner) mesh.is_steiner[v] = readFieldValue(data, *steiner) != 0 ? 1 : 0;
  }
  for (std::size_t p = 0; p < polygons.polygons.size(); ++p) {
    const auto& corners = polygons.polygons[p].vertices;
    for (const auto index : corners) {
      if (index < 0 || static_cast<std::size_t>(index) >= count) {
        throw InputError(source, "polygon " + std::to_string(p), "vertex indices below " + std::to_string(count));
      }
    }
    for (std::size_t i = 2; i < corners.size(); ++i) {
      mesh.faces.push_back({static_cast<std::uint32_t>(corners[0]), static_cast<std::uint32_t>(corners[i - 1]),
                            static_cast<std::uint32_t>(corners[i])});
    }
  }
  return mesh;
}

}  // namespace terramesh::baselines

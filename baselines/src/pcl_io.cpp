#include "baselines/pcl_io.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl/io/obj_io.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/io/vtk_io.h>
#include <pcl/point_types.h>

#include <cstring>
#include <stdexcept>
#include <system_error>

#include "common/input_error.h"
#include "pcl_mesh_conversion.h"

namespace terramesh::baselines {

namespace {

/// Lets PCL write `path` through a temporary file beside it, then renames it into place: readers
/// never see a partial file. `write` returns PCL's status (0 = success).
template <class Write>
void writeThroughTemporary(const std::filesystem::path& path, const char* what, Write write) {
  std::filesystem::path temporary = path;
  temporary += ".partial" + path.extension().string();
  if (write(temporary.string()) != 0) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(std::string(what) + ": PCL could not write " + path.string());
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) throw std::runtime_error(std::string(what) + ": cannot rename into " + path.string() + ": " + error.message());
}

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

pcl::PCLPointField floatField(const std::string& name, std::uint32_t offset) {
  pcl::PCLPointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = pcl::PCLPointField::FLOAT32;
  f.count = 1;
  return f;
}

}  // namespace

void writeMeshWithPcl(const std::filesystem::path& path, const mesher::TriangleMesh& mesh) {
  const std::string ext = lowerExtension(path);
  if (ext != ".ply" && ext != ".obj" && ext != ".vtk") {
    throw std::invalid_argument("writeMeshWithPcl: " + path.string() + ": expected .ply, .obj or .vtk");
  }
  const pcl::PolygonMesh polygons = toPolygonMesh(mesh);
  writeThroughTemporary(path, "writeMeshWithPcl", [&](const std::string& file) {
    if (ext == ".ply") return pcl::io::savePLYFileBinary(file, polygons);
    if (ext == ".obj") return pcl::io::saveOBJFile(file, polygons, 9);
    return pcl::io::saveVTKFile(file, polygons, 9);
  });
}

mesher::TriangleMesh readMeshWithPcl(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext != ".ply" && ext != ".obj") {
    throw std::invalid_argument("readMeshWithPcl: " + path.string() + ": expected .ply or .obj");
  }
  if (!std::filesystem::is_regular_file(path)) throw InputError(path.string(), "file", "an existing mesh file");
  pcl::PolygonMesh polygons;
  const int status = ext == ".ply" ? pcl::io::loadPLYFile(path.string(), polygons)
                                   : pcl::io::loadOBJFile(path.string(), polygons);
  if (status < 0) throw InputError(path.string(), "header", "a mesh PCL's reader accepts");
  return fromPolygonMesh(polygons, path.string());
}

void writeSlamPointsPcd(const std::filesystem::path& path, const SlamPoints& points, double scale) {
  pcl::PointCloud<pcl::PointWithViewpoint> cloud;
  cloud.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p = (points.positions_W[i] * scale).cast<float>();
    const Eigen::Vector3f vp = (points.viewpoints_W[i] * scale).cast<float>();
    cloud.push_back(pcl::PointWithViewpoint(p.x(), p.y(), p.z(), vp.x(), vp.y(), vp.z()));
  }
  writeThroughTemporary(path, "writeSlamPointsPcd", [&](const std::string& file) {
    return cloud.empty() ? pcl::io::savePCDFileASCII(file, cloud) : pcl::io::savePCDFileBinary(file, cloud);
  });
}

void writeTraversabilityPcd(const std::filesystem::path& path, const traversability::LayeredMesh& map) {
  if (map.layers.size() != map.mesh.faces.size()) {
    throw std::invalid_argument("writeTraversabilityPcd: " + std::to_string(map.layers.size()) + " layers for " +
                                std::to_string(map.mesh.faces.size()) + " faces");
  }
  const char* const names[] = {"x", "y", "z", "cost", "class", "slope_deg", "step_m", "roughness_m", "contact",
                               "contact_best", "clearance_m", "lethal_distance_m", "rays", "steiner"};
  constexpr std::size_t kFields = sizeof(names) / sizeof(names[0]);
  pcl::PCLPointCloud2 cloud;
  for (std::size_t i = 0; i < kFields; ++i) cloud.fields.push_back(floatField(names[i], static_cast<std::uint32_t>(4 * i)));
  cloud.point_step = static_cast<std::uint32_t>(4 * kFields);
  cloud.width = static_cast<std::uint32_t>(map.mesh.faces.size());
  cloud.height = 1;
  cloud.is_dense = false;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
  for (std::size_t f = 0; f < map.mesh.faces.size(); ++f) {
    const auto& tri = map.mesh.faces[f];
    const Eigen::Vector3d c = (map.mesh.vertices[tri[0]] + map.mesh.vertices[tri[1]] + map.mesh.vertices[tri[2]]) / 3.0;
    const traversability::FaceLayers& l = map.layers[f];
    const float values[kFields] = {static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()),
                                   l.cost, static_cast<float>(l.face_class), l.slope_deg, l.step_m, l.roughness_m,
                                   l.contact, l.contact_best, l.clearance_m, l.lethal_distance_m,
                                   static_cast<float>(l.rays), l.steiner ? 1.0f : 0.0f};
    std::memcpy(cloud.data.data() + f * cloud.point_step, values, sizeof(values));
  }
  writeThroughTemporary(path, "writeTraversabilityPcd", [&](const std::string& file) {
    pcl::PCDWriter writer;
    return writer.writeBinary(file, cloud);
  });
}

int PcdContents::field(const std::string& name) const {
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (fields[i] == name) return static_cast<int>(i);
  }
  return -1;
}

PcdContents readPcdWithPcl(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path.string(), "file", "an existing PCD file");
  pcl::PCLPointCloud2 cloud;
  pcl::PCDReader reader;
  if (reader.read(path.string(), cloud) < 0) throw InputError(path.string(), "header", "a PCD file PCL's reader accepts");
  PcdContents contents;
  contents.width = cloud.width;
  contents.height = cloud.height;
  for (const pcl::PCLPointField& f : cloud.fields) contents.fields.push_back(f.name);
  const std::size_t count = static_cast<std::size_t>(cloud.width) * cloud.height;
  contents.values.assign(count, std::vector<double>(cloud.fields.size()));
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* point = cloud.data.data() + i * cloud.point_step;
    for (std::size_t f = 0; f < cloud.fields.size(); ++f) contents.values[i][f] = readFieldValue(point, cloud.fields[f]);
  }
  return contents;
}

}  // namespace terramesh::baselines

// traversability.h5: the map in lvr2's HDF5 MeshIO layout, the file mesh_navigation's mesh_map
// opens (lvr2 `hdf5features::MeshIO`, docs/formats.md). HDF5 stays inside this file.
#include <hdf5.h>

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/atomic_file.h"
#include "export_writers.h"

namespace terramesh::traversability::internal {
namespace {

/// Closes an HDF5 identifier when it goes out of scope; a negative id is a failed call.
class Id {
 public:
  Id(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) throw std::runtime_error(what);
  }
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  ~Id() { close_(id_); }
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// Turns HDF5's printing of its error stack off while a file is written (libraries never print).
class QuietErrors {
 public:
  QuietErrors() {
    H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;
  ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
};

/// A creation property list that stamps no time on the objects it creates: the same map gives
/// the same bytes (HDF5 records each object's write time by default).
hid_t untimed(hid_t list_class) {
  const hid_t list = H5Pcreate(list_class);
  if (list >= 0 && H5Pset_obj_track_times(list, 0) < 0) {
    H5Pclose(list);
    return -1;
  }
  return list;
}

class MeshFileWriter {
 public:
  explicit MeshFileWriter(std::string file)
      : file_(std::move(file)),
        group_list_(untimed(H5P_GROUP_CREATE), H5Pclose, failed("group creation list")),
        dataset_list_(untimed(H5P_DATASET_CREATE), H5Pclose, failed("dataset creation list")) {}

  Id group(hid_t parent, const char* name) const {
    return Id(H5Gcreate2(parent, name, H5P_DEFAULT, group_list_, H5P_DEFAULT), H5Gclose, failed("group " + std::string(name)));
  }

  /// A scalar variable-length UTF-8 string attribute: what HighFive's setAttribute<std::string>
  /// writes and lvr2's checkAttribute compares the datatype with.
  void stringAttribute(hid_t object, const char* name, const char* value) const {
    const Id type(H5Tcopy(H5T_C_S1), H5Tclose, failed("string type"));
    if (H5Tset_size(type, H5T_VARIABLE) < 0 || H5Tset_cset(type, H5T_CSET_UTF8) < 0) {
      throw std::runtime_error(failed("string type"));
    }
    const Id space(H5Screate(H5S_SCALAR), H5Sclose, failed("dataspace"));
    const Id attribute(H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                       failed("attribute " + std::string(name)));
    if (H5Awrite(attribute, type, &value) < 0) throw std::runtime_error(failed("attribute " + std::string(name)));
  }

  /// A scalar int dataset.
  void scalarInt(hid_t parent, const char* name, int value) const {
    const Id space(H5Screate(H5S_SCALAR), H5Sclose, failed("dataspace of " + std::string(name)));
    const Id set(H5Dcreate2(parent, name, H5T_NATIVE_INT, space, H5P_DEFAULT, dataset_list_, H5P_DEFAULT), H5Dclose,
                 failed("dataset " + std::string(name)));
    if (H5Dwrite(set, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0) {
      throw std::runtime_error(failed("dataset " + std::string(name)));
    }
  }

  /// A rows x width dataset (lvr2 channels are always two-dimensional).
  template <typename T>
  void dataset(hid_t parent, const std::string& name, hid_t type, const std::vector<T>& values, std::size_t width) const {
    const hsize_t dims[2] = {values.size() / width, width};
    const Id space(H5Screate_simple(2, dims, nullptr), H5Sclose, failed("dataspace of " + name));
    const Id set(H5Dcreate2(parent, name.c_str(), type, space, H5P_DEFAULT, dataset_list_, H5P_DEFAULT), H5Dclose,
                 failed("dataset " + name));
    if (!values.empty() && H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
      throw std::runtime_error(failed("dataset " + name));
    }
  }

  std::string failed(const std::string& what) const { return file_ + ": HDF5: cannot write " + what; }

 private:
  std::string file_;
  Id group_list_;
  Id dataset_list_;
};

/// lvr2's face normal, (v1 - v2) x (v1 - v3) normalised, (0, 0, 1) for a degenerate face; the
/// vertex normal is the normalised sum of its faces' normals, (0, 0, 1) without faces or if the
/// sum vanishes (lvr2 calcFaceNormals / calcVertexNormals).
void lvr2Normals(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<std::uint32_t, 3>>& faces,
                 std::vector<float>& face_normals, std::vector<float>& vertex_normals) {
  std::vector<Eigen::Vector3d> sums(points.size(), Eigen::Vector3d::Zero());
  face_normals.reserve(faces.size() * 3);
  for (const auto& face : faces) {
    const Eigen::Vector3d &a = points[face[0]], &b = points[face[1]], &c = points[face[2]];
    Eigen::Vector3d n = (a - b).cross(a - c);
    n = n.squaredNorm() > 0 ? n.normalized() : Eigen::Vector3d::UnitZ();
    for (std::uint32_t v : face) sums[v] += n;
    for (int k = 0; k < 3; ++k) face_normals.push_back(static_cast<float>(n[k]));
  }
  vertex_normals.reserve(points.size() * 3);
  for (const Eigen::Vector3d& sum : sums) {
    const Eigen::Vector3d n = sum.squaredNorm() > 0 ? sum.normalized() : Eigen::Vector3d::UnitZ();
    for (int k = 0; k < 3; ++k) vertex_normals.push_back(static_cast<float>(n[k]));
  }
}

/// The file's bytes: built with the in-memory (core) driver, so that the atomic writer of common/
/// puts it into place.
std::string buildImage(const std::string& file, const LayeredMesh& map, const RobotProfile& profile) {
  const MeshFileWriter out(file);
  const Id access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, out.failed("file access list"));
  if (H5Pset_fapl_core(access, 1 << 20, 0) < 0) throw std::runtime_error(out.failed("(core driver)"));
  const Id creation(untimed(H5P_FILE_CREATE), H5Pclose, out.failed("file creation list"));  // the root group
  const Id h5(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, creation, access), H5Fclose, out.failed("file"));
  // lvr2's hdf5util::open writes a scalar int `version` = 1 into every file it creates.
  out.scalarInt(h5, "version", 1);
  const Id mesh(out.group(h5, kMeshMapPart));
  out.stringAttribute(mesh, "IO", "MeshIO");
  out.stringAttribute(mesh, "CLASS", "MeshBuffer");

  const MapPlane plane = MapPlane::fromUp(map.up_W, map.metres_per_unit);
  std::vector<Eigen::Vector3d> points;
  std::vector<float> vertices;
  points.reserve(map.mesh.vertices.size());
  for (const Eigen::Vector3d& p : map.mesh.vertices) {
    points.emplace_back(Eigen::Vector3d(plane.x_W.dot(p), plane.y_W.dot(p), plane.z_W.dot(p)) * plane.metres_per_unit);
    for (int k = 0; k < 3; ++k) vertices.push_back(static_cast<float>(points.back()[k]));
  }
  std::vector<std::uint32_t> indices;
  for (const auto& face : map.mesh.faces) indices.insert(indices.end(), face.begin(), face.end());
  std::vector<float> face_normals, vertex_normals;
  lvr2Normals(points, map.mesh.faces, face_normals, vertex_normals);

  const Id geometry(out.group(mesh, "geometry"));
  out.dataset(geometry, "vertices", H5T_NATIVE_FLOAT, vertices, 3);
  out.dataset(geometry, "face_indices", H5T_NATIVE_UINT, indices, 3);
  out.dataset(geometry, "vertex_normals", H5T_NATIVE_FLOAT, vertex_normals, 3);
  const Id face_attributes(out.group(mesh, "face_attributes"));
  out.dataset(face_attributes, "face_normals", H5T_NATIVE_FLOAT, face_normals, 3);
  const Id vertex_attributes(out.group(mesh, "vertex_attributes"));
  out.dataset(vertex_attributes, "vertex_normals", H5T_NATIVE_FLOAT, vertex_normals, 3);
  for (const VertexLayer& layer : meshMapVertexLayers(map, profile)) {
    out.dataset(vertex_attributes, layer.name, H5T_NATIVE_FLOAT, layer.values, 1);
  }

  if (H5Fflush(h5, H5F_SCOPE_GLOBAL) < 0) throw std::runtime_error(out.failed("(flush)"));
  const ssize_t size = H5Fget_file_image(h5, nullptr, 0);
  if (size < 0) throw std::runtime_error(out.failed("(file image)"));
  std::string image(static_cast<std::size_t>(size), '\0');
  if (H5Fget_file_image(h5, image.data(), image.size()) != size) throw std::runtime_error(out.failed("(file image)"));
  return image;
}

}  // namespace

void writeMeshMapH5(const std::filesystem::path& path, const LayeredMesh& map, const RobotProfile& profile) {
  if (map.layers.size() != map.mesh.faces.size()) {
    throw std::invalid_argument("writeMeshMapH5: " + std::to_string(map.layers.size()) + " layer records for " +
                                std::to_string(map.mesh.faces.size()) + " faces");
  }
  std::string image;
  {
    const QuietErrors quiet;
    image = buildImage(path.string(), map, profile);
  }
  writeFileAtomically(path, image);
}

}  // namespace terramesh::traversability::internal

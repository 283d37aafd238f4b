#include "mesher/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/input_error.h"
#include "common/ply.h"

namespace terramesh::mesher {
namespace {

/// The vertex index list of a PLY face element (`vertex_indices` or `vertex_index`).
/// @throw InputError if there is none.
const ply::Property& faceIndices(const std::string& file, const ply::Element& faces) {
  const ply::Property* indices = faces.find("vertex_indices");
  if (!indices) indices = faces.find("vertex_index");
  if (!indices || !indices->isList()) throw InputError(file, "element face", "missing vertex_indices list");
  return *indices;
}

/// Checks face `f` as soon as it is read: a triangle of existing vertices.
void checkFace(const std::string& file, const ply::Property& indices, std::size_t f, std::size_t vertex_count) {
  const std::string where = "face " + std::to_string(f);
  if (indices.listSize(f) != 3) {
    throw InputError(file, where, "expected a triangle, got " + std::to_string(indices.listSize(f)) + " vertices");
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const double index = indices.values[indices.list_offsets[f] + k];
    if (!(index >= 0 && index < static_cast<double>(vertex_count))) {
      throw InputError(file, where, "vertex index " + std::to_string(index) + " out of range (" +
                                        std::to_string(vertex_count) + " vertices)");
    }
  }
}

/// The rays behind each face and how deep their cell reaches, when the file has both (terramesh's
/// own meshes).
void readBehind(const std::string& file, const ply::Element& faces, TriangleMesh& mesh) {
  const ply::Property* crossings = faces.find("back_crossings");
  const ply::Property* depth = faces.find("back_depth");
  if (!crossings || !depth || crossings->isList() || depth->isList()) return;
  for (std::size_t f = 0; f < faces.count; ++f) {
    appendCheckedBehind(crossings->values[f], depth->values[f], file, "face " + std::to_string(f), mesh);
  }
}

TriangleMesh readPly(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::size_t vertex_count = 0;
  const ply::Document document = ply::read(path, [&](const ply::Element& element, std::size_t i) {
    if (element.name == "vertex") vertex_count = i + 1;
    if (element.name == "face") checkFace(file, faceIndices(file, element), i, vertex_count);
  });
  TriangleMesh mesh;
  if (const ply::Element* vertices = document.find("vertex")) {
    const ply::Property* x = vertices->find("x");
    const ply::Property* y = vertices->find("y");
    const ply::Property* z = vertices->find("z");
    if (!x || !y || !z || x->isList() || y->isList() || z->isList()) {
      throw InputError(file, "element vertex", "missing x, y or z property");
    }
    mesh.vertices.resize(vertices->count);
    for (std::size_t i = 0; i < vertices->count; ++i) mesh.vertices[i] = {x->values[i], y->values[i], z->values[i]};
    if (const ply::Property* steiner = vertices->find("steiner"); steiner && !steiner->isList()) {
      mesh.is_steiner.resize(vertices->count);
      for (std::size_t i = 0; i < vertices->count; ++i) mesh.is_steiner[i] = steiner->values[i] != 0;
    }
    if (const ply::Property* driven = vertices->find("driven"); driven && !driven->isList()) {
      mesh.driven_kind.resize(vertices->count);
      for (std::size_t i = 0; i < vertices->count; ++i) {
        const double kind = driven->values[i];
        if (kind != 0 && kind != 1 && kind != 2) {
          std::ostringstream problem;
          problem << "driven " << kind << " (expected 0, 1 driven ground or 2 its underside)";
          throw InputError(file, "vertex " + std::to_string(i), problem.str());
        }
        mesh.driven_kind[i] = static_cast<std::uint8_t>(kind);
      }
    }
  }
  if (const ply::Element* faces = document.find("face")) {
    const ply::Property& indices = faceIndices(file, *faces);
    mesh.faces.resize(faces->count);
    for (std::size_t f = 0; f < faces->count; ++f) {
      for (std::size_t k = 0; k < 3; ++k) {
        mesh.faces[f][k] = static_cast<std::uint32_t>(indices.values[indices.list_offsets[f] + k]);
      }
    }
    // Observation counts, when the file has both (terramesh's own meshes).
    const ply::Property* rays = faces->find("rays");
    const ply::Property* crossings = faces->find("front_crossings");
    if (rays && crossings && !rays->isList() && !crossings->isList()) {
      for (std::size_t f = 0; f < faces->count; ++f) {
        constexpr double kMaxCount = 4294967295.0;
        if (!(rays->values[f] >= 0 && rays->values[f] <= kMaxCount) || !(crossings->values[f] >= 0) ||
            crossings->values[f] > rays->values[f]) {
          throw InputError(file, "face " + std::to_string(f),
                           "rays and front_crossings must be counts with front_crossings <= rays");
        }
        mesh.face_rays.push_back(static_cast<std::uint32_t>(rays->values[f]));
        mesh.face_front_crossings.push_back(static_cast<std::uint32_t>(crossings->values[f]));
      }
    }
    readBehind(file, *faces, mesh);
    if (const ply::Property* sides = faces->find("view_sides"); sides && !sides->isList()) {
      for (std::size_t f = 0; f < faces->count; ++f) {
        mesh.face_view_sides.push_back(checkedViewSides(sides->values[f], file, "face " + std::to_string(f)));
      }
    }
  }
  return mesh;
}

TriangleMesh readOff(const std::string& file, std::istream& in) {
  std::string magic;
  in >> magic;
  if (magic != "OFF") throw InputError(file, "line 1", "expected \"OFF\"");
  std::size_t vertex_count = 0, face_count = 0, edge_count = 0;
  if (!(in >> vertex_count >> face_count >> edge_count)) {
    throw InputError(file, "header", "expected vertex, face and edge counts");
  }
  TriangleMesh mesh;
  // The header's count is untrusted: grow with the vertices actually read, so that a corrupt
  // count fails as a truncated file instead of allocating it.
  mesh.vertices.reserve(std::min<std::size_t>(vertex_count, std::size_t{1} << 20));
  for (std::size_t i = 0; i < vertex_count; ++i) {
    Eigen::Vector3d v;
    if (!(in >> v.x() >> v.y() >> v.z())) {
      throw InputError(file, "vertex " + std::to_string(i), "expected three coordinates");
    }
    mesh.vertices.push_back(v);
  }
  for (std::size_t f = 0; f < face_count; ++f) {
    std::size_t count = 0;
    std::array<std::uint32_t, 3> face{};
    if (!(in >> count) || count != 3 || !(in >> face[0] >> face[1] >> face[2])) {
      throw InputError(file, "face " + std::to_string(f), "expected \"3 I J K\"");
    }
    for (std::uint32_t index : face) {
      if (index >= vertex_count) {
        throw InputError(file, "face " + std::to_string(f), "vertex index out of range");
      }
    }
    mesh.faces.push_back(face);
  }
  return mesh;
}

TriangleMesh readObj(const std::string& file, std::istream& in) {
  TriangleMesh mesh;
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "v") {
      Eigen::Vector3d v;
      if (!(words >> v.x() >> v.y() >> v.z())) {
        throw InputError(file, lineLocation(line_number), "expected \"v X Y Z\"");
      }
      mesh.vertices.push_back(v);
    } else if (keyword == "f") {
      std::vector<long> indices;
      std::string token;
      while (words >> token) {
        const long index = std::strtol(token.c_str(), nullptr, 10);
        const long resolved = index > 0 ? index - 1 : static_cast<long>(mesh.vertices.size()) + index;
        if (index == 0 || resolved < 0 || resolved >= static_cast<long>(mesh.vertices.size())) {
          throw InputError(file, lineLocation(line_number), "vertex index out of range");
        }
        indices.push_back(resolved);
      }
      if (indices.size() != 3) {
        throw InputError(file, lineLocation(line_number), "expected a triangle (3 indices)");
      }
      mesh.faces.push_back({static_cast<std::uint32_t>(indices[0]),
                            static_cast<std::uint32_t>(indices[1]),
                            static_cast<std::uint32_t>(indices[2])});
    }
  }
  return mesh;
}

std::string lowerExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

/// Refuses a non-finite coordinate (NaN or infinity), naming the vertex: no consumer of a mesh can
/// place it, and it would poison every layer computed near it.
TriangleMesh requireFiniteVertices(const std::string& file, TriangleMesh mesh) {
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      throw InputError(file, "vertex " + std::to_string(i), "expected finite x, y and z coordinates");
    }
  }
  return mesh;
}

}  // namespace

void writePly(const std::filesystem::path& path, const TriangleMesh& mesh, const std::vector<std::string>& comments) {
  const bool have_flags = mesh.is_steiner.size() == mesh.vertices.size();
  ply::Document document;
  document.comments.push_back("terramesh manifold mesh");
  document.comments.insert(document.comments.end(), comments.begin(), comments.end());
  ply::Element& vertices = document.addElement("vertex", mesh.vertices.size());
  for (int k = 0; k < 3; ++k) {
    ply::Property& coordinate = vertices.addScalar(std::string(1, "xyz"[k]), ply::Type::kFloat64);
    coordinate.values.reserve(mesh.vertices.size());
    for (const Eigen::Vector3d& v : mesh.vertices) coordinate.values.push_back(v[k]);
  }
  ply::Property& steiner = vertices.addScalar("steiner", ply::Type::kUInt8);
  steiner.values.resize(mesh.vertices.size(), 0.0);
  if (have_flags) {
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) steiner.values[i] = mesh.is_steiner[i] ? 1 : 0;
  }
  // Written only when some vertex is driven, so that meshes without trajectory evidence keep
  // the file layout (and bytes) they always had.
  const bool have_driven =
      mesh.driven_kind.size() == mesh.vertices.size() &&
      std::any_of(mesh.driven_kind.begin(), mesh.driven_kind.end(), [](std::uint8_t kind) { return kind != 0; });
  if (have_driven) {
    ply::Property& driven = vertices.addScalar("driven", ply::Type::kUInt8);
    driven.values.reserve(mesh.vertices.size());
    for (std::uint8_t kind : mesh.driven_kind) driven.values.push_back(kind);
  }
  ply::Element& faces = document.addElement("face", mesh.faces.size());
  ply::Property& indices = faces.addList("vertex_indices", ply::Type::kUInt8, ply::Type::kUInt32);
  indices.values.reserve(3 * mesh.faces.size());
  indices.list_offsets.reserve(mesh.faces.size() + 1);
  indices.list_offsets.push_back(0);
  for (const auto& face : mesh.faces) {
    for (std::uint32_t index : face) indices.values.push_back(index);
    indices.list_offsets.push_back(indices.values.size());
  }
  if (mesh.face_rays.size() == mesh.faces.size() && mesh.face_front_crossings.size() == mesh.faces.size()) {
    for (const auto& [name, counts] : {std::pair<const char*, const std::vector<std::uint32_t>*>{"rays", &mesh.face_rays},
                                      {"front_crossings", &mesh.face_front_crossings}}) {
      ply::Property& property = faces.addScalar(name, ply::Type::kUInt32);
      property.values.assign(counts->begin(), counts->end());
    }
  }
  if (mesh.face_back_crossings.size() == mesh.faces.size() && mesh.face_back_depth.size() == mesh.faces.size()) {
    faces.addScalar("back_crossings", ply::Type::kUInt32)
        .values.assign(mesh.face_back_crossings.begin(), mesh.face_back_crossings.end());
    faces.addScalar("back_depth", ply::Type::kFloat64).values.assign(mesh.face_back_depth.begin(), mesh.face_back_depth.end());
  }
  if (mesh.face_view_sides.size() == mesh.faces.size()) {
    faces.addScalar("view_sides", ply::Type::kUInt8).values.assign(mesh.face_view_sides.begin(), mesh.face_view_sides.end());
  }
  ply::writeFile(path, document, ply::Format::kBinaryLittleEndian);
}

void writeObj(const std::filesystem::path& path, const TriangleMesh& mesh) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out.precision(17);
    out << "# terramesh manifold mesh: " << mesh.vertices.size() << " vertices, "
        << mesh.faces.size() << " faces\n";
    for (const auto& v : mesh.vertices) out << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& f : mesh.faces) out << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  });
}

TriangleMesh readMesh(const std::filesystem::path& path) {
  const std::string extension = lowerExtension(path);
  if (extension != ".ply" && extension != ".obj" && extension != ".off") {
    throw InputError(path.string(), "", "unknown mesh format (expected .ply, .obj or .off)");
  }
  if (extension == ".ply") return requireFiniteVertices(path.string(), readPly(path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  if (extension == ".off") return requireFiniteVertices(path.string(), readOff(path.string(), in));
  return requireFiniteVertices(path.string(), readObj(path.string(), in));
}

std::uint8_t checkedViewSides(double value, const std::string& file, const std::string& where) {
  constexpr double kAll = view_side::kFront | view_side::kBehind;
  if (!(value >= 0 && value <= kAll) || value != static_cast<double>(static_cast<int>(value))) {
    throw InputError(file, where, "view_sides must be an integer from 0 to 3 (bit 1: seen from in front, 2: from behind)");
  }
  return static_cast<std::uint8_t>(value);
}

void appendCheckedBehind(double crossings, double depth, const std::string& file, const std::string& where,
                         TriangleMesh& mesh) {
  constexpr double kMaxCount = 4294967295.0;
  if (!(crossings >= 0 && crossings <= kMaxCount && crossings == std::floor(crossings)) || !(depth >= 0) ||
      !std::isfinite(depth)) {
    throw InputError(file, where, "back_crossings must be a count and back_depth a finite distance >= 0");
  }
  mesh.face_back_crossings.push_back(static_cast<std::uint32_t>(crossings));
  mesh.face_back_depth.push_back(depth);
}

}  // namespace terramesh::mesher

#include "mesher/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/input_error.h"

namespace terramesh::mesher {
namespace {

template <class T>
void writeLittleEndian(std::ostream& out, T value) {
  static_assert(std::is_arithmetic_v<T>);
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.write(bytes, sizeof(T));  // x86-64 and aarch64 are little-endian
}

// ---- PLY reading -------------------------------------------------------------------------

enum class PlyFormat { kAscii, kBinaryLittle, kBinaryBig };

struct PlyProperty {
  std::string name;
  std::string type;         // scalar type, or the item type of a list
  std::string count_type;   // empty unless a list
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

std::size_t plyTypeSize(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

class PlyReader {
 public:
  PlyReader(std::string file, std::istream& in) : file_(std::move(file)), in_(in) {}

  TriangleMesh read() {
    readHeader();
    TriangleMesh mesh;
    for (const PlyElement& element : elements_) {
      if (element.name == "vertex") {
        readVertices(element, mesh);
      } else if (element.name == "face") {
        readFaces(element, mesh);
      } else {
        skipElement(element);
      }
    }
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      for (std::uint32_t index : mesh.faces[f]) {
        if (index >= mesh.vertices.size()) {
          fail("face " + std::to_string(f), "vertex index " + std::to_string(index) +
                                                 " out of range (" +
                                                 std::to_string(mesh.vertices.size()) + " vertices)");
        }
      }
    }
    return mesh;
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
    throw InputError(file_, where, problem);
  }

  void readHeader() {
    std::string line;
    std::size_t line_number = 0;
    auto next = [&]() {
      if (!std::getline(in_, line)) fail(lineLocation(line_number + 1), "PLY header ends early");
      ++line_number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
    };
    next();
    if (line != "ply") fail("line 1", "expected \"ply\"");
    bool have_format = false;
    while (true) {
      next();
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      if (keyword == "end_header") break;
      if (keyword == "format") {
        std::string format;
        words >> format;
        if (format == "ascii") format_ = PlyFormat::kAscii;
        else if (format == "binary_little_endian") format_ = PlyFormat::kBinaryLittle;
        else if (format == "binary_big_endian") format_ = PlyFormat::kBinaryBig;
        else fail(lineLocation(line_number), "unknown PLY format \"" + format + "\"");
        have_format = true;
      } else if (keyword == "element") {
        PlyElement element;
        if (!(words >> element.name >> element.count)) {
          fail(lineLocation(line_number), "expected \"element NAME COUNT\"");
        }
        elements_.push_back(element);
      } else if (keyword == "property") {
        if (elements_.empty()) fail(lineLocation(line_number), "property before any element");
        PlyProperty property;
        std::string type;
        words >> type;
        if (type == "list") {
          words >> property.count_type >> property.type >> property.name;
          if (plyTypeSize(property.count_type) == 0 || plyTypeSize(property.type) == 0) {
            fail(lineLocation(line_number), "unknown list type");
          }
        } else {
          property.type = type;
          words >> property.name;
          if (plyTypeSize(type) == 0) fail(lineLocation(line_number), "unknown type \"" + type + "\"");
        }
        elements_.back().properties.push_back(property);
      } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
        fail(lineLocation(line_number), "unexpected header line \"" + line + "\"");
      }
    }
    if (!have_format) fail("header", "missing format line");
  }

  double readScalar(const std::string& type, const std::string& where) {
    if (format_ == PlyFormat::kAscii) {
      double value = 0;
      if (!(in_ >> value)) fail(where, "expected a number (file truncated or malformed)");
      return value;
    }
    const std::size_t size = plyTypeSize(type);
    unsigned char bytes[8];
    if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(size))) {
      fail(where, "file truncated");
    }
    if (format_ == PlyFormat::kBinaryBig) std::reverse(bytes, bytes + size);
    auto as = [&bytes](auto zero) {
      decltype(zero) value;
      std::memcpy(&value, bytes, sizeof(value));
      return static_cast<double>(value);
    };
    if (type == "char" || type == "int8") return as(std::int8_t{});
    if (type == "uchar" || type == "uint8") return as(std::uint8_t{});
    if (type == "short" || type == "int16") return as(std::int16_t{});
    if (type == "ushort" || type == "uint16") return as(std::uint16_t{});
    if (type == "int" || type == "int32") return as(std::int32_t{});
    if (type == "uint" || type == "uint32") return as(std::uint32_t{});
    if (type == "float" || type == "float32") return as(float{});
    return as(double{});
  }

  void readVertices(const PlyElement& element, TriangleMesh& mesh) {
    int x = -1, y = -1, z = -1, steiner = -1;
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const std::string& name = element.properties[p].name;
      if (name == "x") x = static_cast<int>(p);
      if (name == "y") y = static_cast<int>(p);
      if (name == "z") z = static_cast<int>(p);
      if (name == "steiner") steiner = static_cast<int>(p);
    }
    if (x < 0 || y < 0 || z < 0) fail("element vertex", "missing x, y or z property");
    mesh.vertices.resize(element.count);
    if (steiner >= 0) mesh.is_steiner.resize(element.count);
    std::vector<double> values(element.properties.size());
    for (std::size_t i = 0; i < element.count; ++i) {
      const std::string where = "vertex " + std::to_string(i);
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        if (!element.properties[p].count_type.empty()) {
          skipList(element.properties[p], where);
          continue;
        }
        values[p] = readScalar(element.properties[p].type, where);
      }
      mesh.vertices[i] = {values[static_cast<std::size_t>(x)], values[static_cast<std::size_t>(y)],
                          values[static_cast<std::size_t>(z)]};
      if (steiner >= 0) mesh.is_steiner[i] = values[static_cast<std::size_t>(steiner)] != 0;
    }
  }

  void readFaces(const PlyElement& element, TriangleMesh& mesh) {
    mesh.faces.reserve(element.count);
    for (std::size_t i = 0; i < element.count; ++i) {
      const std::string where = "face " + std::to_string(i);
      bool found = false;
      for (const PlyProperty& property : element.properties) {
        if (property.count_type.empty()) {
          readScalar(property.type, where);
          continue;
        }
        const double count = readScalar(property.count_type, where);
        if (property.name != "vertex_indices" && property.name != "vertex_index") {
          for (int k = 0; k < static_cast<int>(count); ++k) readScalar(property.type, where);
          continue;
        }
        if (count != 3) fail(where, "expected a triangle, got " + std::to_string(count) + " vertices");
        std::array<std::uint32_t, 3> face{};
        for (std::size_t k = 0; k < 3; ++k) {
          const double index = readScalar(property.type, where);
          if (index < 0) fail(where, "negative vertex index");
          face[k] = static_cast<std::uint32_t>(index);
        }
        mesh.faces.push_back(face);
        found = true;
      }
      if (!found) fail("element face", "missing vertex_indices list");
    }
  }

  void skipList(const PlyProperty& property, const std::string& where) {
    const double count = readScalar(property.count_type, where);
    for (int k = 0; k < static_cast<int>(count); ++k) readScalar(property.type, where);
  }

  void skipElement(const PlyElement& element) {
    for (std::size_t i = 0; i < element.count; ++i) {
      const std::string where = element.name + " " + std::to_string(i);
      for (const PlyProperty& property : element.properties) {
        if (property.count_type.empty()) readScalar(property.type, where);
        else skipList(property, where);
      }
    }
  }

  std::string file_;
  std::istream& in_;
  PlyFormat format_ = PlyFormat::kAscii;
  std::vector<PlyElement> elements_;
};

TriangleMesh readOff(const std::string& file, std::istream& in) {
  std::string magic;
  in >> magic;
  if (magic != "OFF") throw InputError(file, "line 1", "expected \"OFF\"");
  std::size_t vertex_count = 0, face_count = 0, edge_count = 0;
  if (!(in >> vertex_count >> face_count >> edge_count)) {
    throw InputError(file, "header", "expected vertex, face and edge counts");
  }
  TriangleMesh mesh;
  mesh.vertices.resize(vertex_count);
  for (std::size_t i = 0; i < vertex_count; ++i) {
    auto& v = mesh.vertices[i];
    if (!(in >> v.x() >> v.y() >> v.z())) {
      throw InputError(file, "vertex " + std::to_string(i), "expected three coordinates");
    }
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

}  // namespace

void writePly(const std::filesystem::path& path, const TriangleMesh& mesh) {
  const bool have_flags = mesh.is_steiner.size() == mesh.vertices.size();
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\ncomment terramesh manifold mesh\n"
        << "element vertex " << mesh.vertices.size() << '\n'
        << "property double x\nproperty double y\nproperty double z\n"
        << "property uchar steiner\n"
        << "element face " << mesh.faces.size() << '\n'
        << "property list uchar uint vertex_indices\nend_header\n";
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) writeLittleEndian(out, mesh.vertices[i][k]);
      writeLittleEndian<std::uint8_t>(out, have_flags && mesh.is_steiner[i] ? 1 : 0);
    }
    for (const auto& face : mesh.faces) {
      writeLittleEndian<std::uint8_t>(out, 3);
      for (std::uint32_t index : face) writeLittleEndian(out, index);
    }
  });
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
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open file for reading");
  if (extension == ".ply") return PlyReader(path.string(), in).read();
  if (extension == ".off") return readOff(path.string(), in);
  return readObj(path.string(), in);
}

}  // namespace terramesh::mesher

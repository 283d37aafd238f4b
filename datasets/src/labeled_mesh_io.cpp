// PLY reading and writing of ground-truth meshes with per-face labels and slopes.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/atomic_file.h"
#include "common/input_error.h"
#include "datasets/labeled_mesh.h"

namespace terramesh::datasets {
namespace {

template <class T>
void putLittleEndian(std::ostream& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.write(bytes, sizeof(T));  // the supported hosts (x86-64, aarch64) are little-endian
}

enum class Encoding { kAscii, kLittleEndian, kBigEndian };

/// One property of a PLY element; `list_count_type` is set for list properties.
struct Property {
  std::string name;
  std::string type;
  std::string list_count_type;
};

struct Element {
  std::string name;
  std::size_t count = 0;
  std::vector<Property> properties;

  int find(const std::string& property_name) const {
    for (std::size_t i = 0; i < properties.size(); ++i) {
      if (properties[i].name == property_name) return static_cast<int>(i);
    }
    return -1;
  }
};

/// Byte width of a PLY scalar type name, 0 if unknown.
std::size_t scalarWidth(const std::string& type) {
  static const std::pair<const char*, std::size_t> kTypes[] = {
      {"char", 1},  {"uchar", 1},  {"int8", 1},   {"uint8", 1},   {"short", 2},   {"ushort", 2},
      {"int16", 2}, {"uint16", 2}, {"int", 4},    {"uint", 4},    {"int32", 4},   {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  for (const auto& [name, width] : kTypes) {
    if (type == name) return width;
  }
  return 0;
}

/// Reads the values of a PLY body in any of the three encodings.
class ValueSource {
 public:
  ValueSource(const std::string& file, std::istream& in, Encoding encoding)
      : file_(file), in_(in), encoding_(encoding) {}

  double next(const std::string& type, const std::string& where) {
    if (encoding_ == Encoding::kAscii) {
      double value = 0.0;
      if (!(in_ >> value)) throw InputError(file_, where, "expected a number (truncated or malformed)");
      return value;
    }
    const std::size_t width = scalarWidth(type);
    unsigned char bytes[8] = {};
    if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(width))) {
      throw InputError(file_, where, "file truncated");
    }
    if (encoding_ == Encoding::kBigEndian) std::reverse(bytes, bytes + width);
    return decode(type, bytes);
  }

 private:
  template <class T>
  static double as(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return static_cast<double>(value);
  }

  static double decode(const std::string& type, const unsigned char* bytes) {
    const std::size_t width = scalarWidth(type);
    const bool is_float = type.find("float") == 0 || type == "double";
    const bool is_unsigned = type[0] == 'u';
    if (is_float) return width == 4 ? as<float>(bytes) : as<double>(bytes);
    switch (width) {
      case 1: return is_unsigned ? as<std::uint8_t>(bytes) : as<std::int8_t>(bytes);
      case 2: return is_unsigned ? as<std::uint16_t>(bytes) : as<std::int16_t>(bytes);
      default: return is_unsigned ? as<std::uint32_t>(bytes) : as<std::int32_t>(bytes);
    }
  }

  const std::string& file_;
  std::istream& in_;
  Encoding encoding_;
};

struct Header {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
};

Header readHeader(const std::string& file, std::istream& in) {
  Header header;
  std::string line;
  std::size_t line_number = 0;
  bool have_format = false;
  while (true) {
    if (!std::getline(in, line)) {
      throw InputError(file, lineLocation(line_number + 1), "header ends before end_header");
    }
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = lineLocation(line_number);
    if (line_number == 1) {
      if (line != "ply") throw InputError(file, where, "expected \"ply\" (not a PLY file)");
      continue;
    }
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      std::string encoding;
      words >> encoding;
      if (encoding == "ascii") header.encoding = Encoding::kAscii;
      else if (encoding == "binary_little_endian") header.encoding = Encoding::kLittleEndian;
      else if (encoding == "binary_big_endian") header.encoding = Encoding::kBigEndian;
      else throw InputError(file, where, "unknown encoding \"" + encoding + "\"");
      have_format = true;
    } else if (keyword == "element") {
      Element element;
      if (!(words >> element.name >> element.count)) {
        throw InputError(file, where, "expected \"element NAME COUNT\"");
      }
      header.elements.push_back(element);
    } else if (keyword == "property") {
      if (header.elements.empty()) throw InputError(file, where, "property before any element");
      Property property;
      words >> property.type;
      if (property.type == "list") words >> property.list_count_type >> property.type;
      words >> property.name;
      const bool known = scalarWidth(property.type) > 0 &&
                         (property.list_count_type.empty() || scalarWidth(property.list_count_type) > 0);
      if (!known || property.name.empty()) {
        throw InputError(file, where, "malformed property \"" + line + "\"");
      }
      header.elements.back().properties.push_back(property);
    } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
      throw InputError(file, where, "unexpected header line \"" + line + "\"");
    }
  }
  if (!have_format) throw InputError(file, "header", "no format line");
  return header;
}

/// Reads one instance of `element`: scalars into `scalars` (by property position), the list
/// named `list_name` into `list`; other lists are read and dropped.
void readInstance(const std::string& file, ValueSource& source, const Element& element,
                  const std::string& where, const std::string& list_name,
                  std::vector<double>& scalars, std::vector<double>& list) {
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    const Property& property = element.properties[p];
    if (property.list_count_type.empty()) {
      scalars[p] = source.next(property.type, where);
      continue;
    }
    const double count = source.next(property.list_count_type, where);
    if (!(count >= 0 && count <= 255 * 255)) {
      throw InputError(file, where, "invalid list length " + std::to_string(count));
    }
    const bool keep = property.name == list_name;
    if (keep) list.clear();
    for (int k = 0; k < static_cast<int>(count); ++k) {
      const double value = source.next(property.type, where);
      if (keep) list.push_back(value);
    }
  }
}

void readVertices(const std::string& file, ValueSource& source, const Element& element,
                  LabeledMesh& result) {
  const int x = element.find("x"), y = element.find("y"), z = element.find("z");
  if (x < 0 || y < 0 || z < 0) throw InputError(file, "element vertex", "missing x, y or z property");
  std::vector<double> scalars(element.properties.size());
  std::vector<double> unused;
  result.mesh.vertices.reserve(element.count);
  for (std::size_t i = 0; i < element.count; ++i) {
    const std::string where = "vertex " + std::to_string(i);
    readInstance(file, source, element, where, "", scalars, unused);
    const Eigen::Vector3d v(scalars[static_cast<std::size_t>(x)], scalars[static_cast<std::size_t>(y)],
                            scalars[static_cast<std::size_t>(z)]);
    if (!v.allFinite()) throw InputError(file, where, "coordinate is not finite");
    result.mesh.vertices.push_back(v);
  }
}

void readFaces(const std::string& file, ValueSource& source, const Element& element,
               LabeledMesh& result) {
  std::string list_name = "vertex_indices";
  if (element.find(list_name) < 0) list_name = "vertex_index";
  const int indices = element.find(list_name);
  const int label = element.find("label");
  const int slope = element.find("slope_deg");
  if (indices < 0 || element.properties[static_cast<std::size_t>(indices)].list_count_type.empty()) {
    throw InputError(file, "element face", "missing list property vertex_indices");
  }
  if (label < 0 || slope < 0) {
    throw InputError(file, "element face", "missing face property label or slope_deg (not a labelled "
                                           "ground-truth mesh)");
  }
  std::vector<double> scalars(element.properties.size());
  std::vector<double> corners;
  result.mesh.faces.reserve(element.count);
  result.labels.reserve(element.count);
  result.slope_deg.reserve(element.count);
  for (std::size_t i = 0; i < element.count; ++i) {
    const std::string where = "face " + std::to_string(i);
    readInstance(file, source, element, where, list_name, scalars, corners);
    if (corners.size() != 3) {
      throw InputError(file, where, "expected a triangle, got " + std::to_string(corners.size()) + " vertices");
    }
    std::array<std::uint32_t, 3> face{};
    for (std::size_t k = 0; k < 3; ++k) {
      if (!(corners[k] >= 0 && corners[k] < static_cast<double>(result.mesh.vertices.size()))) {
        throw InputError(file, where, "vertex index " + std::to_string(corners[k]) + " out of range (" +
                                          std::to_string(result.mesh.vertices.size()) + " vertices)");
      }
      face[k] = static_cast<std::uint32_t>(corners[k]);
    }
    const double label_value = scalars[static_cast<std::size_t>(label)];
    if (!(label_value >= 0 && label_value < static_cast<double>(kSurfaceLabelCount)) ||
        label_value != std::floor(label_value)) {
      throw InputError(file, where, "label " + std::to_string(label_value) + " is not a surface label");
    }
    const double slope_value = scalars[static_cast<std::size_t>(slope)];
    if (!(slope_value >= 0 && slope_value <= 180)) {
      throw InputError(file, where, "slope_deg " + std::to_string(slope_value) + " outside [0, 180]");
    }
    result.mesh.faces.push_back(face);
    result.labels.push_back(static_cast<SurfaceLabel>(static_cast<int>(label_value)));
    result.slope_deg.push_back(static_cast<float>(slope_value));
  }
}

}  // namespace

void writeLabeledPly(const std::filesystem::path& path, const LabeledMesh& mesh) {
  mesh.validate();
  writeFileAtomically(path, [&mesh](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\n"
        << "comment terramesh ground truth: label = road 0, sidewalk 1, curb 2, wall 3, obstacle 4, "
           "vegetation 5, ceiling 6, ramp 7; slope_deg = angle of the normal to up\n"
        << "element vertex " << mesh.mesh.vertices.size()
        << "\nproperty double x\nproperty double y\nproperty double z\n"
        << "element face " << mesh.mesh.faces.size()
        << "\nproperty list uchar uint vertex_indices\nproperty uchar label\nproperty float slope_deg\n"
        << "end_header\n";
    for (const Eigen::Vector3d& v : mesh.mesh.vertices) {
      for (int k = 0; k < 3; ++k) putLittleEndian(out, v[k]);
    }
    for (std::size_t f = 0; f < mesh.mesh.faces.size(); ++f) {
      putLittleEndian(out, std::uint8_t{3});
      for (std::uint32_t index : mesh.mesh.faces[f]) putLittleEndian(out, index);
      putLittleEndian(out, static_cast<std::uint8_t>(mesh.labels[f]));
      putLittleEndian(out, mesh.slope_deg[f]);
    }
  });
}

LabeledMesh readLabeledPly(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(file, "", "cannot open file");
  const Header header = readHeader(file, in);
  ValueSource source(file, in, header.encoding);
  LabeledMesh result;
  bool have_faces = false;
  for (const Element& element : header.elements) {
    if (element.name == "vertex") {
      readVertices(file, source, element, result);
    } else if (element.name == "face") {
      if (result.mesh.vertices.empty() && element.count > 0) {
        throw InputError(file, "element face", "faces before (or without) the vertex element");
      }
      readFaces(file, source, element, result);
      have_faces = true;
    } else {
      std::vector<double> scalars(element.properties.size());
      std::vector<double> unused;
      for (std::size_t i = 0; i < element.count; ++i) {
        readInstance(file, source, element, element.name + " " + std::to_string(i), "", scalars, unused);
      }
    }
  }
  if (!have_faces) throw InputError(file, "header", "no face element");
  return result;
}

}  // namespace terramesh::datasets

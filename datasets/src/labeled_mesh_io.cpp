// PLY reading and writing of ground-truth meshes with per-face labels and slopes (common/ply.h).
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "common/input_error.h"
#include "common/ply.h"
#include "datasets/labeled_mesh.h"

namespace terramesh::datasets {
namespace {

/// A scalar property of `element`, or nullptr.
const ply::Property* scalar(const ply::Element& element, const std::string& name) {
  const ply::Property* property = element.find(name);
  return property && !property->isList() ? property : nullptr;
}

/// The properties of a labelled mesh's elements.
struct VertexFields {
  const ply::Property* x;
  const ply::Property* y;
  const ply::Property* z;
};
struct FaceFields {
  const ply::Property* indices;
  const ply::Property* label;
  const ply::Property* slope;
};

VertexFields vertexFields(const std::string& file, const ply::Element& element) {
  const VertexFields fields{scalar(element, "x"), scalar(element, "y"), scalar(element, "z")};
  if (!fields.x || !fields.y || !fields.z) throw InputError(file, "element vertex", "missing x, y or z property");
  return fields;
}

FaceFields faceFields(const std::string& file, const ply::Element& element) {
  FaceFields fields{element.find("vertex_indices"), scalar(element, "label"), scalar(element, "slope_deg")};
  if (!fields.indices) fields.indices = element.find("vertex_index");
  if (!fields.indices || !fields.indices->isList()) {
    throw InputError(file, "element face", "missing list property vertex_indices");
  }
  if (!fields.label || !fields.slope) {
    throw InputError(file, "element face", "missing face property label or slope_deg (not a labelled "
                                           "ground-truth mesh)");
  }
  return fields;
}

/// Checks vertex `i` as soon as it is read.
void checkVertex(const std::string& file, const VertexFields& fields, std::size_t i) {
  const Eigen::Vector3d v(fields.x->values[i], fields.y->values[i], fields.z->values[i]);
  if (!v.allFinite()) throw InputError(file, "vertex " + std::to_string(i), "coordinate is not finite");
}

/// Checks face `i` as soon as it is read: a triangle of existing vertices, a label, a slope.
void checkFace(const std::string& file, const FaceFields& fields, std::size_t i, std::size_t vertex_count) {
  const std::string where = "face " + std::to_string(i);
  const ply::Property& indices = *fields.indices;
  if (indices.listSize(i) != 3) {
    throw InputError(file, where, "expected a triangle, got " + std::to_string(indices.listSize(i)) + " vertices");
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const double corner = indices.values[indices.list_offsets[i] + k];
    if (!(corner >= 0 && corner < static_cast<double>(vertex_count))) {
      throw InputError(file, where, "vertex index " + std::to_string(corner) + " out of range (" +
                                        std::to_string(vertex_count) + " vertices)");
    }
  }
  const double label = fields.label->values[i];
  if (!(label >= 0 && label < static_cast<double>(kSurfaceLabelCount)) || label != std::floor(label)) {
    throw InputError(file, where, "label " + std::to_string(label) + " is not a surface label");
  }
  const double slope = fields.slope->values[i];
  if (!(slope >= 0 && slope <= 180)) {
    throw InputError(file, where, "slope_deg " + std::to_string(slope) + " outside [0, 180]");
  }
}

}  // namespace

void writeLabeledPly(const std::filesystem::path& path, const LabeledMesh& mesh) {
  mesh.validate();
  ply::Document document;
  document.comments.push_back(
      "terramesh ground truth: label = road 0, sidewalk 1, curb 2, wall 3, obstacle 4, vegetation 5, ceiling 6, "
      "ramp 7; slope_deg = angle of the normal to up");
  ply::Element& vertices = document.addElement("vertex", mesh.mesh.vertices.size());
  for (int k = 0; k < 3; ++k) {
    ply::Property& coordinate = vertices.addScalar(std::string(1, "xyz"[k]), ply::Type::kFloat64);
    coordinate.values.reserve(mesh.mesh.vertices.size());
    for (const Eigen::Vector3d& v : mesh.mesh.vertices) coordinate.values.push_back(v[k]);
  }
  const std::size_t face_count = mesh.mesh.faces.size();
  ply::Element& faces = document.addElement("face", face_count);
  ply::Property& indices = faces.addList("vertex_indices", ply::Type::kUInt8, ply::Type::kUInt32);
  indices.values.reserve(3 * face_count);
  indices.list_offsets.reserve(face_count + 1);
  indices.list_offsets.push_back(0);
  for (const auto& face : mesh.mesh.faces) {
    for (std::uint32_t index : face) indices.values.push_back(index);
    indices.list_offsets.push_back(indices.values.size());
  }
  // Each property is filled before the next is added (adding may move the earlier ones).
  ply::Property& labels = faces.addScalar("label", ply::Type::kUInt8);
  for (const SurfaceLabel label : mesh.labels) labels.values.push_back(static_cast<double>(label));
  ply::Property& slopes = faces.addScalar("slope_deg", ply::Type::kFloat32);
  for (const float slope : mesh.slope_deg) slopes.values.push_back(slope);
  ply::writeFile(path, document, ply::Format::kBinaryLittleEndian);
}

LabeledMesh readLabeledPly(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::size_t vertex_count = 0;
  std::optional<VertexFields> vertex_fields;
  std::optional<FaceFields> face_fields;
  const ply::Document document = ply::read(path, [&](const ply::Element& element, std::size_t i) {
    if (element.name == "vertex") {
      if (!vertex_fields) vertex_fields = vertexFields(file, element);
      checkVertex(file, *vertex_fields, i);
      vertex_count = i + 1;
    } else if (element.name == "face") {
      if (!face_fields) {
        if (vertex_count == 0) throw InputError(file, "element face", "faces before (or without) the vertex element");
        face_fields = faceFields(file, element);
      }
      checkFace(file, *face_fields, i, vertex_count);
    }
  });
  const ply::Element* vertices = document.find("vertex");
  const ply::Element* faces = document.find("face");
  if (!faces) throw InputError(file, "header", "no face element");
  LabeledMesh result;
  if (vertices) {
    const VertexFields v = vertexFields(file, *vertices);
    result.mesh.vertices.reserve(vertices->count);
    for (std::size_t i = 0; i < vertices->count; ++i) {
      result.mesh.vertices.emplace_back(v.x->values[i], v.y->values[i], v.z->values[i]);
    }
  }
  const FaceFields f = faceFields(file, *faces);
  result.mesh.faces.reserve(faces->count);
  result.labels.reserve(faces->count);
  result.slope_deg.reserve(faces->count);
  for (std::size_t i = 0; i < faces->count; ++i) {
    const double* corners = &f.indices->values[f.indices->list_offsets[i]];
    result.mesh.faces.push_back({static_cast<std::uint32_t>(corners[0]), static_cast<std::uint32_t>(corners[1]),
                                 static_cast<std::uint32_t>(corners[2])});
    result.labels.push_back(static_cast<SurfaceLabel>(static_cast<int>(f.label->values[i])));
    result.slope_deg.push_back(static_cast<float>(f.slope->values[i]));
  }
  return result;
}

}  // namespace terramesh::datasets

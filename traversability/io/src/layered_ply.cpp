// traversability.ply: the layered mesh as a standard PLY (MeshLab / CloudCompare read it).
#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/input_error.h"
#include "common/ply.h"
#include "export_writers.h"
#include "mesher/mesh_io.h"
#include "traversability/layer_registry.h"

namespace terramesh::traversability::internal {
namespace {

using ply::Type;

/// The header comment that names the bits of `reasons`, lowest first, each after a space.
constexpr std::string_view kReasonBitsComment = "reasons bits, lowest first:";

Type plyType(LayerType type) {
  switch (type) {
    case LayerType::kUInt8: return Type::kUInt8;
    case LayerType::kUInt16: return Type::kUInt16;
    case LayerType::kUInt32: return Type::kUInt32;
    case LayerType::kFloat32: break;
  }
  return Type::kFloat32;
}

/// The largest value an integer layer's type holds (0 for float layers).
double integerLimit(LayerType type) {
  switch (type) {
    case LayerType::kUInt8: return 255.0;
    case LayerType::kUInt16: return 65535.0;
    case LayerType::kUInt32: return 4294967295.0;
    case LayerType::kFloat32: break;
  }
  return 0.0;
}

/// A registry layer's value read from a file, checked: an integer layer holds an integer of its
/// type; `evidence` one of its three codes.
double checkedValue(const LayerInfo& layer, double value, const std::string& file, const std::string& where) {
  const double limit = integerLimit(layer.type);
  if (limit > 0 && !(value >= 0 && value <= limit && value == std::floor(value))) {
    throw InputError(file, where,
                     std::string(layer.name) + " " + std::to_string(value) + " (expected an integer in [0, " +
                         std::to_string(static_cast<std::uint64_t>(limit)) + "])");
  }
  if (std::string_view(layer.name) == "evidence" && !(value == 0 || value == 1 || value == 2)) {
    throw InputError(file, where, "evidence " + std::to_string(value) + " (expected 0 measured, 1 driven or 2 interpolated)");
  }
  return value;
}

const ply::Property& require(const ply::Element& element, const std::string& name, const std::string& file) {
  const ply::Property* property = element.find(name);
  if (!property) throw InputError(file, "element " + element.name, "missing property \"" + name + "\"");
  if (property->isList()) throw InputError(file, "element " + element.name, "property \"" + name + "\" must be a scalar");
  return *property;
}

}  // namespace

void writeLayeredPly(const std::filesystem::path& path, const LayeredMesh& map) {
  const mesher::TriangleMesh& mesh = map.mesh;
  ply::Document document;
  document.comments.push_back("terramesh traversability map: per-face layers (docs/traversability.md)");
  document.comments.push_back("cost in [0,1], NaN = unknown; lengths in metres; infinite clearance = nothing above");
  document.comments.push_back("evidence: 0 measured, 1 driven, 2 interpolated; uncertain = the evidence cannot decide");
  std::string bits = std::string(kReasonBitsComment);
  for (const char* name : reason::names()) bits += std::string(" ") + name;
  document.comments.push_back(bits);
  // Each property is filled right after it is added (adding may move the earlier ones).
  const auto scalar = [](ply::Element& element, const char* name, Type type, std::size_t count, auto value) {
    ply::Property& property = element.addScalar(name, type);
    property.values.reserve(count);
    for (std::size_t i = 0; i < count; ++i) property.values.push_back(static_cast<double>(value(i)));
  };
  const std::size_t vertex_count = mesh.vertices.size(), face_count = mesh.faces.size();
  ply::Element& vertices = document.addElement("vertex", vertex_count);
  for (int k = 0; k < 3; ++k) {
    const char* names[] = {"x", "y", "z"};
    scalar(vertices, names[k], Type::kFloat64, vertex_count, [&](std::size_t v) { return mesh.vertices[v][k]; });
  }
  const bool have_flags = mesh.is_steiner.size() == vertex_count;
  scalar(vertices, "steiner", Type::kUInt8, vertex_count, [&](std::size_t v) { return have_flags && mesh.is_steiner[v]; });
  const std::vector<float> vertex_cost = map.vertexCost();
  scalar(vertices, "cost", Type::kFloat32, vertex_count, [&](std::size_t v) { return vertex_cost[v]; });

  ply::Element& faces = document.addElement("face", face_count);
  ply::Property& indices = faces.addList("vertex_indices", Type::kUInt8, Type::kUInt32);
  indices.list_offsets.push_back(0);
  for (const auto& face : mesh.faces) {
    for (std::uint32_t v : face) indices.values.push_back(v);
    indices.list_offsets.push_back(indices.values.size());
  }
  const auto& layers = map.layers;
  scalar(faces, "cost", Type::kFloat32, face_count, [&](std::size_t f) {
    return layers[f].face_class == FaceClass::kUnknown ? std::numeric_limits<float>::quiet_NaN() : layers[f].cost;
  });
  scalar(faces, "lethal", Type::kUInt8, face_count, [&](std::size_t f) { return layers[f].face_class == FaceClass::kLethal; });
  scalar(faces, "unknown", Type::kUInt8, face_count,
         [&](std::size_t f) { return layers[f].face_class == FaceClass::kUnknown; });
  scalar(faces, "uncertain", Type::kUInt8, face_count,
         [&](std::size_t f) { return layers[f].face_class == FaceClass::kUncertain; });
  // Every registry layer but the cost, written first beside the class flags.
  for (const LayerInfo& layer : faceLayerRegistry()) {
    if (std::string_view(layer.name) == "cost") continue;
    scalar(faces, layer.name, plyType(layer.type), face_count, [&](std::size_t f) { return layer.get(layers[f]); });
  }
  // What the evidence of a recomputation (another robot: plan --robot, traverse) starts from.
  const bool crossings = mesh.face_front_crossings.size() == face_count;
  if (crossings) {
    scalar(faces, "front_crossings", Type::kUInt32, face_count,
           [&](std::size_t f) { return mesh.face_front_crossings[f]; });
  }
  if (mesh.face_back_crossings.size() == face_count && mesh.face_back_depth.size() == face_count) {
    scalar(faces, "back_crossings", Type::kUInt32, face_count, [&](std::size_t f) { return mesh.face_back_crossings[f]; });
    scalar(faces, "back_depth", Type::kFloat64, face_count, [&](std::size_t f) { return mesh.face_back_depth[f]; });
  }
  if (mesh.face_view_sides.size() == face_count) {
    scalar(faces, "view_sides", Type::kUInt8, face_count, [&](std::size_t f) { return mesh.face_view_sides[f]; });
  }
  scalar(faces, "steiner", Type::kUInt8, face_count, [&](std::size_t f) { return layers[f].steiner; });
  ply::writeFile(path, document, ply::Format::kBinaryLittleEndian);
}

LayeredMesh readLayeredPly(const std::filesystem::path& path) {
  const std::string file = path.string();
  const ply::Document document = ply::read(path);
  const ply::Element* vertices = document.find("vertex");
  const ply::Element* faces = document.find("face");
  if (!vertices) throw InputError(file, "header", "missing element \"vertex\"");
  if (!faces) throw InputError(file, "header", "missing element \"face\"");
  LayeredMesh map;
  mesher::TriangleMesh& mesh = map.mesh;
  const ply::Property& x = require(*vertices, "x", file);
  const ply::Property& y = require(*vertices, "y", file);
  const ply::Property& z = require(*vertices, "z", file);
  mesh.vertices.resize(vertices->count);
  for (std::size_t v = 0; v < vertices->count; ++v) mesh.vertices[v] = {x.values[v], y.values[v], z.values[v]};
  if (const ply::Property* flags = vertices->find("steiner"); flags && !flags->isList()) {
    mesh.is_steiner.resize(vertices->count);
    for (std::size_t v = 0; v < vertices->count; ++v) mesh.is_steiner[v] = flags->values[v] != 0;
  }

  const ply::Property* indices = faces->find("vertex_indices");
  if (!indices) indices = faces->find("vertex_index");
  if (!indices || !indices->isList()) throw InputError(file, "element face", "missing list property \"vertex_indices\"");
  const ply::Property& cost = require(*faces, "cost", file);
  const ply::Property& lethal = require(*faces, "lethal", file);
  const ply::Property& unknown = require(*faces, "unknown", file);
  const ply::Property& rays = require(*faces, "rays", file);
  const ply::Property& steiner = require(*faces, "steiner", file);
  const ply::Property* uncertain = faces->find("uncertain");
  const ply::Property* front_crossings = faces->find("front_crossings");
  const ply::Property* view_sides = faces->find("view_sides");
  const ply::Property* back_crossings = faces->find("back_crossings");
  const ply::Property* back_depth = faces->find("back_depth");
  const bool behind = back_crossings && back_depth && !back_crossings->isList() && !back_depth->isList();
  // The registry's layers (the cost is read and checked with the class below); optional ones may
  // be missing (older files): their faces keep the defaults.
  std::vector<std::pair<const LayerInfo*, const ply::Property*>> registry_layers;
  for (const LayerInfo& layer : faceLayerRegistry()) {
    if (std::string_view(layer.name) == "cost") continue;
    const ply::Property* property = layer.optional_in_files ? faces->find(layer.name) : &require(*faces, layer.name, file);
    if (property && !property->isList()) registry_layers.emplace_back(&layer, property);
  }
  mesh.faces.resize(faces->count);
  map.layers.resize(faces->count);
  for (std::size_t f = 0; f < faces->count; ++f) {
    const std::string where = "face " + std::to_string(f);
    if (indices->listSize(f) != 3) throw InputError(file, where, "expected a triangle (3 vertex indices)");
    for (std::size_t k = 0; k < 3; ++k) {
      const double index = indices->values[indices->list_offsets[f] + k];
      if (!(index >= 0) || index >= static_cast<double>(vertices->count)) {
        throw InputError(file, where, "vertex index " + std::to_string(index) + " out of range (" +
                                          std::to_string(vertices->count) + " vertices)");
      }
      mesh.faces[f][k] = static_cast<std::uint32_t>(index);
    }
    FaceLayers& layers = map.layers[f];
    const bool is_uncertain = uncertain && !uncertain->isList() && uncertain->values[f] != 0;
    if ((lethal.values[f] != 0) + (unknown.values[f] != 0) + is_uncertain > 1) {
      throw InputError(file, where, "more than one of lethal, unknown and uncertain");
    }
    layers.face_class = lethal.values[f] != 0   ? FaceClass::kLethal
                        : unknown.values[f] != 0 ? FaceClass::kUnknown
                        : is_uncertain           ? FaceClass::kUncertain
                                                 : FaceClass::kFree;
    layers.cost = static_cast<float>(cost.values[f]);
    if (layers.face_class != FaceClass::kUnknown && !(layers.cost >= 0 && layers.cost <= 1)) {
      throw InputError(file, where, "cost must be in [0, 1] for a known face");
    }
    // Every registry layer checked for its type (rays an integer of uint's range, ...) and set.
    for (const auto& [layer, property] : registry_layers) {
      layer->set(layers, checkedValue(*layer, property->values[f], file, where));
    }
    layers.steiner = steiner.values[f] != 0;
    if (front_crossings && !front_crossings->isList()) {
      const double c = front_crossings->values[f];
      if (!(c >= 0) || c > rays.values[f]) {
        throw InputError(file, where, "front_crossings must be a count <= rays");
      }
      mesh.face_rays.push_back(layers.rays);
      mesh.face_front_crossings.push_back(static_cast<std::uint32_t>(c));
    }
    if (view_sides && !view_sides->isList()) mesh.face_view_sides.push_back(mesher::checkedViewSides(view_sides->values[f], file, where));
    if (behind) mesher::appendCheckedBehind(back_crossings->values[f], back_depth->values[f], file, where, mesh);
  }
  return map;
}

}  // namespace terramesh::traversability::internal

#include "point_cloud2.h"

#include <array>
#include <cmath>
#include <unordered_map>

#include "binary_input.h"

namespace terramesh::datasets::internal {
namespace {

constexpr std::uint8_t kInt8 = 1, kUint8 = 2, kInt16 = 3, kUint16 = 4, kInt32 = 5, kUint32 = 6,
                       kFloat32 = 7, kFloat64 = 8;

/// Bytes of one element of a datatype, 0 for an unknown code.
std::uint32_t datatypeBytes(std::uint8_t datatype) {
  switch (datatype) {
    case kInt8:
    case kUint8:
      return 1;
    case kInt16:
    case kUint16:
      return 2;
    case kInt32:
    case kUint32:
    case kFloat32:
      return 4;
    case kFloat64:
      return 8;
    default:
      return 0;
  }
}

const CloudField* findField(const CloudBytes& cloud, std::string_view name) {
  for (const CloudField& field : cloud.fields) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

/// The field `name`, checked to lie within a point.
/// @throw CloudProblem if it is missing, of an unknown type or beyond point_step.
const CloudField& requireField(const CloudBytes& cloud, std::string_view name) {
  const CloudField* field = findField(cloud, name);
  if (field == nullptr) {
    throw CloudProblem("PointCloud2 has no field \"" + std::string(name) + "\"");
  }
  const std::uint64_t bytes = datatypeBytes(field->datatype);
  if (bytes == 0) {
    throw CloudProblem("PointCloud2 field \"" + std::string(name) + "\" has unknown " +
                       cloudDatatypeName(field->datatype));
  }
  if (std::uint64_t{field->offset} + bytes * std::max<std::uint32_t>(field->count, 1) >
      cloud.point_step) {
    throw CloudProblem("PointCloud2 field \"" + std::string(name) + "\" (offset " +
                       std::to_string(field->offset) + ", " + cloudDatatypeName(field->datatype) +
                       ") ends beyond point_step " + std::to_string(cloud.point_step));
  }
  return *field;
}

double loadCoordinate(const CloudField& field, const unsigned char* point) {
  return field.datatype == kFloat64 ? loadLittleEndian<double>(point + field.offset)
                                    : double{loadLittleEndian<float>(point + field.offset)};
}

/// The value of an integer field; negative values come back as -1.
std::int64_t loadInteger(const CloudField& field, const unsigned char* point) {
  const unsigned char* at = point + field.offset;
  switch (field.datatype) {
    case kInt8:
      return loadLittleEndian<std::int8_t>(at);
    case kUint8:
      return loadLittleEndian<std::uint8_t>(at);
    case kInt16:
      return loadLittleEndian<std::int16_t>(at);
    case kUint16:
      return loadLittleEndian<std::uint16_t>(at);
    case kInt32:
      return loadLittleEndian<std::int32_t>(at);
    default:
      return loadLittleEndian<std::uint32_t>(at);
  }
}

void checkLayout(const CloudBytes& cloud) {
  if (cloud.is_bigendian)
    throw CloudProblem("PointCloud2 is big-endian (only little-endian clouds are read)");
  const std::uint64_t points = std::uint64_t{cloud.width} * cloud.height;
  if (points > 0 && std::uint64_t{cloud.row_step} < std::uint64_t{cloud.width} * cloud.point_step) {
    throw CloudProblem("PointCloud2 row_step " + std::to_string(cloud.row_step) +
                       " is less than width " + std::to_string(cloud.width) + " x point_step " +
                       std::to_string(cloud.point_step));
  }
  if (std::uint64_t{cloud.row_step} * cloud.height != cloud.size) {
    throw CloudProblem("PointCloud2 data has " + std::to_string(cloud.size) +
                       " bytes, expected row_step " + std::to_string(cloud.row_step) +
                       " x height " + std::to_string(cloud.height));
  }
}

}  // namespace

std::string cloudDatatypeName(std::uint8_t datatype) {
  static const std::array<const char*, 9> kNames = {
      "", "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  if (datatype >= 1 && datatype < kNames.size()) return kNames[datatype];
  return "datatype " + std::to_string(datatype);
}

DecodedCloud decodeCloud(const CloudBytes& cloud, std::string_view id_field) {
  checkLayout(cloud);
  std::array<const CloudField*, 3> xyz{};
  for (int k = 0; k < 3; ++k) {
    const std::string name(1, static_cast<char>('x' + k));
    xyz[static_cast<std::size_t>(k)] = &requireField(cloud, name);
    const std::uint8_t type = xyz[static_cast<std::size_t>(k)]->datatype;
    if (type != kFloat32 && type != kFloat64) {
      throw CloudProblem("PointCloud2 field \"" + name + "\" is " + cloudDatatypeName(type) +
                         ", expected float32 or float64");
    }
  }
  const CloudField* id = id_field.empty() || findField(cloud, id_field) == nullptr
                             ? nullptr
                             : &requireField(cloud, id_field);
  if (id != nullptr && (id->datatype == kFloat32 || id->datatype == kFloat64 || id->count > 1)) {
    throw CloudProblem("PointCloud2 field \"" + id->name + "\" is " +
                       cloudDatatypeName(id->datatype) +
                       (id->count > 1 ? " x " + std::to_string(id->count) : std::string()) +
                       ", expected one integer (the point id)");
  }
  DecodedCloud decoded;
  decoded.ids_from_field = id != nullptr;
  const std::size_t points = std::size_t{cloud.width} * cloud.height;
  decoded.positions.reserve(points);
  decoded.ids.reserve(points);
  std::unordered_map<std::uint64_t, std::size_t> first_index;
  for (std::size_t index = 0; index < points; ++index) {
    const unsigned char* point = cloud.data + (index / cloud.width) * cloud.row_step +
                                 (index % cloud.width) * cloud.point_step;
    const Eigen::Vector3d position(loadCoordinate(*xyz[0], point), loadCoordinate(*xyz[1], point),
                                   loadCoordinate(*xyz[2], point));
    if (!position.allFinite()) {
      ++decoded.non_finite_points;
      continue;
    }
    std::uint64_t point_id = index;
    if (id != nullptr) {
      const std::int64_t value = loadInteger(*id, point);
      if (value < 0) {
        throw CloudProblem("point " + std::to_string(index) + ": field \"" + id->name + "\" is " +
                           std::to_string(value) + ", expected a point id >= 0");
      }
      point_id = static_cast<std::uint64_t>(value);
      const auto [first, inserted] = first_index.emplace(point_id, index);
      if (!inserted) {
        throw CloudProblem("point " + std::to_string(index) + ": point id " +
                           std::to_string(point_id) +
                           " is listed twice in this cloud (first at point " +
                           std::to_string(first->second) + ")");
      }
    }
    decoded.positions.push_back(position);
    decoded.ids.push_back(point_id);
  }
  return decoded;
}

}  // namespace terramesh::datasets::internal

#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace terramesh::datasets::internal {

/// One field of a sensor_msgs/PointCloud2, as the message describes it (datatype codes of
/// sensor_msgs/PointField: 1 INT8, 2 UINT8, 3 INT16, 4 UINT16, 5 INT32, 6 UINT32, 7 FLOAT32,
/// 8 FLOAT64).
struct CloudField {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
  std::uint32_t count = 1;
};

/// A PointCloud2's layout and bytes, without ROS types (the bytes stay owned by the message).
struct CloudBytes {
  std::vector<CloudField> fields;
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  bool is_bigendian = false;
  const unsigned char* data = nullptr;
  std::size_t size = 0;
};

/// The finite points of a cloud: positions in the cloud's frame, and per point either the value
/// of the id field or the point's index in the cloud (row-major, counting skipped points).
struct DecodedCloud {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::uint64_t> ids;
  bool ids_from_field = false;        ///< ids are the id field's values, else indices
  std::size_t non_finite_points = 0;  ///< skipped: x, y or z NaN or infinite
};

/// A cloud that cannot be read; the message says what is wrong, in the cloud's terms.
class CloudProblem : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The name of a PointField datatype code ("float32", ...), or "datatype N".
std::string cloudDatatypeName(std::uint8_t datatype);

/// Decodes x, y, z (float32 or float64 each) and, when the cloud has a field `id_field` (empty:
/// never), the point ids from it (an integer field of one element, values >= 0).
/// O(points).
/// @throw CloudProblem for a missing or non-float x/y/z, an id field that is not an integer, a
///        negative id or one listed twice, a big-endian cloud, fields beyond point_step, or
///        data whose size is not row_step * height.
DecodedCloud decodeCloud(const CloudBytes& cloud, std::string_view id_field);

}  // namespace terramesh::datasets::internal

// traversability.h5 (lvr2 HDF5 MeshIO layout for mesh_navigation's mesh_map), read back with the
// HDF5 C API the way lvr2's reader checks it: group attributes and their datatypes, 2-D channels
// of the expected types, and per-vertex layers against values worked out by hand.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "export_writers.h"
#include "test_support/temp_dir.h"
#include "traversability/map_directory.h"

namespace terramesh::traversability {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// A 3 x 1 strip of unit squares (8 vertices, 6 faces) in the z = 0 plane, normals up:
///   4---5---6---7      faces 0, 1: free (cost 0.2, 0.4); 2, 3: lethal; 4: uncertain; 5: unknown
///   | 0/| 2/| 4/|
///   |/1 |/3 |/5 |
///   0---1---2---3
LayeredMesh strip() {
  LayeredMesh map;
  for (int row = 0; row < 2; ++row) {
    for (int x = 0; x < 4; ++x) map.mesh.vertices.emplace_back(x, row, 0);
  }
  for (std::uint32_t x = 0; x < 3; ++x) {
    map.mesh.faces.push_back({x, x + 5, x + 4});
    map.mesh.faces.push_back({x, x + 1, x + 5});
  }
  map.layers.resize(6);
  const FaceClass classes[] = {FaceClass::kFree,   FaceClass::kFree,      FaceClass::kLethal,
                               FaceClass::kLethal, FaceClass::kUncertain, FaceClass::kUnknown};
  const float costs[] = {0.2f, 0.4f, 1, 1, 0.9f, NAN};
  for (std::size_t f = 0; f < 6; ++f) {
    FaceLayers& l = map.layers[f];
    l.face_class = classes[f];
    l.cost = costs[f];
    l.slope_deg = 10.0f * static_cast<float>(f);
    l.step_m = 0.01f * static_cast<float>(f);
    l.roughness_m = f == 1 ? NAN : 0.02f;
    l.contact = 1.0f - 0.1f * static_cast<float>(f);
    l.clearance_m = f == 0 ? 2.0f : kInf;
    l.lethal_distance_m = classes[f] == FaceClass::kLethal ? 0.0f : 0.5f + static_cast<float>(f);
    l.evidence = f == 5 ? Evidence::kInterpolated : Evidence::kMeasured;
    l.height_uncertainty_m = f == 5 ? kInf : 0.03f;
    l.rays = 5;
  }
  return map;
}

struct Dataset {
  std::vector<hsize_t> dims;
  bool is_float32 = false;
  bool is_uint32 = false;
  std::vector<float> floats;
  std::vector<std::uint32_t> uints;
};

class H5File {
 public:
  explicit H5File(const std::filesystem::path& path) : id_(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {}
  ~H5File() {
    if (id_ >= 0) H5Fclose(id_);
  }
  H5File(const H5File&) = delete;
  H5File& operator=(const H5File&) = delete;
  bool ok() const { return id_ >= 0; }
  bool exists(const std::string& path) const { return H5Lexists(id_, path.c_str(), H5P_DEFAULT) > 0; }

  /// The value of a string attribute, or "" if it is not what HighFive's std::string type is
  /// (variable length, UTF-8, scalar): lvr2's checkAttribute compares that exact datatype.
  std::string stringAttribute(const std::string& object, const std::string& name) const {
    const hid_t attribute = H5Aopen_by_name(id_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    if (attribute < 0) return "";
    const hid_t type = H5Aget_type(attribute), space = H5Aget_space(attribute);
    const hid_t highfive = H5Tcopy(H5T_C_S1);
    H5Tset_size(highfive, H5T_VARIABLE);
    H5Tset_cset(highfive, H5T_CSET_UTF8);
    std::string value;
    if (H5Tequal(type, highfive) > 0 && H5Sget_simple_extent_type(space) == H5S_SCALAR) {
      char* text = nullptr;
      if (H5Aread(attribute, highfive, &text) >= 0 && text) value = text;
      H5free_memory(text);
    }
    H5Tclose(highfive);
    H5Sclose(space);
    H5Tclose(type);
    H5Aclose(attribute);
    return value;
  }

  Dataset read(const std::string& path) const {
    Dataset result;
    const hid_t set = H5Dopen2(id_, path.c_str(), H5P_DEFAULT);
    if (set < 0) return result;
    const hid_t type = H5Dget_type(set), space = H5Dget_space(set);
    result.dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
    H5Sget_simple_extent_dims(space, result.dims.data(), nullptr);
    result.is_float32 = H5Tequal(type, H5T_NATIVE_FLOAT) > 0;
    result.is_uint32 = H5Tequal(type, H5T_NATIVE_UINT) > 0;
    const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
    if (result.is_float32) {
      result.floats.resize(count);
      H5Dread(set, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, result.floats.data());
    } else if (result.is_uint32) {
      result.uints.resize(count);
      H5Dread(set, H5T_NATIVE_UINT, H5S_ALL, H5S_ALL, H5P_DEFAULT, result.uints.data());
    }
    H5Sclose(space);
    H5Tclose(type);
    H5Dclose(set);
    return result;
  }

 private:
  hid_t id_;
};

class MeshMapH5Test : public ::testing::Test {
 protected:
  void SetUp() override {
    map_ = strip();
    profile_.inscribed_radius_m = 1.0;
    profile_.inflation_radius_m = 3.0;
    profile_.cost_scaling_factor = 2.0;
    config_.write_geotiff = false;
  }
  std::vector<float> layer(const std::string& name) {
    const H5File file(dir_ / "traversability.h5");
    const Dataset d = file.read("/mesh/vertex_attributes/" + name);
    EXPECT_EQ(d.dims, (std::vector<hsize_t>{8, 1})) << name;
    EXPECT_TRUE(d.is_float32) << name;
    return d.floats;
  }

  LayeredMesh map_;
  RobotProfile profile_;
  ExportConfig config_;
  test::TempDir dir_;
};

TEST_F(MeshMapH5Test, TheMeshGroupIsWhatLvr2MeshIoAccepts) {
  map_.up_W = Eigen::Vector3d(0, -1, 0);  // y down, as in an ORB-SLAM map
  map_.metres_per_unit = 2.0;
  for (auto& v : map_.mesh.vertices) v = Eigen::Vector3d(v.x(), -v.z(), v.y());  // the strip stands upright
  const ExportReport report = writeMapDirectory(dir_.path(), map_, profile_, config_);
  EXPECT_NE(std::find(report.files.begin(), report.files.end(), "traversability.h5"), report.files.end());
  const H5File file(dir_ / "traversability.h5");
  ASSERT_TRUE(file.ok());
  EXPECT_EQ(file.stringAttribute("/mesh", "IO"), "MeshIO");
  EXPECT_EQ(file.stringAttribute("/mesh", "CLASS"), "MeshBuffer");
  EXPECT_FALSE(file.exists("/mesh/edge_attributes"));  // mesh_map computes its own edge handles

  const Dataset vertices = file.read("/mesh/geometry/vertices");
  ASSERT_EQ(vertices.dims, (std::vector<hsize_t>{8, 3}));
  ASSERT_TRUE(vertices.is_float32);
  // Metric plan frame, z = up: the upright strip lies flat again, scaled by 2.
  const MapPlane plane = MapPlane::fromUp(map_.up_W, 2.0);
  for (std::size_t v = 0; v < 8; ++v) {
    const Eigen::Vector3d& p = map_.mesh.vertices[v];
    EXPECT_FLOAT_EQ(vertices.floats[3 * v], static_cast<float>(2.0 * plane.x_W.dot(p))) << v;
    EXPECT_FLOAT_EQ(vertices.floats[3 * v + 1], static_cast<float>(2.0 * plane.y_W.dot(p))) << v;
    EXPECT_NEAR(vertices.floats[3 * v + 2], 0.0, 1e-6) << v;
  }
  const Dataset indices = file.read("/mesh/geometry/face_indices");
  ASSERT_EQ(indices.dims, (std::vector<hsize_t>{6, 3}));
  ASSERT_TRUE(indices.is_uint32);
  for (std::size_t f = 0; f < 6; ++f) {
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(indices.uints[3 * f + k], map_.mesh.faces[f][k]);
  }
  for (const char* path : {"/mesh/geometry/vertex_normals", "/mesh/vertex_attributes/vertex_normals",
                           "/mesh/face_attributes/face_normals"}) {
    const Dataset normals = file.read(path);
    ASSERT_EQ(normals.dims.size(), 2u) << path;
    EXPECT_EQ(normals.dims[1], 3u) << path;
    ASSERT_TRUE(normals.is_float32) << path;
    for (std::size_t i = 0; i < normals.dims[0]; ++i) {  // every face faces up in the plan frame
      EXPECT_NEAR(normals.floats[3 * i + 2], 1.0, 1e-6) << path << " " << i;
    }
  }
  EXPECT_EQ(file.read("/mesh/face_attributes/face_normals").dims[0], 6u);
}

TEST_F(MeshMapH5Test, VertexLayersTakeTheWorstOfTheirFaces) {
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  // Vertex 0: faces 0, 1 (free). 1: 1, 2, 3. 2: 3, 4, 5. 3: 5 (unknown only). 5: 0, 1, 2.
  const std::vector<float> cost = layer("cost"), allow = layer("cost_allow_uncertain");
  EXPECT_FLOAT_EQ(cost[0], 0.4f);  // max of 0.2 and 0.4
  EXPECT_EQ(cost[1], kInf);        // lethal face 2
  EXPECT_EQ(cost[3], kInf);        // unknown: no drivable face
  EXPECT_EQ(cost[7], kInf);        // uncertain face 4 (and unknown 5)
  EXPECT_FLOAT_EQ(allow[7], 0.9f);
  EXPECT_EQ(allow[3], kInf);
  EXPECT_EQ(layer("lethal"), (std::vector<float>{0, 1, 1, 0, 0, 1, 1, 0}));
  EXPECT_EQ(layer("uncertain"), (std::vector<float>{0, 0, 0, 0, 0, 0, 0, 1}));
  EXPECT_EQ(layer("unknown"), (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 0}));
  EXPECT_EQ(layer("border"), std::vector<float>(8, 1.0f));  // an open strip: every vertex on its boundary
  const std::vector<float> steepness = layer("steepness");
  EXPECT_FLOAT_EQ(steepness[0], static_cast<float>(10 * M_PI / 180));
  EXPECT_FLOAT_EQ(steepness[3], static_cast<float>(50 * M_PI / 180));
  const std::vector<float> roughness = layer("roughness");
  EXPECT_FLOAT_EQ(roughness[0], 0.02f);  // the NaN of face 1 is no data, skipped
  EXPECT_FLOAT_EQ(layer("height_diff")[2], 0.05f);
  const std::vector<float> inflation = layer("inflation");
  EXPECT_EQ(inflation[1], kInf);
  EXPECT_FLOAT_EQ(inflation[0], 1.0f);                                    // 0.5 m: inside the inscribed radius
  EXPECT_EQ(inflation[3], 0.0f);                                          // 5.5 m: beyond 3 m
  EXPECT_FLOAT_EQ(layer("contact")[2], 0.5f);  // lowest of 0.7, 0.6, 0.5
  const std::vector<float> clearance = layer("clearance");
  EXPECT_FLOAT_EQ(clearance[0], 2.0f);
  EXPECT_EQ(clearance[1], kInf);
  EXPECT_EQ(layer("evidence")[2], 2.0f);
  EXPECT_EQ(layer("height_uncertainty_m")[3], kInf);
}

TEST_F(MeshMapH5Test, InflationFollowsTheProfileBetweenTheRadii) {
  map_.layers[0].lethal_distance_m = 2.0f;
  map_.layers[1].lethal_distance_m = 2.5f;
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  // Vertex 4 has face 0 only: 2 m, between the inscribed (1 m) and inflation (3 m) radii.
  EXPECT_FLOAT_EQ(layer("inflation")[4], static_cast<float>(std::exp(-2.0 * (2.0 - 1.0))));
  EXPECT_DOUBLE_EQ(profile_.inflationTerm(2.0), std::exp(-2.0));
  EXPECT_EQ(profile_.inflationTerm(3.5), 0.0);
  EXPECT_EQ(profile_.inflationTerm(NAN), 0.0);
}

/// The values of one layer of meshMapVertexLayers, by name.
std::vector<float> vertexLayer(const LayeredMesh& map, const RobotProfile& profile, const std::string& name) {
  for (const internal::VertexLayer& l : internal::meshMapVertexLayers(map, profile)) {
    if (l.name == name) return l.values;
  }
  ADD_FAILURE() << "no layer " << name;
  return {};
}

TEST_F(MeshMapH5Test, AVertexWithoutFacesIsUnknownAndNeverNan) {
  map_.mesh.vertices.emplace_back(9, 9, 9);
  const std::vector<internal::VertexLayer> layers = internal::meshMapVertexLayers(map_, profile_);
  ASSERT_EQ(layers.size(), 16u);
  for (const internal::VertexLayer& l : layers) {
    ASSERT_EQ(l.values.size(), 9u) << l.name;
    if (l.name == "contact" || l.name == "evidence" || l.name == "height_uncertainty_m" || l.name == "reasons" ||
        l.name == "heading_fits") {
      EXPECT_TRUE(std::isnan(l.values[8])) << l.name;  // terramesh's own layers: NaN = no data
    } else {
      EXPECT_FALSE(std::isnan(l.values[8])) << l.name;
    }
  }
  EXPECT_EQ(vertexLayer(map_, profile_, "cost")[8], kInf);
  EXPECT_EQ(vertexLayer(map_, profile_, "height_diff")[8], kInf);
  EXPECT_EQ(vertexLayer(map_, profile_, "clearance")[8], 0.0f);  // no data: the robot does not fit
}

TEST_F(MeshMapH5Test, UnknownClearanceIsNoClearanceForMeshMap) {
  map_.layers[0].clearance_m = NAN;  // the first face above face 0 is closing geometry
  const std::vector<float> clearance = vertexLayer(map_, profile_, "clearance");
  EXPECT_EQ(clearance[4], 0.0f);  // face 0 only
  EXPECT_EQ(clearance[0], 0.0f);  // faces 0 (unknown) and 1 (+inf): the unknown wins
  EXPECT_EQ(clearance[1], kInf);
}

TEST_F(MeshMapH5Test, RewritesAtomicallyAndCanBeTurnedOff) {
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  map_.layers[0].cost = 0.6f;
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  EXPECT_FLOAT_EQ(layer("cost")[4], 0.6f);
  for (const auto& entry : std::filesystem::directory_iterator(dir_.path())) {
    EXPECT_NE(entry.path().filename().string().front(), '.') << "temporary file left: " << entry.path();
  }
  const auto mode = std::filesystem::status(dir_ / "traversability.h5").permissions();
  EXPECT_EQ(mode & std::filesystem::perms::all,
            std::filesystem::perms::owner_read | std::filesystem::perms::owner_write |
                std::filesystem::perms::group_read | std::filesystem::perms::others_read);
  config_.write_mesh_map_h5 = false;
  const ExportReport report = writeMapDirectory(dir_.path(), map_, profile_, config_);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "traversability.h5"));
  EXPECT_EQ(std::find(report.files.begin(), report.files.end(), "traversability.h5"), report.files.end());
}

TEST_F(MeshMapH5Test, TheSameMapGivesTheSameBytes) {
  const auto bytes = [](const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  internal::writeMeshMapH5(dir_ / "a.h5", map_, profile_);
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // HDF5 stamps times in seconds
  internal::writeMeshMapH5(dir_ / "b.h5", map_, profile_);
  const std::string a = bytes(dir_ / "a.h5");
  ASSERT_GT(a.size(), 1000u);
  EXPECT_TRUE(a == bytes(dir_ / "b.h5")) << "no object may carry its write time";
  map_.layers[0].cost = 0.6f;
  internal::writeMeshMapH5(dir_ / "c.h5", map_, profile_);
  EXPECT_FALSE(a == bytes(dir_ / "c.h5"));
}

TEST_F(MeshMapH5Test, AFailedWriteNamesTheFileAndLeavesTheOldOne) {
  const std::filesystem::path missing = dir_ / "no_such_dir" / "traversability.h5";
  try {
    internal::writeMeshMapH5(missing, map_, profile_);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(missing.string()), std::string::npos) << error.what();
  }
  map_.layers.pop_back();
  EXPECT_THROW(internal::writeMeshMapH5(dir_ / "x.h5", map_, profile_), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.h5"));
}

TEST(MeshMapLayers, BorderIsTheOpenBoundaryAndTheUnknown) {
  // A 2 x 2 grid of squares: vertex 4 in the middle is inside, the other 8 on the boundary.
  LayeredMesh map;
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 3; ++x) map.mesh.vertices.emplace_back(x, y, 0);
  }
  for (std::uint32_t y = 0; y < 2; ++y) {
    for (std::uint32_t x = 0; x < 2; ++x) {
      const std::uint32_t v = 3 * y + x;
      map.mesh.faces.push_back({v, v + 1, v + 4});
      map.mesh.faces.push_back({v, v + 4, v + 3});
    }
  }
  map.layers.resize(map.mesh.faces.size());
  for (FaceLayers& l : map.layers) {
    l.face_class = FaceClass::kFree;
    l.cost = 0.1f;
  }
  const auto border = [&] { return vertexLayer(map, RobotProfile{}, "border"); };
  EXPECT_EQ(border(), (std::vector<float>{1, 1, 1, 1, 0, 1, 1, 1, 1}));
  map.layers[0].face_class = FaceClass::kUnknown;  // face {0, 1, 4} touches the middle
  EXPECT_EQ(border()[4], 1.0f);
}

TEST(VertexWorst, HighestOrLowestSkippingNan) {
  LayeredMesh map = strip();
  const auto contact = map.vertexWorst([](const FaceLayers& f) { return f.contact; }, LayeredMesh::Worst::kLowest);
  EXPECT_FLOAT_EQ(contact[0], 0.9f);
  EXPECT_FLOAT_EQ(contact[3], 0.5f);
  const auto roughness = map.vertexWorst([](const FaceLayers& f) { return f.roughness_m; });
  EXPECT_FLOAT_EQ(roughness[0], 0.02f);
  map.layers[0].roughness_m = NAN;
  EXPECT_TRUE(std::isnan(map.vertexWorst([](const FaceLayers& f) { return f.roughness_m; })[4]));
  // vertexCost is the same rule: unknown faces skipped, lethal counts 1.
  const auto cost = map.vertexCost();
  EXPECT_FLOAT_EQ(cost[0], 0.4f);
  EXPECT_FLOAT_EQ(cost[1], 1.0f);
  EXPECT_TRUE(std::isnan(cost[3]));
}

}  // namespace
}  // namespace terramesh::traversability

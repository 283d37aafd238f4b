// Exports of a traversability map: level segmentation, traversability.ply round trip, Nav2 maps
// (PGM + YAML, cost PNG), GeoTIFF layers, read back with independent parsers (yaml-cpp, GDAL).
#include <Eigen/Geometry>
#include <gdal.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "common/input_error.h"
#include "test_support/temp_dir.h"
#include "traversability/layer_registry.h"
#include "traversability/map_directory.h"
#include "traversability/map_levels.h"

namespace terramesh::traversability {
namespace {

using Eigen::Vector3d;

/// Builds a mesh of unit-cell height-field patches whose coincident vertices are welded, so that
/// faces of touching patches share edges.
class MeshBuilder {
 public:
  /// Cells [x0, x1) x [y0, y1) with 1 m spacing, normals up.
  void patch(int x0, int x1, int y0, int y1, const std::function<double(double, double)>& z, const char* tag) {
    for (int x = x0; x < x1; ++x) {
      for (int y = y0; y < y1; ++y) {
        const auto v = [&](int i, int j) { return vertex({double(i), double(j), z(i, j)}); };
        face(v(x, y), v(x + 1, y), v(x + 1, y + 1), tag);
        face(v(x, y), v(x + 1, y + 1), v(x, y + 1), tag);
      }
    }
  }
  void face(std::uint32_t a, std::uint32_t b, std::uint32_t c, const char* tag) {
    mesh.faces.push_back({a, b, c});
    tags.emplace_back(tag);
  }
  std::uint32_t vertex(const Vector3d& p) {
    const auto key = std::make_tuple(std::lround(p.x() * 1000), std::lround(p.y() * 1000), std::lround(p.z() * 1000));
    const auto [it, inserted] = index_.emplace(key, static_cast<std::uint32_t>(mesh.vertices.size()));
    if (inserted) mesh.vertices.push_back(p);
    return it->second;
  }
  /// Every face free with cost 0.2, except as changed afterwards.
  LayeredMesh layered() const {
    LayeredMesh map;
    map.mesh = mesh;
    map.layers.resize(mesh.faces.size());
    for (FaceLayers& l : map.layers) {
      l.face_class = FaceClass::kFree;
      l.cost = 0.2f;
      l.slope_deg = 1;
      l.rays = 7;
      l.evidence = Evidence::kMeasured;
      l.height_uncertainty_m = 0.04f;
    }
    return map;
  }

  mesher::TriangleMesh mesh;
  std::vector<std::string> tags;

 private:
  std::map<std::tuple<long, long, long>, std::uint32_t> index_;
};

/// Two floors 3 m apart over [0, 20] x [0, 10], joined by a ramp beside them (y in [10, 14],
/// rising from x = 20 to x = 0) with landings that do not overlap the other floor; a lethal wall
/// on the ground floor and a ceiling (the upper slab's underside, unknown) that no level may take.
MeshBuilder twoFloorGarage() {
  MeshBuilder b;
  const auto flat = [](double z) { return [z](double, double) { return z; }; };
  b.patch(0, 20, 0, 10, flat(0), "floor0");
  b.patch(20, 24, 0, 14, flat(0), "floor0");
  b.patch(0, 20, 10, 14, [](double x, double) { return 3.0 * (20 - x) / 20; }, "ramp");
  b.patch(0, 20, 0, 10, flat(3), "floor1");
  b.patch(-4, 0, 0, 14, flat(3), "floor1");
  // A wall (vertical quad) standing on the ground floor at x = 10.03, y in [2, 4].
  const auto w0 = b.vertex({10.03, 2, 0}), w1 = b.vertex({10.03, 4, 0}), w2 = b.vertex({10.03, 4, 1}), w3 = b.vertex({10.03, 2, 1});
  b.face(w0, w1, w2, "wall");
  b.face(w0, w2, w3, "wall");
  // The ceiling of the ground floor, facing down, 0.2 m below the upper floor.
  const auto c0 = b.vertex({5, 5, 2.8}), c1 = b.vertex({6, 5, 2.8}), c2 = b.vertex({6, 6, 2.8});
  b.face(c0, c2, c1, "ceiling");
  return b;
}

LayeredMesh garageMap(const MeshBuilder& b) {
  LayeredMesh map = b.layered();
  for (std::size_t f = 0; f < map.layers.size(); ++f) {
    if (b.tags[f] == "wall") {
      map.layers[f].face_class = FaceClass::kLethal;
      map.layers[f].cost = 1;
    } else if (b.tags[f] == "ceiling") {
      map.layers[f].face_class = FaceClass::kUnknown;
      map.layers[f].cost = NAN;
    }
  }
  return map;
}

TEST(LevelSegmentation, TwoFloorsAndARampGiveTwoLevels) {
  const MeshBuilder b = twoFloorGarage();
  const LayeredMesh map = garageMap(b);
  const MapPlane plane = MapPlane::fromUp(Vector3d::UnitZ(), 1.0);
  const Levels levels = segmentLevels(map, plane, LevelConfig{});
  ASSERT_EQ(levels.count(), 2u);
  EXPECT_LT(levels.mean_height_m[0], levels.mean_height_m[1]);
  for (std::size_t f = 0; f < b.tags.size(); ++f) {
    if (b.tags[f] == "floor0" || b.tags[f] == "wall") {
      EXPECT_EQ(levels.face_level[f], 0) << b.tags[f] << " " << f;
    }
    if (b.tags[f] == "ceiling") {
      EXPECT_EQ(levels.face_level[f], Levels::kNone);
    }
    if (b.tags[f] == "wall") {
      EXPECT_FALSE(levels.walkable[f]);
    }
  }
  for (std::size_t f = 0; f < b.tags.size(); ++f) {
    const Vector3d centroid = (b.mesh.vertices[b.mesh.faces[f][0]] + b.mesh.vertices[b.mesh.faces[f][1]] +
                               b.mesh.vertices[b.mesh.faces[f][2]]) / 3;
    if (b.tags[f] == "floor1") {
      EXPECT_EQ(levels.face_level[f], 1) << f;
    }
    // A level climbs at most level_separation_m (1.5 m) from its seed: the ramp's lower half
    // belongs to the ground floor's level, its upper half to the upper floor's it leads to.
    if (b.tags[f] == "ramp") {
      EXPECT_EQ(levels.face_level[f], centroid.z() <= LevelConfig{}.level_separation_m ? 0 : 1) << f;
    }
  }
  // The whole upper floor (20 x 10 over the ground floor, 4 x 14 beyond it) and the ramp's upper
  // half (10 x 4): the upper floor is one map, not split where the ramp reaches it.
  EXPECT_NEAR(levels.walkable_area_m2[1], 296.0, 1e-6);
}

/// Brute-force oracle: no two walkable faces of one level overlap in plan at heights more than
/// the separation apart.
void expectSingleValued(const LayeredMesh& map, const Levels& levels, double separation_m) {
  const auto& m = map.mesh;
  const auto centroid = [&](std::size_t f) {
    return Vector3d((m.vertices[m.faces[f][0]] + m.vertices[m.faces[f][1]] + m.vertices[m.faces[f][2]]) / 3);
  };
  const auto heightInside = [&](std::size_t f, const Vector3d& p, double& z) {
    const Vector3d a = m.vertices[m.faces[f][0]], b = m.vertices[m.faces[f][1]], c = m.vertices[m.faces[f][2]];
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(det) < 1e-12) return false;
    const double u = ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / det;
    const double v = ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / det;
    if (u <= 1e-9 || v <= 1e-9 || u + v >= 1 - 1e-9) return false;
    z = a.z() + u * (b.z() - a.z()) + v * (c.z() - a.z());
    return true;
  };
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    if (!levels.walkable[f]) continue;
    const Vector3d p = centroid(f);
    for (std::size_t g = 0; g < m.faces.size(); ++g) {
      double z = 0;
      if (g == f || !levels.walkable[g] || levels.face_level[g] != levels.face_level[f] || !heightInside(g, p, z)) continue;
      EXPECT_LE(std::abs(z - p.z()), separation_m) << "faces " << f << " and " << g;
    }
  }
}

TEST(LevelSegmentation, EveryLevelIsSingleValued) {
  const MeshBuilder b = twoFloorGarage();
  const LayeredMesh map = garageMap(b);
  const Levels levels = segmentLevels(map, MapPlane::fromUp(Vector3d::UnitZ(), 1.0), LevelConfig{});
  expectSingleValued(map, levels, LevelConfig{}.level_separation_m);
  // Without the overlap test the two floors would be one level: make sure the oracle can fail.
  LevelConfig loose;
  loose.level_separation_m = 100;
  const Levels merged = segmentLevels(map, MapPlane::fromUp(Vector3d::UnitZ(), 1.0), loose);
  EXPECT_EQ(merged.count(), 1u);
}

MeshBuilder street() {
  MeshBuilder b;
  b.patch(0, 60, 0, 12, [](double x, double y) { return 0.05 * std::sin(x) + (y >= 10 ? 0.15 : 0.0); }, "street");
  return b;
}

TEST(LevelSegmentation, AStreetIsOneLevel) {
  const MeshBuilder b = street();
  const Levels levels = segmentLevels(b.layered(), MapPlane::fromUp(Vector3d::UnitZ(), 1.0), LevelConfig{});
  ASSERT_EQ(levels.count(), 1u);
  for (std::int32_t level : levels.face_level) EXPECT_EQ(level, 0);
  EXPECT_NEAR(levels.walkable_area_m2[0], 720.0, 1e-6);
}

TEST(LevelSegmentation, SpecksAreMergedOrDropped) {
  MeshBuilder b = street();
  // A 1 m^2 platform 5 m above the street: too small to be a level, too high to merge.
  b.patch(30, 31, 5, 6, [](double, double) { return 5.0; }, "speck");
  const LayeredMesh map = b.layered();
  const Levels levels = segmentLevels(map, MapPlane::fromUp(Vector3d::UnitZ(), 1.0), LevelConfig{});
  ASSERT_EQ(levels.count(), 1u);
  for (std::size_t f = 0; f < b.tags.size(); ++f) {
    if (b.tags[f] == "speck") {
      EXPECT_EQ(levels.face_level[f], Levels::kNone);
    }
  }
}

TEST(MapPlane, AxesAreOrthonormalAndFollowWorldX) {
  const MapPlane plane = MapPlane::fromUp(Vector3d(0, 0.3, 1), 2.0);
  EXPECT_NEAR(plane.x_W.dot(plane.y_W), 0, 1e-12);
  EXPECT_NEAR(plane.x_W.dot(plane.z_W), 0, 1e-12);
  EXPECT_NEAR(plane.z_W.norm(), 1, 1e-12);
  EXPECT_NEAR(plane.x_W.cross(plane.y_W).dot(plane.z_W), 1, 1e-12);
  EXPECT_NEAR(plane.x_W.x(), 1, 1e-12);  // world x is already perpendicular to this up
  EXPECT_NEAR(plane.heightM(Vector3d(0, 0, 1)), 2.0 / std::sqrt(1.09), 1e-12);
  EXPECT_THROW(MapPlane::fromUp(Vector3d::Zero(), 1.0), std::invalid_argument);
  EXPECT_THROW(MapPlane::fromUp(Vector3d::UnitZ(), 0.0), std::invalid_argument);
}

// ---- map directory ---------------------------------------------------------------------------

struct Pgm {
  std::size_t width = 0, height = 0;
  std::vector<unsigned char> pixels;
  unsigned char at(std::size_t col, std::size_t row) const { return pixels.at(row * width + col); }
};

Pgm readPgm(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  in >> magic;
  EXPECT_EQ(magic, "P5");
  std::vector<long> numbers;
  while (numbers.size() < 3) {
    in >> std::ws;
    if (in.peek() == '#') {
      std::string comment;
      std::getline(in, comment);
      continue;
    }
    long n = 0;
    in >> n;
    numbers.push_back(n);
  }
  in.get();  // the single whitespace after maxval
  Pgm pgm;
  pgm.width = static_cast<std::size_t>(numbers[0]);
  pgm.height = static_cast<std::size_t>(numbers[1]);
  EXPECT_EQ(numbers[2], 255);
  pgm.pixels.resize(pgm.width * pgm.height);
  in.read(reinterpret_cast<char*>(pgm.pixels.data()), static_cast<std::streamsize>(pgm.pixels.size()));
  EXPECT_TRUE(in.good());
  EXPECT_EQ(in.peek(), EOF);
  return pgm;
}

/// Image column and row (row 0 = top = largest y) of plan point (x, y) in a Nav2 map.
std::pair<std::size_t, std::size_t> pixelOf(const YAML::Node& yaml, std::size_t image_height, double x, double y) {
  const double r = yaml["resolution"].as<double>();
  const double ox = yaml["origin"][0].as<double>(), oy = yaml["origin"][1].as<double>();
  const auto col = static_cast<std::size_t>(std::floor((x - ox) / r));
  const auto grid_row = static_cast<std::size_t>(std::floor((y - oy) / r));
  return {col, image_height - 1 - grid_row};
}

class MapDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    builder_ = twoFloorGarage();
    map_ = garageMap(builder_);
    for (std::size_t f = 0; f < builder_.tags.size(); ++f) {
      if (builder_.tags[f] != "floor0") continue;
      const auto& v = builder_.mesh.vertices[builder_.mesh.faces[f][0]];
      if (v.x() >= 2 && v.x() < 3 && v.y() >= 2 && v.y() < 5) {
        map_.layers[f].face_class = FaceClass::kLethal;
        map_.layers[f].cost = 1;
        map_.layers[f].reasons = reason::kTooSteep;
      }
      if (v.x() >= 4 && v.x() < 5 && v.y() >= 2 && v.y() < 5) {
        map_.layers[f].face_class = FaceClass::kUnknown;
        map_.layers[f].cost = NAN;
        map_.layers[f].steiner = true;
        map_.layers[f].evidence = Evidence::kInterpolated;
        map_.layers[f].height_uncertainty_m = INFINITY;
        map_.layers[f].reasons = reason::kClosingGeometry;
      }
      if (v.x() >= 6 && v.x() < 7 && v.y() >= 2 && v.y() < 5) {
        map_.layers[f].face_class = FaceClass::kUncertain;
        map_.layers[f].cost = 0.9f;
        map_.layers[f].evidence = Evidence::kInterpolated;
        map_.layers[f].height_uncertainty_m = 0.3f;
        map_.layers[f].reasons = reason::kPossibleStep | reason::kWorstCaseRelief;
      }
    }
    map_.mesh.is_steiner.assign(map_.mesh.vertices.size(), 0);
    map_.mesh.is_steiner[3] = 1;
    map_.layers[5].clearance_m = 2.25f;
    map_.layers[6].lethal_distance_m = 0.75f;
    map_.layers[7].roughness_m = NAN;
    profile_.name = "export_test_robot";
    config_.grid_resolution_m = 0.1;
  }

  MeshBuilder builder_;
  LayeredMesh map_;
  RobotProfile profile_;
  ExportConfig config_;
  test::TempDir dir_;
};

TEST_F(MapDirectoryTest, WritesEveryFileOfEveryLevel) {
  const ExportReport report = writeMapDirectory(dir_.path(), map_, profile_, config_);
  EXPECT_EQ(report.levels, 2u);
  for (const char* name : {"traversability.ply", "level_0.pgm", "level_0.yaml", "level_0_cost.png", "level_0_cost.yaml",
                           "layers_level_0.tif", "level_1.pgm", "layers_level_1.tif", "robot.yaml", "map_frame.yaml",
                           "traversability_summary.txt"}) {
    EXPECT_TRUE(std::filesystem::exists(dir_ / name)) << name;
    EXPECT_NE(std::find(report.files.begin(), report.files.end(), name), report.files.end()) << name;
  }
  for (const auto& entry : std::filesystem::directory_iterator(dir_.path())) {
    EXPECT_NE(entry.path().filename().string().front(), '.') << "temporary file left: " << entry.path();
  }
  std::ifstream summary(dir_ / "traversability_summary.txt");
  std::stringstream text;
  text << summary.rdbuf();
  EXPECT_NE(text.str().find("levels: 2"), std::string::npos) << text.str();
}

TEST_F(MapDirectoryTest, RoundTripPreservesMeshLayersNanAndFrame) {
  map_.up_W = Vector3d(0, 0.1, 1).normalized();
  map_.metres_per_unit = 2.5;
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  const MapDirectory read = readMapDirectory(dir_.path());
  const LayeredMesh& m = read.map;
  ASSERT_EQ(m.mesh.vertices.size(), map_.mesh.vertices.size());
  ASSERT_EQ(m.mesh.faces, map_.mesh.faces);
  EXPECT_EQ(m.mesh.is_steiner, map_.mesh.is_steiner);
  for (std::size_t v = 0; v < m.mesh.vertices.size(); ++v) EXPECT_EQ(m.mesh.vertices[v], map_.mesh.vertices[v]);
  const auto same = [](double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; };
  std::size_t unknown = 0, uncertain = 0;
  for (std::size_t f = 0; f < m.layers.size(); ++f) {
    const FaceLayers &a = m.layers[f], &b = map_.layers[f];
    EXPECT_EQ(a.face_class, b.face_class) << f;
    for (const LayerInfo& layer : faceLayerRegistry()) {
      EXPECT_TRUE(same(layer.get(a), layer.get(b))) << "face " << f << ", " << layer.name;
    }
    EXPECT_EQ(a.steiner, b.steiner);
    unknown += a.face_class == FaceClass::kUnknown;
    uncertain += a.face_class == FaceClass::kUncertain;
  }
  EXPECT_GT(unknown, 0u);
  EXPECT_GT(uncertain, 0u);
  EXPECT_TRUE(std::isinf(m.layers[0].clearance_m));
  EXPECT_TRUE(std::isnan(m.layers[7].roughness_m));
  EXPECT_NEAR((m.up_W - map_.up_W).norm(), 0, 1e-15);
  EXPECT_EQ(m.metres_per_unit, 2.5);
  EXPECT_EQ(read.profile.name, "export_test_robot");
}

TEST_F(MapDirectoryTest, Nav2TrinaryMapHasTheConventionalPixels) {
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  const YAML::Node yaml = YAML::LoadFile((dir_ / "level_0.yaml").string());
  EXPECT_EQ(yaml["image"].as<std::string>(), "level_0.pgm");
  EXPECT_EQ(yaml["mode"].as<std::string>(), "trinary");
  EXPECT_EQ(yaml["resolution"].as<double>(), 0.1);
  ASSERT_EQ(yaml["origin"].size(), 3u);
  EXPECT_EQ(yaml["origin"][2].as<double>(), 0.0);
  EXPECT_EQ(yaml["negate"].as<int>(), 0);
  EXPECT_EQ(yaml["occupied_thresh"].as<double>(), 0.65);
  EXPECT_EQ(yaml["free_thresh"].as<double>(), 0.196);
  const Pgm pgm = readPgm(dir_ / "level_0.pgm");
  // Level 0 spans at least x in [0, 24] and y in [0, 14]: at 0.1 m, 240 x 140 cells or more.
  EXPECT_GE(pgm.width, 240u);
  EXPECT_GE(pgm.height, 140u);
  const auto pixel = [&](double x, double y) {
    const auto [col, row] = pixelOf(yaml, pgm.height, x, y);
    return pgm.at(col, row);
  };
  EXPECT_EQ(pixel(15.55, 7.55), 254);  // free floor
  EXPECT_EQ(pixel(2.55, 3.55), 0);     // lethal faces
  EXPECT_EQ(pixel(10.05, 3.05), 0);    // the wall (no plan area) is rasterised along its base
  EXPECT_EQ(pixel(4.55, 3.55), 205);   // unknown faces
  EXPECT_EQ(pixel(6.55, 3.55), 205);   // uncertain faces: neither free nor lethal
  EXPECT_EQ(pixel(22.55, 13.55), 254); // the landing
  EXPECT_EQ(pgm.at(0, 0), 205);        // padding: no surface
  // Row 0 is the top: the lethal patch at y in [2, 5] is near the bottom of the image.
  EXPECT_GT(pixelOf(yaml, pgm.height, 2.55, 3.55).second, pgm.height / 2);
  // Level 1 holds the upper floor at the same plan position as level 0's free floor.
  const YAML::Node yaml1 = YAML::LoadFile((dir_ / "level_1.yaml").string());
  const Pgm pgm1 = readPgm(dir_ / "level_1.pgm");
  const auto [c1, r1] = pixelOf(yaml1, pgm1.height, 2.55, 3.55);
  EXPECT_EQ(pgm1.at(c1, r1), 254);  // free upstairs, above the lethal patch
}

TEST_F(MapDirectoryTest, CostMapUsesScaleModeWithAlphaForUnknown) {
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  const YAML::Node yaml = YAML::LoadFile((dir_ / "level_0_cost.yaml").string());
  EXPECT_EQ(yaml["mode"].as<std::string>(), "scale");
  EXPECT_EQ(yaml["image"].as<std::string>(), "level_0_cost.png");
  GDALAllRegister();
  GDALDatasetH png = GDALOpen((dir_ / "level_0_cost.png").c_str(), GA_ReadOnly);
  ASSERT_NE(png, nullptr);
  ASSERT_EQ(GDALGetRasterCount(png), 2);
  const auto h = static_cast<std::size_t>(GDALGetRasterYSize(png));
  const auto read = [&](int band, double x, double y) {
    const auto [col, row] = pixelOf(yaml, h, x, y);
    unsigned char value = 0;
    EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(png, band), GF_Read, static_cast<int>(col), static_cast<int>(row), 1, 1,
                           &value, 1, 1, GDT_Byte, 0, 0),
              CE_None);
    return value;
  };
  // What nav2_map_server computes in scale mode (negate 0): occ = (255 - p) / 255, then
  // occ > 0.65 -> 100, occ < 0.196 -> 0, else rint((occ - 0.196) / (0.65 - 0.196) * 100).
  const auto nav2 = [](unsigned char p) {
    const double occ = (255.0 - p) / 255.0;
    return occ > 0.65 ? 100.0 : occ < 0.196 ? 0.0 : std::rint((occ - 0.196) / (0.65 - 0.196) * 100);
  };
  EXPECT_NEAR(nav2(read(1, 15.55, 7.55)), 20, 1);  // cost 0.2
  EXPECT_EQ(read(2, 15.55, 7.55), 255);
  EXPECT_EQ(nav2(read(1, 2.55, 3.55)), 100);  // lethal
  EXPECT_EQ(read(2, 4.55, 3.55), 0);          // unknown: transparent
  EXPECT_NEAR(nav2(read(1, 6.55, 3.55)), 90, 1);  // uncertain: its own cost, 0.9
  EXPECT_EQ(read(2, 6.55, 3.55), 255);
  GDALClose(png);
}

TEST_F(MapDirectoryTest, GeoTiffHasNamedBandsNanNodataAndTheLayerValues) {
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  GDALAllRegister();
  for (int level = 0; level < 2; ++level) {
    const std::string name = "layers_level_" + std::to_string(level) + ".tif";
    GDALDatasetH tif = GDALOpen((dir_ / name).c_str(), GA_ReadOnly);
    ASSERT_NE(tif, nullptr);
    // The cost, the class, every other layer of the registry in its order, the height.
    const std::vector<std::string> bands = {"cost",         "class",        "slope_deg",   "step_m",
                                            "roughness_m",  "contact",      "contact_best", "clearance_m",
                                            "lethal_distance_m", "height_uncertainty_m", "evidence", "rays",
                                            "reasons",      "heading_fits", "height_m"};
    const auto bandOf = [&bands](const std::string& band_name) {
      return static_cast<int>(std::find(bands.begin(), bands.end(), band_name) - bands.begin()) + 1;
    };
    ASSERT_EQ(GDALGetRasterCount(tif), static_cast<int>(bands.size()));
    double transform[6];
    ASSERT_EQ(GDALGetGeoTransform(tif, transform), CE_None);
    EXPECT_EQ(transform[1], 0.1);
    EXPECT_EQ(transform[5], -0.1);
    const auto value = [&](int band, double x, double y) {
      const int col = static_cast<int>(std::floor((x - transform[0]) / transform[1]));
      const int row = static_cast<int>(std::floor((y - transform[3]) / transform[5]));
      float v = 0;
      EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(tif, band), GF_Read, col, row, 1, 1, &v, 1, 1, GDT_Float32, 0, 0),
                CE_None);
      return v;
    };
    for (std::size_t b = 0; b < bands.size(); ++b) {
      GDALRasterBandH band = GDALGetRasterBand(tif, static_cast<int>(b + 1));
      EXPECT_EQ(GDALGetDescription(band), bands[b]);
      int has_nodata = 0;
      EXPECT_TRUE(std::isnan(GDALGetRasterNoDataValue(band, &has_nodata)));
      EXPECT_TRUE(has_nodata);
      EXPECT_TRUE(std::isnan(value(static_cast<int>(b + 1), transform[0] + 0.05, transform[3] - 0.05)));  // padding
    }
    EXPECT_FLOAT_EQ(value(1, 15.55, 7.55), 0.2f);
    EXPECT_EQ(value(2, 15.55, 7.55), 0.0f);
    EXPECT_EQ(value(3, 15.55, 7.55), 1.0f);
    EXPECT_EQ(value(bandOf("rays"), 15.55, 7.55), 7.0f);
    EXPECT_NEAR(value(bandOf("height_m"), 15.55, 7.55), level == 0 ? 0.0 : 3.0, 1e-6);
    if (level == 0) {
      EXPECT_EQ(value(2, 2.55, 3.55), 1.0f);  // lethal class
      EXPECT_TRUE(std::isnan(value(1, 4.55, 3.55)));  // unknown cost
      EXPECT_EQ(value(2, 4.55, 3.55), 2.0f);
      EXPECT_EQ(value(2, 6.55, 3.55), 3.0f);  // uncertain class
      EXPECT_FLOAT_EQ(value(1, 6.55, 3.55), 0.9f);
      EXPECT_EQ(value(bandOf("evidence"), 6.55, 3.55), 2.0f);  // interpolated
      EXPECT_FLOAT_EQ(value(bandOf("height_uncertainty_m"), 6.55, 3.55), 0.3f);
      EXPECT_EQ(value(bandOf("reasons"), 6.55, 3.55), 80.0f);  // possible step + worst case does not fit
      EXPECT_EQ(value(bandOf("reasons"), 2.55, 3.55), 1.0f);   // too steep
    }
    EXPECT_EQ(value(bandOf("evidence"), 15.55, 7.55), 0.0f);  // measured
    EXPECT_FLOAT_EQ(value(bandOf("height_uncertainty_m"), 15.55, 7.55), 0.04f);
    GDALClose(tif);
  }
}

TEST_F(MapDirectoryTest, MapFrameYamlAndStaleLevelsAndNoGeotiff) {
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  const YAML::Node frame = YAML::LoadFile((dir_ / "map_frame.yaml").string());
  for (const char* key : {"up", "metres_per_unit", "plan_x", "plan_y"}) EXPECT_TRUE(frame[key]) << key;
  EXPECT_EQ(frame["up"][2].as<double>(), 1.0);
  // A one-level map written over it removes level 1 and, without GeoTIFF, every .tif.
  config_.write_geotiff = false;
  const ExportReport report = writeMapDirectory(dir_.path(), street().layered(), profile_, config_);
  EXPECT_EQ(report.levels, 1u);
  EXPECT_TRUE(std::filesystem::exists(dir_ / "level_0.pgm"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "level_1.pgm"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "level_1_cost.png"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "layers_level_0.tif"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "layers_level_1.tif"));
}

TEST_F(MapDirectoryTest, ReadingABrokenDirectoryNamesTheFile) {
  EXPECT_THROW(readMapDirectory(dir_ / "missing"), InputError);
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  std::filesystem::resize_file(dir_ / "traversability.ply", std::filesystem::file_size(dir_ / "traversability.ply") - 9);
  try {
    readMapDirectory(dir_.path());
    FAIL() << "a truncated PLY must be refused";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("traversability.ply"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("face "), std::string::npos) << error.what();
  }
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  std::ofstream(dir_ / "map_frame.yaml") << "up: [0, 0, 1]\nmetres_per_unit: -1\n";
  try {
    readMapDirectory(dir_.path());
    FAIL() << "a negative scale must be refused";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("map_frame.yaml"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("metres_per_unit"), std::string::npos) << error.what();
  }
}

TEST_F(MapDirectoryTest, ABadRegistryLayerValueNamesTheFaceTheLayerAndWhatWasExpected) {
  writeMapDirectory(dir_.path(), map_, profile_, config_);
  // One triangle in ASCII, every required layer, then `evidence` and `reasons` as given.
  const auto writePly = [&](const std::string& evidence, const std::string& reasons) {
    std::ofstream(dir_ / "traversability.ply")
        << "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
           "element face 1\nproperty list uchar uint vertex_indices\nproperty float cost\nproperty uchar lethal\n"
           "property uchar unknown\nproperty float slope_deg\nproperty float step_m\nproperty float roughness_m\n"
           "property float contact\nproperty float contact_best\nproperty float clearance_m\n"
           "property float lethal_distance_m\nproperty float evidence\nproperty uint rays\n"
           "property float reasons\nproperty uchar steiner\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
        << "3 0 1 2 0.5 0 0 1 0 0 1 1 inf inf " << evidence << " 4 " << reasons << " 0\n";
  };
  writePly("0", "80");
  EXPECT_EQ(readMapDirectory(dir_.path()).map.layers.at(0).reasons, reason::kPossibleStep | reason::kWorstCaseRelief);
  for (const auto& [evidence, reasons, expected] :
       {std::tuple<std::string, std::string, std::string>{"7", "0", "evidence 7"}, {"0", "1.5", "reasons 1.5"},
        {"0", "70000", "reasons 70000"}}) {
    writePly(evidence, reasons);
    try {
      readMapDirectory(dir_.path());
      FAIL() << expected << " must be refused";
    } catch (const InputError& error) {
      const std::string what = error.what();
      EXPECT_NE(what.find("traversability.ply"), std::string::npos) << what;
      EXPECT_NE(what.find("face 0"), std::string::npos) << what;
      EXPECT_NE(what.find(expected.substr(0, expected.find(' '))), std::string::npos) << what;
      EXPECT_NE(what.find("expected"), std::string::npos) << what;
    }
  }
}

TEST(LayerRegistry, NamesEachLayerOnceAndFindsItByName) {
  std::set<std::string> names;
  for (const LayerInfo& layer : faceLayerRegistry()) {
    EXPECT_TRUE(names.insert(layer.name).second) << layer.name << " twice";
    EXPECT_EQ(findFaceLayer(layer.name), &layer);
    // A value set is the value read back (exact for the integer layers).
    FaceLayers face;
    face.face_class = FaceClass::kFree;
    layer.set(face, 2.0);
    EXPECT_EQ(layer.get(face), 2.0) << layer.name;
  }
  EXPECT_EQ(findFaceLayer("no_such_layer"), nullptr);
  ASSERT_NE(findFaceLayer("reasons"), nullptr);
  EXPECT_EQ(findFaceLayer("reasons")->type, LayerType::kUInt16);
  EXPECT_EQ(findFaceLayer("reasons")->worst, LayeredMesh::Worst::kBitwiseOr);
  EXPECT_EQ(reason::names().size(), reason::kCount);
  EXPECT_EQ(std::string(reason::names()[4]), "possible_step");
  EXPECT_EQ(reason::kPossibleStep, 1u << 4);
}

TEST(ExportConfig, ValidateListsEveryProblem) {
  ExportConfig config;
  config.grid_resolution_m = 0;
  config.levels.level_separation_m = -1;
  try {
    config.validate();
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("grid_resolution_m"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("level_separation_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace terramesh::traversability

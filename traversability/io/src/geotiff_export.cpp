// layers_level_N.tif: every layer of one level on its plan grid, one Float32 band each (GDAL).
#include <gdal.h>
#include <cpl_conv.h>
#include <cpl_string.h>
#include <unistd.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>

#include "export_writers.h"
#include "plan_geometry.h"
#include "traversability/layer_registry.h"

namespace terramesh::traversability::internal {

const std::vector<std::string>& geotiffBandNames() {
  static const std::vector<std::string> kNames = [] {
    // The cost, the class, every other registry layer in its order, then the height of the
    // surface at the cell's centre.
    std::vector<std::string> names = {"cost", "class"};
    for (const LayerInfo& layer : faceLayerRegistry()) {
      if (std::string_view(layer.name) != "cost") names.emplace_back(layer.name);
    }
    names.emplace_back("height_m");
    return names;
  }();
  return kNames;
}

void writeLayerGeoTiff(const std::filesystem::path& path, const LevelGrid& grid, const LayeredMesh& map,
                       const MapPlane& plane) {
  const std::size_t w = grid.width, h = grid.height;
  const std::size_t bands = geotiffBandNames().size();
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> data(bands * w * h, kNaN);
  std::vector<FacePlan> plans(map.mesh.faces.size());  // computed on first use (valid = done)
  for (std::size_t row = 0; row < h; ++row) {
    for (std::size_t col = 0; col < w; ++col) {
      const std::size_t cell = grid.index(col, h - 1 - row);  // raster row 0 = largest y
      if (grid.face[cell] < 0) continue;
      const auto f = static_cast<std::size_t>(grid.face[cell]);
      const FaceLayers& l = map.layers[f];
      const bool unknown = l.face_class == FaceClass::kUnknown;
      if (!plans[f].valid) plans[f] = planFace(map.mesh, f, plane);
      const FacePlan& face = plans[f];
      const Eigen::Vector2d centre(grid.origin_x_m + (static_cast<double>(col) + 0.5) * grid.resolution_m,
                                   grid.origin_y_m + (static_cast<double>(h - 1 - row) + 0.5) * grid.resolution_m);
      std::size_t b = 0;
      const auto put = [&](double value) { data[b++ * w * h + row * w + col] = static_cast<float>(value); };
      put(unknown ? kNaN : l.face_class == FaceClass::kLethal ? 1.0f : l.cost);
      put(static_cast<int>(l.face_class));
      for (const LayerInfo& layer : faceLayerRegistry()) {
        if (std::string_view(layer.name) != "cost") put(layer.get(l));
      }
      put(heightAt(face, centre));
    }
  }

  GDALAllRegister();
  GDALDriverH driver = GDALGetDriverByName("GTiff");
  if (!driver) throw std::runtime_error(path.string() + ": GDAL has no GTiff driver");
  const std::filesystem::path temporary =
      path.parent_path() / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()));
  char** options = nullptr;
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  // Fastest DEFLATE: the map is rewritten every few keyframes; level 6 + predictor was ~3x slower
  // for ~15 % smaller files (gdal_translate on the demo street's 2665 x 1115 grid).
  options = CSLSetNameValue(options, "ZLEVEL", "1");
  options = CSLSetNameValue(options, "INTERLEAVE", "BAND");
  CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");
  GDALDatasetH dataset = GDALCreate(driver, temporary.c_str(), static_cast<int>(w), static_cast<int>(h),
                                    static_cast<int>(bands), GDT_Float32, options);
  CSLDestroy(options);
  bool ok = dataset != nullptr;
  if (ok) {
    // North-up: x grows with the column, y falls with the row from the top edge.
    double transform[6] = {grid.origin_x_m, grid.resolution_m, 0, grid.origin_y_m + static_cast<double>(h) * grid.resolution_m,
                           0, -grid.resolution_m};
    ok = GDALSetGeoTransform(dataset, transform) == CE_None;
    GDALSetMetadataItem(dataset, "TERRAMESH_FRAME",
                        "local metric map frame of map_frame.yaml (no CRS); x, y in metres", nullptr);
    for (std::size_t b = 0; ok && b < bands; ++b) {
      GDALRasterBandH band = GDALGetRasterBand(dataset, static_cast<int>(b + 1));
      GDALSetDescription(band, geotiffBandNames()[b].c_str());
      ok = GDALSetRasterNoDataValue(band, std::numeric_limits<double>::quiet_NaN()) == CE_None &&
           GDALRasterIO(band, GF_Write, 0, 0, static_cast<int>(w), static_cast<int>(h), data.data() + b * w * h,
                        static_cast<int>(w), static_cast<int>(h), GDT_Float32, 0, 0) == CE_None;
    }
  }
  if (dataset) {
    CPLErrorReset();
    GDALClose(dataset);  // flushes; GDAL 3.6 reports failures only through CPLGetLastErrorType
    if (CPLGetLastErrorType() >= CE_Failure) ok = false;
  }
  CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", nullptr);
  if (!ok) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(path.string() + ": cannot write GeoTIFF: " + CPLGetLastErrorMsg());
  }
  std::filesystem::rename(temporary, path);
}

}  // namespace terramesh::traversability::internal

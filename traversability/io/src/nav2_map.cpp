// Nav2 / ROS map_server maps of one level: a trinary PGM and a scale-mode cost PNG, each with
// its YAML (conventions of nav2_map_server's map_io.cpp, see docs/traversability.md).
#include <gdal.h>
#include <cpl_conv.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "common/atomic_file.h"
#include "export_writers.h"

namespace terramesh::traversability::internal {
namespace {

constexpr unsigned char kFreePixel = 254, kLethalPixel = 0, kUnknownPixel = 205;
constexpr double kOccupiedThresh = 0.65, kFreeThresh = 0.196;

/// Scale-mode grey level of a free cell of cost c: the loader reads occupancy
/// occ = (255 - p) / 255 and maps occ in [free_thresh, occupied_thresh] linearly to 0..100; we aim
/// at round(99 c) so that no free cell ever reads as lethal (100).
unsigned char costPixel(float cost) {
  const double value = std::round(std::clamp(static_cast<double>(cost), 0.0, 1.0) * 99.0);
  if (value <= 0) return kFreePixel;
  const double occupancy = kFreeThresh + value / 100.0 * (kOccupiedThresh - kFreeThresh);
  return static_cast<unsigned char>(std::lround(255.0 * (1.0 - occupancy)));
}

std::string yamlText(const std::string& image, const std::string& mode, const LevelGrid& grid,
                     const MapPlane& plane, double level_height_m) {
  std::ostringstream out;
  out.precision(12);
  out << "# terramesh traversability map, one walkable level (mean height " << level_height_m << " m).\n"
      << "# Map frame (metres): x = (" << plane.x_W.transpose() << "), y = (" << plane.y_W.transpose()
      << "), up = (" << plane.z_W.transpose() << ") in the mesh frame, times metres_per_unit "
      << plane.metres_per_unit << " (see map_frame.yaml).\n";
  if (mode == "trinary") out << "# Pixels: 254 free, 0 lethal, 205 unknown; row 0 is the largest y.\n";
  else out << "# Grey level carries the cost (see docs/traversability.md); alpha 0 = unknown.\n";
  out << "image: " << image << "\nmode: " << mode << "\nresolution: " << grid.resolution_m << "\norigin: ["
      << grid.origin_x_m << ", " << grid.origin_y_m << ", 0.0]\nnegate: 0\noccupied_thresh: " << kOccupiedThresh
      << "\nfree_thresh: " << kFreeThresh << '\n';
  return out.str();
}

std::filesystem::path temporaryName(const std::filesystem::path& path) {
  return path.parent_path() / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()));
}

/// Writes a grey + alpha PNG with GDAL (temp file, then rename).
void writeGreyAlphaPng(const std::filesystem::path& path, std::size_t width, std::size_t height,
                       std::vector<unsigned char>& grey, std::vector<unsigned char>& alpha) {
  GDALAllRegister();
  GDALDriverH mem = GDALGetDriverByName("MEM");
  GDALDriverH png = GDALGetDriverByName("PNG");
  if (!mem || !png) throw std::runtime_error(path.string() + ": GDAL has no MEM or PNG driver");
  GDALDatasetH source = GDALCreate(mem, "", static_cast<int>(width), static_cast<int>(height), 2, GDT_Byte, nullptr);
  if (!source) throw std::runtime_error(path.string() + ": cannot create an in-memory image");
  CPLErr error = CE_None;
  for (int band = 1; band <= 2; ++band) {
    GDALRasterBandH h = GDALGetRasterBand(source, band);
    GDALSetRasterColorInterpretation(h, band == 1 ? GCI_GrayIndex : GCI_AlphaBand);
    std::vector<unsigned char>& data = band == 1 ? grey : alpha;
    if (error == CE_None) {
      error = GDALRasterIO(h, GF_Write, 0, 0, static_cast<int>(width), static_cast<int>(height), data.data(),
                           static_cast<int>(width), static_cast<int>(height), GDT_Byte, 0, 0);
    }
  }
  const std::filesystem::path temporary = temporaryName(path);
  CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");
  GDALDatasetH copy = error == CE_None ? GDALCreateCopy(png, temporary.c_str(), source, FALSE, nullptr, nullptr, nullptr)
                                       : nullptr;
  CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", nullptr);
  GDALClose(source);
  bool ok = copy != nullptr;
  if (copy) {
    CPLErrorReset();
    GDALClose(copy);
    ok = CPLGetLastErrorType() < CE_Failure;
  }
  if (!ok) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw std::runtime_error(path.string() + ": cannot write PNG: " + CPLGetLastErrorMsg());
  }
  std::filesystem::rename(temporary, path);
}

}  // namespace

void writeNav2Maps(const std::filesystem::path& dir, const std::string& base, const LevelGrid& grid,
                   const LayeredMesh& map, const MapPlane& plane, double level_height_m,
                   std::vector<std::string>& files) {
  const std::size_t w = grid.width, h = grid.height;
  // Image row 0 is the top of the map (largest y): grid row h - 1.
  std::string pgm = "P5\n# terramesh trinary map\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
  const std::size_t header = pgm.size();
  pgm.resize(header + w * h);
  std::vector<unsigned char> grey(w * h), alpha(w * h);
  for (std::size_t row = 0; row < h; ++row) {
    for (std::size_t col = 0; col < w; ++col) {
      const std::size_t cell = grid.index(col, h - 1 - row), pixel = row * w + col;
      const FaceClass c = grid.cell_class[cell];
      pgm[header + pixel] = static_cast<char>(c == FaceClass::kFree     ? kFreePixel
                                              : c == FaceClass::kLethal ? kLethalPixel
                                                                        : kUnknownPixel);
      // Uncertain cells are unknown in the trinary map (the evidence cannot decide: never free,
      // never lethal by invention) and carry their own cost in the scale map.
      const bool has_cost = c == FaceClass::kFree || c == FaceClass::kUncertain;
      const float cost = has_cost ? map.layers[static_cast<std::size_t>(grid.face[cell])].cost : 0.0f;
      const bool no_cost = c == FaceClass::kUnknown || !std::isfinite(cost);  // a free face without a cost
      alpha[pixel] = no_cost ? 0 : 255;
      grey[pixel] = no_cost ? kUnknownPixel : c == FaceClass::kLethal ? kLethalPixel : costPixel(cost);
    }
  }
  writeFileAtomically(dir / (base + ".pgm"), pgm);
  writeFileAtomically(dir / (base + ".yaml"), yamlText(base + ".pgm", "trinary", grid, plane, level_height_m));
  files.push_back(base + ".pgm");
  files.push_back(base + ".yaml");
  if (w == 0 || h == 0) return;
  writeGreyAlphaPng(dir / (base + "_cost.png"), w, h, grey, alpha);
  writeFileAtomically(dir / (base + "_cost.yaml"), yamlText(base + "_cost.png", "scale", grid, plane, level_height_m));
  files.push_back(base + "_cost.png");
  files.push_back(base + "_cost.yaml");
}

}  // namespace terramesh::traversability::internal

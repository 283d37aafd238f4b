// traversability_summary.txt: areas per level, layer statistics (every registry layer marked
// in_summary), face counts, and faces per reason they are not free.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "export_writers.h"
#include "traversability/layer_registry.h"

namespace terramesh::traversability::internal {
namespace {

void statsLine(std::ostream& out, const std::string& name, std::vector<float> values) {
  out << "  " << std::left << std::setw(18) << name << std::right;
  std::size_t infinite = 0;
  values.erase(std::remove_if(values.begin(), values.end(),
                              [&](float v) {
                                if (std::isinf(v)) ++infinite;
                                return !std::isfinite(v);
                              }),
               values.end());
  if (values.empty()) {
    out << " no finite values";
  } else {
    std::sort(values.begin(), values.end());
    out << " min " << std::setw(10) << values.front() << "  median " << std::setw(10) << values[values.size() / 2]
        << "  max " << std::setw(10) << values.back() << "  (" << values.size() << " faces";
    out << ")";
  }
  if (infinite > 0) out << ", " << infinite << " infinite";
  out << '\n';
}

}  // namespace

std::string mapSummary(const LayeredMesh& map, const Levels& levels, const std::vector<LevelGrid>& grids) {
  std::ostringstream out;
  out << std::setprecision(4);
  std::size_t counts[4] = {0, 0, 0, 0}, evidence[3] = {0, 0, 0};
  for (const FaceLayers& l : map.layers) {
    ++counts[static_cast<int>(l.face_class)];
    ++evidence[static_cast<int>(l.evidence)];
  }
  out << "faces: " << map.layers.size() << " (free " << counts[0] << ", lethal " << counts[1] << ", unknown "
      << counts[2] << ", uncertain " << counts[3] << ")\nevidence: measured " << evidence[0] << ", driven "
      << evidence[1] << ", interpolated " << evidence[2] << " faces\nvertices: " << map.mesh.vertices.size()
      << "\nmetres_per_unit: " << map.metres_per_unit
      << "\nup: " << map.up_W.x() << " " << map.up_W.y() << " " << map.up_W.z() << "\nlevels: " << levels.count()
      << '\n';
  for (std::size_t l = 0; l < levels.count(); ++l) {
    const LevelGrid& grid = grids[l];
    std::size_t cells[4] = {0, 0, 0, 0}, empty = 0, faces = 0;
    for (std::size_t i = 0; i < grid.face.size(); ++i) {
      if (grid.face[i] < 0) ++empty;
      else ++cells[static_cast<int>(grid.cell_class[i])];
    }
    for (std::int32_t level : levels.face_level) faces += level == static_cast<std::int32_t>(l);
    const double cell_area = grid.resolution_m * grid.resolution_m;
    out << "level " << l << ": mean height " << levels.mean_height_m[l] << " m, walkable area "
        << levels.walkable_area_m2[l] << " m^2, " << faces << " faces; grid " << grid.width << " x " << grid.height
        << " at " << grid.resolution_m << " m: free " << static_cast<double>(cells[0]) * cell_area << " m^2, lethal "
        << static_cast<double>(cells[1]) * cell_area  << " m^2, unknown " << static_cast<double>(cells[2]) * cell_area
        << " m^2, uncertain " << static_cast<double>(cells[3]) * cell_area << " m^2, no surface " << static_cast<double>(empty) * cell_area << " m^2\n";
  }
  out << "layer statistics over known faces:\n";
  const auto known = [&](auto get) {
    std::vector<float> values;
    for (const FaceLayers& l : map.layers) {
      if (l.face_class != FaceClass::kUnknown) values.push_back(get(l));
    }
    return values;
  };
  std::vector<float> free_cost;
  for (const FaceLayers& l : map.layers) {
    if (l.face_class == FaceClass::kFree) free_cost.push_back(l.cost);
  }
  statsLine(out, "cost (free faces)", free_cost);
  for (const LayerInfo& layer : faceLayerRegistry()) {
    if (!layer.in_summary) continue;
    statsLine(out, layer.name, known([&layer](const FaceLayers& l) { return static_cast<float>(layer.get(l)); }));
  }
  // Why faces are not free: per reason, the faces of each class whose rule it is.
  out << "why not free (faces per reason; a face may have several):\n";
  const std::vector<const char*>& names = reason::names();
  for (std::size_t bit = 0; bit < names.size(); ++bit) {
    std::size_t per_class[4] = {0, 0, 0, 0};
    for (const FaceLayers& l : map.layers) per_class[static_cast<int>(l.face_class)] += (l.reasons >> bit) & 1u;
    const std::size_t faces = per_class[1] + per_class[2] + per_class[3];
    if (faces == 0) continue;
    out << "  " << std::left << std::setw(22) << names[bit] << std::right << ' ' << faces << " ("
        << (per_class[1] > 0 ? "lethal" : per_class[3] > 0 ? "uncertain" : "unknown") << ")\n";
  }
  return out.str();
}

}  // namespace terramesh::traversability::internal

#include "traversability/layer_registry.h"

#include <cmath>
#include <limits>

namespace terramesh::traversability {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kNoRange = 1.0f, kNoRangeMax = 0.0f;  // display_min > display_max: no fixed range
using Worst = LayeredMesh::Worst;

/// A float field of FaceLayers.
template <float FaceLayers::*Member>
double getField(const FaceLayers& face) {
  return face.*Member;
}
template <float FaceLayers::*Member>
void setField(FaceLayers& face, double value) {
  face.*Member = static_cast<float>(value);
}

std::vector<LayerInfo> makeRegistry() {
  std::vector<LayerInfo> layers;
  layers.push_back({"cost", "", LayerType::kFloat32, "cost (0 free .. 1 limit; lethal 1, NaN unknown)",
                    [](const FaceLayers& f) -> double { return f.face_class == FaceClass::kUnknown ? kNaN : f.cost; },
                    [](FaceLayers& f, double v) { f.cost = static_cast<float>(v); }, false, Worst::kHighest, 0.0f, 1.0f, false,
                    false});
  const auto field = [&layers](const char* name, const char* unit, const char* description,
                               double (*get)(const FaceLayers&), void (*set)(FaceLayers&, double), Worst worst,
                               bool optional = false, bool in_mesh_map = false) {
    layers.push_back({name, unit, LayerType::kFloat32, description, get, set, optional, worst, kNoRange, kNoRangeMax,
                      true, in_mesh_map});
  };
  field("slope_deg", "deg", "slope (deg)", getField<&FaceLayers::slope_deg>, setField<&FaceLayers::slope_deg>,
        Worst::kHighest);
  field("step_m", "m", "step (m)", getField<&FaceLayers::step_m>, setField<&FaceLayers::step_m>, Worst::kHighest);
  field("roughness_m", "m", "roughness (m)", getField<&FaceLayers::roughness_m>, setField<&FaceLayers::roughness_m>,
        Worst::kHighest);
  field("contact", "fraction", "contact (fraction)", getField<&FaceLayers::contact>, setField<&FaceLayers::contact>,
        Worst::kLowest, false, true);
  field("contact_best", "fraction", "best contact (fraction)", getField<&FaceLayers::contact_best>,
        setField<&FaceLayers::contact_best>, Worst::kLowest);
  field("clearance_m", "m", "clearance (m; inf = nothing above)", getField<&FaceLayers::clearance_m>,
        setField<&FaceLayers::clearance_m>, Worst::kLowest);
  field("lethal_distance_m", "m", "distance to lethal (m)", getField<&FaceLayers::lethal_distance_m>,
        setField<&FaceLayers::lethal_distance_m>, Worst::kLowest);
  field("height_uncertainty_m", "m", "height uncertainty bound (m)", getField<&FaceLayers::height_uncertainty_m>,
        setField<&FaceLayers::height_uncertainty_m>, Worst::kHighest, true, true);
  layers.push_back({"evidence", "code", LayerType::kUInt8, "evidence (0 measured, 1 driven, 2 interpolated)",
                    [](const FaceLayers& f) -> double { return static_cast<int>(f.evidence); },
                    [](FaceLayers& f, double v) { f.evidence = static_cast<Evidence>(static_cast<int>(v)); }, true,
                    Worst::kHighest, 0.0f, 2.0f, false, true});
  layers.push_back({"rays", "count", LayerType::kUInt32, "observedness (rays through the face)",
                    [](const FaceLayers& f) -> double { return f.rays; },
                    [](FaceLayers& f, double v) { f.rays = static_cast<std::uint32_t>(v); }, false, Worst::kLowest,
                    kNoRange, kNoRangeMax, true, false});
  layers.push_back({"reasons", "bits", LayerType::kUInt16,
                    "why not free (bits: too steep, no heading fits, low clearance, guessed wall, possible step, "
                    "slope may exceed, worst-case relief, possible obstacle, obstacle extension, unconfirmed point, "
                    "unknown low clearance, closing geometry, few rays)",
                    [](const FaceLayers& f) -> double { return f.reasons; },
                    [](FaceLayers& f, double v) { f.reasons = static_cast<std::uint16_t>(v); }, true,
                    Worst::kBitwiseOr, kNoRange, kNoRangeMax, false, true});
  layers.push_back({"heading_fits", "bits", LayerType::kUInt32,
                    "headings of travel that fit in the worst case (bit k: k x 180 / contact_headings deg)",
                    [](const FaceLayers& f) -> double { return f.heading_fits; },
                    [](FaceLayers& f, double v) { f.heading_fits = static_cast<std::uint32_t>(v); }, true,
                    Worst::kBitwiseAnd, kNoRange, kNoRangeMax, false, true});
  return layers;
}

}  // namespace

const std::vector<LayerInfo>& faceLayerRegistry() {
  static const std::vector<LayerInfo> kLayers = makeRegistry();
  return kLayers;
}

const LayerInfo* findFaceLayer(std::string_view name) {
  for (const LayerInfo& layer : faceLayerRegistry()) {
    if (name == layer.name) return &layer;
  }
  return nullptr;
}

const std::vector<const char*>& reason::names() {
  static const std::vector<const char*> kNames = {
      "too_steep",         "no_heading_fits",    "low_clearance",         "guessed_wall",
      "possible_step",     "slope_may_exceed",   "worst_case_relief",     "possible_obstacle",
      "obstacle_extension", "unconfirmed_point", "unknown_low_clearance", "closing_geometry",
      "few_rays",          "seen_from_behind"};
  return kNames;
}

}  // namespace terramesh::traversability

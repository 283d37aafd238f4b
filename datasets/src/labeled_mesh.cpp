#include "datasets/labeled_mesh.h"

#include <array>
#include <stdexcept>
#include <string>

namespace terramesh::datasets {
namespace {

constexpr std::array<std::string_view, kSurfaceLabelCount> kLabelNames = {
    "road", "sidewalk", "curb", "wall", "obstacle", "vegetation", "ceiling", "ramp"};

}  // namespace

std::string_view toString(SurfaceLabel label) {
  const auto index = static_cast<std::size_t>(label);
  return index < kLabelNames.size() ? kLabelNames[index] : std::string_view("unknown");
}

std::optional<SurfaceLabel> parseSurfaceLabel(std::string_view name) {
  for (std::size_t i = 0; i < kLabelNames.size(); ++i) {
    if (kLabelNames[i] == name) return static_cast<SurfaceLabel>(i);
  }
  return std::nullopt;
}

void LabeledMesh::validate() const {
  const std::size_t faces = mesh.faces.size();
  if (labels.size() != faces || slope_deg.size() != faces) {
    throw std::invalid_argument("LabeledMesh: " + std::to_string(faces) + " faces but " +
                                std::to_string(labels.size()) + " labels and " +
                                std::to_string(slope_deg.size()) + " slopes");
  }
}

}  // namespace terramesh::datasets

#include "mesher/mesher.h"

#include "mesher_impl.h"

namespace terramesh::mesher {

namespace {
const MesherConfig& validated(const MesherConfig& config) {
  config.validate();
  return config;
}
}  // namespace

Mesher::Mesher(const MesherConfig& config) : impl_(std::make_unique<Impl>(validated(config))) {}
Mesher::~Mesher() = default;
Mesher::Mesher(Mesher&&) noexcept = default;
Mesher& Mesher::operator=(Mesher&&) noexcept = default;

UpdateStats Mesher::integrateKeyframe(const Keyframe& keyframe) {
  return impl_->integrateKeyframe(keyframe);
}
UpdateStats Mesher::removePoints(const std::vector<PointId>& points) {
  return impl_->removePoints(points);
}
UpdateStats Mesher::removeKeyframe(KeyframeId keyframe) { return impl_->removeKeyframe(keyframe); }
TriangleMesh Mesher::extractMesh() const { return impl_->extractMesh(); }
MapSize Mesher::size() const { return impl_->size(); }
const MesherConfig& Mesher::config() const { return impl_->config(); }
std::vector<CellVisibility> Mesher::cellVisibility() const { return impl_->cellVisibility(); }
InvariantReport Mesher::checkInvariants() const { return impl_->checkInvariants(); }

}  // namespace terramesh::mesher

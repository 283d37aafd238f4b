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
UpdateStats Mesher::removeKeyframes(const std::vector<KeyframeId>& keyframes) {
  return impl_->removeKeyframes(keyframes);
}
UpdateStats Mesher::releaseFarSteiner(const std::vector<Eigen::Vector3d>& keep_W, double reach_m) {
  return impl_->releaseFarSteiner(keep_W, reach_m);
}
TriangleMesh Mesher::extractMesh() const { return impl_->extractMesh(); }
std::uint64_t Mesher::revision() const { return impl_->revision(); }
SurfaceDelta Mesher::changesSince(std::uint64_t revision) const { return impl_->changesSince(revision); }
std::vector<SurfaceFace> Mesher::surfaceFaces() const { return impl_->surfaceFaces(); }
std::vector<SurfaceFace> Mesher::facesAround(const std::vector<VertexKey>& vertices) const {
  return impl_->facesAround(vertices);
}
std::vector<UnconfirmedPoint> Mesher::unconfirmedPoints() const { return impl_->unconfirmedPoints(); }
UnconfirmedCursor Mesher::unconfirmedCursor() const { return impl_->unconfirmedCursor(); }
UnconfirmedChanges Mesher::unconfirmedChangesSince(const UnconfirmedCursor& cursor) const {
  return impl_->unconfirmedChangesSince(cursor);
}
MapSize Mesher::size() const { return impl_->size(); }
const MesherConfig& Mesher::config() const { return impl_->config(); }
std::vector<CellVisibility> Mesher::cellVisibility() const { return impl_->cellVisibility(); }
InvariantReport Mesher::checkInvariants() const { return impl_->checkInvariants(); }

}  // namespace terramesh::mesher

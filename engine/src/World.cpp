#include "crowdcloth/World.h"

#include "WorldImpl.h"

namespace cc {
namespace {

detail::WorldImpl& impl(World* w) { return *static_cast<detail::WorldImpl*>(w); }
const detail::WorldImpl& impl(const World* w) { return *static_cast<const detail::WorldImpl*>(w); }

} // namespace

Result<World*> World::create(const WorldDesc& desc) {
    auto world = detail::WorldImpl::create(desc);
    if (!world.isOk()) return world.status();
    return static_cast<World*>(world.value());
}

void World::destroy(World* world) { delete static_cast<detail::WorldImpl*>(world); }

Result<AssetId> World::addClothAsset(const ClothAssetDesc& desc) { return impl(this).addClothAsset(desc); }

Result<BodyId> World::addMannequinBody(const MannequinDesc& desc) {
    auto body = detail::makeMannequinBody(desc);
    if (!body.isOk()) return body.status();
    return impl(this).addBody(std::move(body).value());
}

Result<BodyId> World::addCharacterBody(const Character& character, const BodyDesc& desc) {
    auto body = detail::makeCharacterBody(character, desc);
    if (!body.isOk()) return body.status();
    return impl(this).addBody(std::move(body).value());
}

Status World::setBodyLandmarks(BodyId body, const BodyLandmarkDesc& landmarks) {
    return impl(this).setBodyLandmarks(body, landmarks);
}
Result<BodyLandmarkDesc> World::bodyLandmarks(BodyId body) const { return impl(this).bodyLandmarks(body); }
Result<uint32_t> World::bodyClipCount(BodyId body) const { return impl(this).bodyClipCount(body); }
Result<const char*> World::bodyClipName(BodyId body, uint32_t index) const { return impl(this).bodyClipName(body, index); }

Result<BodyId> World::addSkinnedBody(const float* bindPositions, uint32_t vertexCount, uint32_t strideBytes,
                                     const uint32_t* triangles, uint32_t triangleCount) {
    auto body = detail::makeHostSkinnedBody(bindPositions, vertexCount, strideBytes, triangles, triangleCount);
    if (!body.isOk()) return body.status();
    return impl(this).addBody(std::move(body).value());
}

Result<CharacterId> World::addCharacter(const CharacterDesc& desc) { return impl(this).addCharacter(desc); }
Status World::removeCharacter(CharacterId id) { return impl(this).removeCharacter(id); }
Status World::setCharacterRoot(CharacterId id, const double position[3], double yaw) {
    return impl(this).setCharacterRoot(id, position, yaw);
}
Status World::setCharacterPlaybackRate(CharacterId id, double playbackRate) {
    return impl(this).setCharacterPlaybackRate(id, playbackRate);
}
Status World::setCharacterSkinnedVertices(CharacterId id, const float* positions, uint32_t vertexCount,
                                          uint32_t strideBytes) {
    return impl(this).setCharacterSkinnedVertices(id, positions, vertexCount, strideBytes);
}
Result<GarmentId> World::addGarment(AssetId asset, CharacterId character, const GarmentDesc& desc) {
    return impl(this).addGarment(asset, character, desc);
}
Status World::removeGarment(GarmentId id) { return impl(this).removeGarment(id); }
Status World::setCameras(const CameraDesc* cameras, uint32_t count) { return impl(this).setCameras(cameras, count); }
Status World::setFrameBudget(double milliseconds) { return impl(this).setFrameBudget(milliseconds); }
Status World::step(double dt) { return impl(this).step(dt); }
Status World::beginStep(double dt) { return impl(this).beginStep(dt); }
uint32_t World::stepTaskCount() const { return impl(this).stepTaskCount(); }
Status World::runStepTask(uint32_t index) { return impl(this).runStepTask(index); }
bool World::nextStepPhase() { return impl(this).nextStepPhase(); }
Status World::endStep() { return impl(this).endStep(); }
Result<RenderMeshView> World::renderMesh(GarmentId id) const { return impl(this).renderMesh(id); }
Result<RenderMeshView> World::characterMesh(CharacterId id) { return impl(this).characterMesh(id); }
Result<GarmentStats> World::garmentStats(GarmentId id) const { return impl(this).garmentStats(id); }
Result<ClothAssetDesc> World::garmentFit(GarmentId id) const { return impl(this).garmentFit(id); }
const FrameStats& World::frameStats() const { return impl(this).frameStats(); }
std::string World::statsJson() const { return impl(this).statsJson(); }
uint64_t World::stateHash() const { return impl(this).stateHash(); }

} // namespace cc

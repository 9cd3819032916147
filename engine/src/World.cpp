#include "crowdcloth/World.h"

#include "WorldImpl.h"

namespace cc {
namespace {

detail::WorldImpl& impl(World* w) { return *static_cast<detail::WorldImpl*>(w); }
const detail::WorldImpl& impl(const World* w) { return *static_cast<const detail::WorldImpl*>(w); }

/// Between beginStep() and endStep() the step's tasks read and write the characters, garments
/// and bodies: a call that changes them (or reads what the tasks write) would race with them or
/// leave a task a dangling pointer, so it is refused, naming itself.
Status outsideStep(const World* w, const char* call) {
    if (!impl(w).stepOpen()) return Status::ok();
    return Status::error(StatusCode::InvalidOperation, std::string("World::") + call +
                                                           ": a step is open (beginStep() without endStep()); "
                                                           "call it after endStep()");
}

} // namespace

Result<World*> World::create(const WorldDesc& desc) {
    auto world = detail::WorldImpl::create(desc);
    if (!world.isOk()) return world.status();
    return static_cast<World*>(world.value());
}

void World::destroy(World* world) { delete static_cast<detail::WorldImpl*>(world); }

Result<AssetId> World::addClothAsset(const ClothAssetDesc& desc) {
    if (Status s = outsideStep(this, "addClothAsset"); !s) return s;
    return impl(this).addClothAsset(desc);
}

Status World::setErrorTable(AssetId design, const ErrorTable& table) {
    if (Status s = outsideStep(this, "setErrorTable"); !s) return s;
    return impl(this).setErrorTable(design, table);
}

Status World::loadErrorTable(AssetId design, const char* directory) {
    if (Status s = outsideStep(this, "loadErrorTable"); !s) return s;
    return impl(this).loadErrorTable(design, directory);
}

Result<BodyId> World::addMannequinBody(const MannequinDesc& desc) {
    if (Status s = outsideStep(this, "addMannequinBody"); !s) return s;
    auto body = detail::makeMannequinBody(desc);
    if (!body.isOk()) return body.status();
    return impl(this).addBody(std::move(body).value());
}

Result<BodyId> World::addCharacterBody(const Character& character, const BodyDesc& desc) {
    if (Status s = outsideStep(this, "addCharacterBody"); !s) return s;
    auto body = detail::makeCharacterBody(character, desc);
    if (!body.isOk()) return body.status();
    return impl(this).addBody(std::move(body).value());
}

Status World::setBodyLandmarks(BodyId body, const BodyLandmarkDesc& landmarks) {
    if (Status s = outsideStep(this, "setBodyLandmarks"); !s) return s;
    return impl(this).setBodyLandmarks(body, landmarks);
}
Result<BodyLandmarkDesc> World::bodyLandmarks(BodyId body) const { return impl(this).bodyLandmarks(body); }
Result<uint32_t> World::bodyClipCount(BodyId body) const { return impl(this).bodyClipCount(body); }
Result<const char*> World::bodyClipName(BodyId body, uint32_t index) const { return impl(this).bodyClipName(body, index); }

Result<BodyId> World::addSkinnedBody(const float* bindPositions, uint32_t vertexCount, uint32_t strideBytes,
                                     const uint32_t* triangles, uint32_t triangleCount) {
    if (Status s = outsideStep(this, "addSkinnedBody"); !s) return s;
    auto body = detail::makeHostSkinnedBody(bindPositions, vertexCount, strideBytes, triangles, triangleCount);
    if (!body.isOk()) return body.status();
    return impl(this).addBody(std::move(body).value());
}

Result<CharacterId> World::addCharacter(const CharacterDesc& desc) {
    if (Status s = outsideStep(this, "addCharacter"); !s) return s;
    return impl(this).addCharacter(desc);
}
Status World::removeCharacter(CharacterId id) {
    if (Status s = outsideStep(this, "removeCharacter"); !s) return s;
    return impl(this).removeCharacter(id);
}
Status World::setCharacterRoot(CharacterId id, const double position[3], double yaw) {
    if (Status s = outsideStep(this, "setCharacterRoot"); !s) return s;
    return impl(this).setCharacterRoot(id, position, yaw);
}
Status World::setCharacterPlaybackRate(CharacterId id, double playbackRate) {
    if (Status s = outsideStep(this, "setCharacterPlaybackRate"); !s) return s;
    return impl(this).setCharacterPlaybackRate(id, playbackRate);
}
Status World::setCharacterSkinnedVertices(CharacterId id, const float* positions, uint32_t vertexCount,
                                          uint32_t strideBytes) {
    if (Status s = outsideStep(this, "setCharacterSkinnedVertices"); !s) return s;
    return impl(this).setCharacterSkinnedVertices(id, positions, vertexCount, strideBytes);
}
Result<GarmentId> World::addGarment(AssetId asset, CharacterId character, const GarmentDesc& desc) {
    if (Status s = outsideStep(this, "addGarment"); !s) return s;
    return impl(this).addGarment(asset, character, desc);
}
Status World::removeGarment(GarmentId id) {
    if (Status s = outsideStep(this, "removeGarment"); !s) return s;
    return impl(this).removeGarment(id);
}
Status World::setGarmentLevel(GarmentId id, int32_t forceLevel) {
    if (Status s = outsideStep(this, "setGarmentLevel"); !s) return s;
    return impl(this).setGarmentLevel(id, forceLevel);
}
Status World::setCameras(const CameraDesc* cameras, uint32_t count) {
    if (Status s = outsideStep(this, "setCameras"); !s) return s;
    return impl(this).setCameras(cameras, count);
}
Status World::setFrameBudget(double milliseconds) {
    if (Status s = outsideStep(this, "setFrameBudget"); !s) return s;
    return impl(this).setFrameBudget(milliseconds);
}
Status World::step(double dt) { return impl(this).step(dt); }
Status World::beginStep(double dt) { return impl(this).beginStep(dt); }
uint32_t World::stepTaskCount() const { return impl(this).stepTaskCount(); }
Status World::runStepTask(uint32_t index) { return impl(this).runStepTask(index); }
bool World::nextStepPhase() { return impl(this).nextStepPhase(); }
Status World::endStep() { return impl(this).endStep(); }
Result<RenderMeshView> World::renderMesh(GarmentId id) const {
    if (Status s = outsideStep(this, "renderMesh"); !s) return s;
    return impl(this).renderMesh(id);
}
Result<RenderMeshView> World::characterMesh(CharacterId id) {
    if (Status s = outsideStep(this, "characterMesh"); !s) return s;
    return impl(this).characterMesh(id);
}
Result<GarmentStats> World::garmentStats(GarmentId id) const {
    if (Status s = outsideStep(this, "garmentStats"); !s) return s;
    return impl(this).garmentStats(id);
}
Result<ClothAssetDesc> World::garmentFit(GarmentId id) const {
    if (Status s = outsideStep(this, "garmentFit"); !s) return s;
    return impl(this).garmentFit(id);
}
const FrameStats& World::frameStats() const { return impl(this).frameStats(); }
std::string World::statsJson() const { return impl(this).statsJson(); }
Status World::setShadowCheck(const ShadowCheckDesc& desc) {
    if (Status s = outsideStep(this, "setShadowCheck"); !s) return s;
    return impl(this).setShadowCheck(desc);
}

const std::vector<ShadowCheckResult>& World::shadowCheckResults() const { return impl(this).shadowCheckResults(); }

uint64_t World::stateHash() const { return impl(this).stateHash(); }

Result<std::vector<uint8_t>> World::saveState() const {
    if (Status s = outsideStep(this, "saveState"); !s) return s;
    return impl(this).saveState();
}

Status World::restoreState(const void* data, std::size_t size, RestoreMode mode) {
    if (Status s = outsideStep(this, "restoreState"); !s) return s;
    return impl(this).restoreState(data, size, mode);
}

} // namespace cc

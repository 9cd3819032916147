// The World's bodies and the garments fitted to them: imported characters, host landmarks, and
// the per-body cooking of garment designs (WorldImpl's frame loop lives in WorldImpl.cpp).
#include "GarmentFit.h"
#include "WorldImpl.h"

namespace cc::detail {
namespace {

Status staleBody() { return Status::invalidArgument("body is null, stale or from another world"); }

} // namespace

Result<AssetId> WorldImpl::fittedAsset(DesignRecord& design, const std::shared_ptr<const BodyAsset>& body) {
    for (const auto& [fittedBody, asset] : design.fitted)
        if (fittedBody == body) return asset;
    auto cooked = cookFittedGarment(design.desc, *body);
    if (!cooked.isOk()) return cooked.status();
    auto record = std::make_unique<AssetRecord>();
    record->asset = std::make_shared<const CookedAsset>(std::move(cooked).value());
    record->errors = design.errors;
    const auto h = mAssets.add(std::move(record));
    const AssetId id{h.index1, h.generation};
    design.fitted.push_back({body, id});
    return id;
}

Status WorldImpl::setErrorTable(AssetId id, const ErrorTable& table) {
    DesignRecord* design = mDesigns.get(id);
    if (!design) return Status::invalidArgument("setErrorTable: asset is null, stale or from another world");
    if (Status s = table.validate(); !s) return Status::invalidArgument("setErrorTable: " + s.message());
    if (table.levelCount() != design->desc.levelCount)
        return Status::invalidArgument("setErrorTable: the table has " + std::to_string(table.levelCount()) +
                                       " levels, the design " + std::to_string(design->desc.levelCount));
    if (table.key != errorTableKey(design->desc, mDesc, table.cook))
        return Status::invalidArgument("setErrorTable: the table was measured for another design or World effort "
                                       "(substeps, solverIterations, strainLimit, gravity): cook it for this one");
    design->errors = std::make_shared<const ErrorTable>(table.nonIncreasingInLevel());
    for (const auto& fitted : design->fitted)
        if (AssetRecord* asset = mAssets.get(fitted.second)) asset->errors = design->errors;
    return Status::ok();
}

Status WorldImpl::loadErrorTable(AssetId id, const char* directory) {
    const DesignRecord* design = mDesigns.get(id);
    if (!design) return Status::invalidArgument("loadErrorTable: asset is null, stale or from another world");
    if (!directory || !*directory) return Status::invalidArgument("loadErrorTable: directory is null or empty");
    auto table = loadOrCookErrorTable(directory, design->desc, mDesc);
    if (!table.isOk()) return Status::error(table.status().code(), "loadErrorTable: " + table.status().message());
    return setErrorTable(id, table.value());
}

Status WorldImpl::setBodyLandmarks(BodyId id, const BodyLandmarkDesc& landmarks) {
    BodyRecord* record = mBodies.get(id);
    if (!record) return staleBody();
    // Characters already made keep the body they were made with (their garments are bound to it).
    BodyAsset changed = *record->body;
    if (Status s = applyLandmarks(changed, landmarks); !s) return s;
    record->body = std::make_shared<const BodyAsset>(std::move(changed));
    return Status::ok();
}

Result<BodyLandmarkDesc> WorldImpl::bodyLandmarks(BodyId id) const {
    const BodyRecord* record = mBodies.get(id);
    if (!record) return staleBody();
    if (!record->body->fitStatus) return record->body->fitStatus;
    return landmarksOf(*record->body);
}

Result<ClothAssetDesc> WorldImpl::garmentFit(GarmentId id) const {
    const GarmentInstance* g = mGarments.get(id);
    if (!g) return Status::invalidArgument("garment is null, stale or from another world");
    return g->asset().desc;
}

Result<uint32_t> WorldImpl::bodyClipCount(BodyId id) const {
    const BodyRecord* record = mBodies.get(id);
    if (!record) return staleBody();
    return uint32_t(record->body->hostSkinned ? 0 : record->body->character().clips.size());
}

Result<const char*> WorldImpl::bodyClipName(BodyId id, uint32_t index) const {
    const BodyRecord* record = mBodies.get(id);
    if (!record) return staleBody();
    const auto& clips = record->body->character().clips;
    if (record->body->hostSkinned || index >= clips.size())
        return Status::invalidArgument("bodyClipName: clip " + std::to_string(index) + " of " + std::to_string(clips.size()));
    return clips[index].name.c_str();
}

} // namespace cc::detail

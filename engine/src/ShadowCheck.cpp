#include "ShadowCheck.h"

#include <algorithm>
#include <cmath>

#include "crowdcloth/lod/ScreenError.h"

namespace cc {

Status ShadowCheckDesc::validate() const {
    if (garments > 64) return Status::invalidArgument("ShadowCheckDesc.garments must be in [0, 64]");
    if (!(windowSeconds >= 0.05 && windowSeconds <= 2.0))
        return Status::invalidArgument("ShadowCheckDesc.windowSeconds must be in [0.05, 2] s");
    if (substeps < 2 || substeps > 64) return Status::invalidArgument("ShadowCheckDesc.substeps must be in [2, 64]");
    if (iterations < 1 || iterations > 100)
        return Status::invalidArgument("ShadowCheckDesc.iterations must be in [1, 100]");
    return Status::ok();
}

namespace detail {

Status ShadowCheck::configure(const ShadowCheckDesc& desc) {
    if (Status s = desc.validate(); !s) return s;
    mDesc = desc;
    clear();
    mWindows.resize(desc.garments);
    return Status::ok();
}

void ShadowCheck::clear() {
    for (Window& w : mWindows) w.copy.reset(), w.twin.reset();
    mResults.clear();
}

Result<const cloth::SubstepFactor*> ShadowCheck::factorFor(const CookedAsset& asset, double substep) {
    for (const CachedFactor& f : mFactors)
        if (f.asset == &asset && f.substep == substep) return f.factor.get();
    auto built = asset.levels.back().cloth->buildFactor(substep);
    if (!built.isOk()) return built.status();
    // Few assets and one frame time in a run: a handful of factors.
    mFactors.push_back({&asset, substep, std::move(built).value()});
    return mFactors.back().factor.get();
}

bool ShadowCheck::start(Window& w, const GarmentRef& item, const ShadowFrame& frame) {
    GarmentInstance& garment = *item.garment;
    CharacterInstance& character = *item.character;
    auto made = garment.clone(character);
    if (!made.isOk()) return false;
    std::unique_ptr<GarmentInstance> copy = std::move(made).value();
    copy->switchLevel(int(copy->asset().levels.size()) - 1);
    copy->schedule.level = copy->level();
    copy->schedule.updateInterval = 1;
    copy->context.selfCollision = frame.selfCollision && garment.schedule.selfCollision;

    // Its own body collider: the character's is moved at the times its garments update, which the
    // copy must not change.
    if (Status s = character.updateSkin(); !s) return false;
    if (w.collider && w.topology == character.bodyTopology) {
        if (!w.collider->reset(character.skinnedPositions)) return false;
    } else {
        w.collider.reset();
        if (!character.bodyTopology) return false;
        auto collider = collision::BodyCollider::create(*frame.device, character.bodyTopology, character.skinnedPositions);
        if (!collider.isOk()) return false;
        w.collider = std::move(collider).value();
        w.topology = character.bodyTopology;
    }
    w.colliderTime = frame.time;
    w.twin.reset();
    if (mDesc.selfCheck) {
        auto twin = copy->clone(character);
        if (!twin.isOk()) return false;
        w.twin = std::move(twin).value();
        w.twin->context.selfCollision = copy->context.selfCollision;
    }
    w.id = item.id;
    copy->context.collider = w.collider.get();
    if (w.twin) w.twin->context.collider = w.collider.get();
    w.copy = std::move(copy);
    w.framesLeft = std::max(1, int(std::lround(mDesc.windowSeconds / frame.dt)));
    return true;
}

bool ShadowCheck::advance(Window& w, CharacterInstance& character, const ShadowFrame& frame) {
    if (Status s = character.updateSkin(); !s) return false;
    // Moved over the time between the world's clock readings, as the character's own collider
    // is (not frame.dt: the clock's sums differ from it in the last bits).
    if (!w.collider->update(character.skinnedPositions, frame.time - w.colliderTime)) return false;
    w.colliderTime = frame.time;
    if (!stepCopy(*w.copy, w.workspace, int(mDesc.substeps), character, frame)) return false;
    return !w.twin || stepCopy(*w.twin, w.workspace, std::max(1, int(mDesc.substeps) / 2), character, frame);
}

bool ShadowCheck::stepCopy(GarmentInstance& copy, cloth::SubstepWorkspace& workspace, int substeps,
                           CharacterInstance& character, const ShadowFrame& frame) {
    copy.advanceFrame();
    GarmentUpdateContext& context = copy.context;
    context.dt = frame.dt;
    context.carried = 0.0;
    context.continuous = true;
    context.proxies = false;
    setInertialForces(copy, character, frame.gravity, frame.time - copy.lastUpdateTime, frame.longestStep);

    const CookedAsset& asset = copy.asset();
    cloth::SubstepSettings settings;
    settings.method = cloth::SubstepMethod::Newton;
    settings.substeps = substeps;
    settings.iterations = int(mDesc.iterations);
    settings.strainLimit = frame.strainLimit;
    settings.contactThickness = asset.desc.thickness;
    settings.compressionStiffness = asset.desc.compressionStiffness;
    settings.friction = cloth::Friction{asset.desc.friction, 0.8 * asset.desc.friction};
    auto factor = factorFor(asset, frame.dt / double(substeps));
    if (!factor.isOk()) return false;

    GarmentUpdateReport report;
    if (!copy.prepare(character, report)) return false;
    const cloth::SubstepLane lane = copy.lane();
    cloth::SubstepLaneReport laneReport;
    const Status solved = cloth::stepSubsteps(*copy.cookedLevel().cloth, *factor.value(), frame.dt, settings,
                                              Span<const cloth::SubstepLane>(&lane, 1), workspace,
                                              Span<cloth::SubstepLaneReport>(&laneReport, 1));
    if (!solved || !laneReport.status) return false;
    if (!copy.finish(settings, report)) return false;
    copy.lastUpdateTime = frame.time;
    return true;
}

void ShadowCheck::measure(const Window& w, GarmentInstance& garment, const CharacterInstance& character,
                          const ShadowFrame& frame) {
    garment.publish(character);  // what the host would draw now
    w.copy->publish(character);
    const RenderMeshView shown = garment.renderView(), reference = w.copy->renderView();
    if (shown.vertexCount != reference.vertexCount) return;
    ShadowCheckResult r;
    r.garment = w.id;
    r.level = garment.level();
    r.referenceLevel = w.copy->level();
    r.updateInterval = uint32_t(std::max(0, garment.schedule.updateInterval));
    r.screenRadiusPx = garment.schedule.screenRadiusPx;
    r.predictedErrorPx = garment.schedule.predictedErrorPx;
    const lod::MeshDeviation metres = lod::meshDeviation(shown.positions, reference.positions, shown.vertexCount);
    r.measuredRmsMetres = metres.rmsMetres;
    r.measuredMaxMetres = metres.maxMetres;
    auto pixels = [&](const float* a, const float* b) {
        double worst = 0.0;
        for (const lod::SchedulerCamera& camera : frame.cameras)
            worst = std::max(worst, lod::meshDeviation(a, b, shown.vertexCount, &camera).maxPixels);
        return worst;
    };
    r.measuredErrorPx = pixels(shown.positions, reference.positions);
    if (w.twin) {
        w.twin->publish(character);
        r.referenceCheckPx = pixels(w.twin->renderView().positions, reference.positions);
    } else {
        r.referenceCheckPx = -1.0;
    }
    mResults.push_back(r);
}

void ShadowCheck::step(const ShadowFrame& frame, Span<const GarmentRef> items) {
    mResults.clear();
    if (!enabled()) return;
    auto find = [&](GarmentId id) -> const GarmentRef* {
        for (const GarmentRef& item : items)
            if (item.id.index1 == id.index1 && item.id.generation == id.generation) return &item;
        return nullptr;
    };
    // 1. Running windows take this frame's step; those that end are measured.
    for (Window& w : mWindows) {
        if (!w.copy) continue;
        const GarmentRef* item = find(w.id);
        if (!item || item->garment->stats.failed || !advance(w, *item->character, frame)) {
            w.copy.reset(), w.twin.reset();  // its garment went or failed, or a reference did: no result
            continue;
        }
        if (--w.framesLeft > 0) continue;
        measure(w, *item->garment, *item->character, frame);
        w.copy.reset(), w.twin.reset();
    }
    // 2. Free windows start on garments updated and seen this frame, the next handles after the
    //    last one started (round robin: every visible garment is sampled in turn).
    auto running = [&](GarmentId id) {
        return std::any_of(mWindows.begin(), mWindows.end(), [&](const Window& w) {
            return w.copy && w.id.index1 == id.index1 && w.id.generation == id.generation;
        });
    };
    auto eligible = [&](const GarmentRef& item) {
        const GarmentInstance& g = *item.garment;
        return g.stats.updated && !g.stats.failed && g.schedule.visible && !running(item.id);
    };
    for (Window& w : mWindows) {
        if (w.copy) continue;
        const GarmentRef* next = nullptr;
        for (const GarmentRef& item : items)
            if (eligible(item) && item.id.index1 > mCursor && (!next || item.id.index1 < next->id.index1)) next = &item;
        if (!next)
            for (const GarmentRef& item : items)
                if (eligible(item) && (!next || item.id.index1 < next->id.index1)) next = &item;
        if (!next) break;
        mCursor = next->id.index1;
        if (!start(w, *next, frame)) w.copy.reset(), w.twin.reset();
    }
}

} // namespace detail
} // namespace cc

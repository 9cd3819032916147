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
namespace {

/// [s] a reference runs before its first window: started from the garment's state (a coarser
/// level's, prolonged), the finest level first settles into its own folds, a transient that
/// depends on the substeps as much as anything measured after it.
constexpr double kWarmupSeconds = 0.5;

bool sameId(GarmentId a, GarmentId b) { return a.index1 == b.index1 && a.generation == b.generation; }

} // namespace

Status ShadowCheck::configure(const ShadowCheckDesc& desc) {
    if (Status s = desc.validate(); !s) return s;
    mDesc = desc;
    clear();
    mFollows.resize(desc.garments);
    return Status::ok();
}

void ShadowCheck::clear() {
    for (Follow& f : mFollows) drop(f);
    mResults.clear();
}

void ShadowCheck::drop(Follow& f) {
    f.reference.reset();
    f.copy.reset();
    f.twin.reset();
    f.windowFramesLeft = 0;
}

bool ShadowCheck::startFollowing(Follow& f, const GarmentRef& item, const ShadowFrame& frame) {
    CharacterInstance& character = *item.character;
    auto made = item.garment->clone(character);
    if (!made.isOk()) return false;
    std::unique_ptr<GarmentInstance> reference = std::move(made).value();
    reference->switchLevel(int(reference->asset().levels.size()) - 1, false);
    reference->schedule.level = reference->level();
    reference->context.selfCollision = frame.selfCollision && item.garment->schedule.selfCollision;
    // A mesh collider of its own: the character's is moved at the times its garments update,
    // which the reference must not change.
    if (Status s = character.updateSkin(); !s) return false;
    if (f.mesh && f.topology == character.bodyTopology) {
        if (!f.mesh->reset(character.skinnedPositions)) return false;
    } else {
        f.mesh.reset();
        if (!character.bodyTopology) return false;
        auto collider = collision::BodyCollider::create(*frame.device, character.bodyTopology, character.skinnedPositions);
        if (!collider.isOk()) return false;
        f.mesh = std::move(collider).value();
        f.topology = character.bodyTopology;
    }
    f.meshTime = frame.time;
    f.id = item.id;
    f.reference = std::move(reference);
    f.warmupFramesLeft = std::max(1, int(std::lround(kWarmupSeconds / frame.dt)));
    f.windowFramesLeft = 0;
    f.windowsLeft = kWindowsPerGarment;
    return true;
}

bool ShadowCheck::openWindow(Follow& f, const GarmentRef& item) {
    const GarmentInstance& garment = *item.garment;
    CharacterInstance& character = *item.character;
    const lod::GarmentSchedule& s = garment.schedule;
    Configuration& c = f.configuration;
    c.level = garment.level();
    c.substeps = std::max(1, s.substeps);
    c.iterations = std::max(1, s.iterations);
    c.continuous = s.collision == lod::CollisionDetail::MeshContinuous;
    c.proxies = s.collision == lod::CollisionDetail::Proxies && !character.body->hostSkinned;
    c.selfCollision = f.reference->context.selfCollision;
    c.predictedErrorPx = s.predictedErrorPx;
    c.screenRadiusPx = s.screenRadiusPx;
    c.updateInterval = uint32_t(std::max(0, s.updateInterval));
    for (std::unique_ptr<GarmentInstance>* slot : {&f.copy, &f.twin}) {
        auto made = f.reference->clone(character);
        if (!made.isOk()) return false;
        *slot = std::move(made).value();
    }
    f.copy->switchLevel(c.level, false);  // restricted through the cooked transfers
    f.copy->schedule.level = c.level;
    f.copy->context.selfCollision = c.selfCollision;
    f.twin->context.selfCollision = c.selfCollision;
    if (c.proxies) {
        if (!character.posedCapsules(mCapsuleScratch)) return false;
        if (!f.capsulesMade) {
            auto made = collision::CapsuleCollider::create(mCapsuleScratch);
            if (!made.isOk()) return false;
            f.capsules = std::move(made).value();
            f.capsulesMade = true;
        } else if (!f.capsules.reset(mCapsuleScratch)) {
            return false;
        }
        f.capsulesTime = f.reference->lastUpdateTime;
    }
    return true;
}

bool ShadowCheck::update(GarmentInstance& g, Follow& scratch, double dt, int substeps,
                         int iterations, const collision::Collider* collider, bool continuous,
                         CharacterInstance& character, const ShadowFrame& frame) {
    GarmentUpdateContext& context = g.context;
    context.dt = dt;
    context.carried = 0.0;
    context.collider = collider;
    context.continuous = continuous;
    context.proxies = false;
    context.strainLimit = frame.strainLimit;
    setInertialForces(g, character, frame.gravity, frame.time - g.lastUpdateTime, frame.longestStep);

    const cloth::SubstepSettings settings = g.solverSettings(substeps, iterations, frame.strainLimit);
    auto factor = frame.factors->get(g, g.level(), dt / double(substeps), frame.frame);
    if (!factor.isOk()) return false;

    GarmentUpdateReport report;
    if (!g.prepare(character, scratch.update, report)) return false;
    const cloth::SubstepLane lane = g.lane();
    cloth::SubstepLaneReport laneReport;
    const Status solved = cloth::stepSubsteps(*g.cookedLevel().cloth, *factor.value(), dt, settings,
                                              Span<const cloth::SubstepLane>(&lane, 1), scratch.workspace,
                                              Span<cloth::SubstepLaneReport>(&laneReport, 1));
    if (!solved || !laneReport.status) return false;
    if (!g.finish(character, settings, scratch.update, report)) return false;
    g.lastUpdateTime = frame.time;
    return true;
}

bool ShadowCheck::advance(Follow& f, const GarmentRef& item, const ShadowFrame& frame) {
    CharacterInstance& character = *item.character;
    if (Status s = character.updateSkin(); !s) return false;
    // Moved over the time between the world's clock readings, as the character's own collider
    // is (not frame.dt: the clock's sums differ from it in the last bits).
    if (!f.mesh->update(character.skinnedPositions, frame.time - f.meshTime)) return false;
    f.meshTime = frame.time;
    const int substeps = int(mDesc.substeps), iterations = int(mDesc.iterations);
    if (!update(*f.reference, f, frame.dt, substeps, iterations, f.mesh.get(), true, character, frame))
        return false;
    if (f.windowFramesLeft == 0) return true;
    if (!update(*f.twin, f, frame.dt, substeps / 2, iterations, f.mesh.get(), true, character, frame))
        return false;
    // The copy is updated when the garment is (every updateInterval-th frame, over the same step):
    // in between it is carried with the character, as the garment is drawn.
    const GarmentInstance& garment = *item.garment;
    if (!garment.stats.updated) return true;
    const Configuration& c = f.configuration;
    const collision::Collider* collider = f.mesh.get();
    if (c.proxies) {
        if (!character.posedCapsules(mCapsuleScratch)) return false;
        if (!f.capsules.update(mCapsuleScratch, frame.time - f.capsulesTime)) return false;
        f.capsulesTime = frame.time;
        collider = &f.capsules;
    }
    return update(*f.copy, f, garment.context.dt, c.substeps, c.iterations, collider, c.continuous,
                  character, frame);
}

void ShadowCheck::measure(Follow& f, const CharacterInstance& character, const ShadowFrame& frame) {
    f.reference->publish(character);
    f.copy->publish(character);
    f.twin->publish(character);
    const RenderMeshView reference = f.reference->renderView(), shown = f.copy->renderView();
    if (shown.vertexCount != reference.vertexCount) return;
    const Configuration& c = f.configuration;
    ShadowCheckResult r;
    r.garment = f.id;
    r.level = c.level;
    r.referenceLevel = f.reference->level();
    r.updateInterval = c.updateInterval;
    r.screenRadiusPx = c.screenRadiusPx;
    r.predictedErrorPx = c.predictedErrorPx;
    const lod::MeshDeviation metres = lod::meshDeviation(shown.positions, reference.positions, shown.vertexCount);
    r.measuredRmsMetres = metres.rmsMetres;
    r.measuredMaxMetres = metres.maxMetres;
    // On the camera that shows it worst (largest and RMS each over the cameras).
    auto pixels = [&](const float* a, double& outMax, double& outRms) {
        for (const lod::SchedulerCamera& camera : frame.cameras) {
            const lod::MeshDeviation d = lod::meshDeviation(a, reference.positions, shown.vertexCount, &camera);
            outMax = std::max(outMax, d.maxPixels);
            outRms = std::max(outRms, d.rmsPixels);
        }
    };
    pixels(shown.positions, r.measuredErrorPx, r.measuredRmsPx);
    pixels(f.twin->renderView().positions, r.referenceCheckPx, r.referenceCheckRmsPx);
    mResults.push_back(r);
}

void ShadowCheck::step(const ShadowFrame& frame, Span<const GarmentRef> items) {
    mResults.clear();
    if (!enabled()) return;
    auto find = [&](GarmentId id) -> const GarmentRef* {
        for (const GarmentRef& item : items)
            if (sameId(item.id, id)) return &item;
        return nullptr;
    };
    auto seenAndUpdated = [](const GarmentInstance& g) {
        return g.stats.updated && !g.stats.failed && g.schedule.visible;
    };
    // 1. Followed garments: the reference (and an open window) take this frame's step; a window
    //    that ends is measured; a new one opens on a frame the garment is updated and seen.
    for (Follow& f : mFollows) {
        if (!f.reference) continue;
        const GarmentRef* item = find(f.id);
        if (!item || item->garment->stats.failed || !advance(f, *item, frame)) {
            drop(f);  // its garment went or failed, or a copy did: no result
            continue;
        }
        if (f.windowFramesLeft > 0 && --f.windowFramesLeft == 0) {
            measure(f, *item->character, frame);
            f.copy.reset();
            f.twin.reset();
            if (--f.windowsLeft == 0) {
                drop(f);
                continue;
            }
        }
        if (f.warmupFramesLeft > 0) --f.warmupFramesLeft;
        if (f.warmupFramesLeft == 0 && f.windowFramesLeft == 0 && seenAndUpdated(*item->garment)) {
            if (!openWindow(f, *item)) {
                drop(f);
                continue;
            }
            f.windowFramesLeft = std::max(1, int(std::lround(mDesc.windowSeconds / frame.dt)));
        }
    }
    // 2. Free slots follow garments updated and seen this frame, the next handles after the last
    //    one followed (round robin: every visible garment is sampled in turn).
    auto followed = [&](GarmentId id) {
        return std::any_of(mFollows.begin(), mFollows.end(),
                           [&](const Follow& f) { return f.reference && sameId(f.id, id); });
    };
    auto eligible = [&](const GarmentRef& item) { return seenAndUpdated(*item.garment) && !followed(item.id); };
    for (Follow& f : mFollows) {
        if (f.reference) continue;
        const GarmentRef* next = nullptr;
        for (const GarmentRef& item : items)
            if (eligible(item) && item.id.index1 > mCursor && (!next || item.id.index1 < next->id.index1)) next = &item;
        if (!next)
            for (const GarmentRef& item : items)
                if (eligible(item) && (!next || item.id.index1 < next->id.index1)) next = &item;
        if (!next) break;
        mCursor = next->id.index1;
        if (!startFollowing(f, *next, frame)) drop(f);
    }
}

} // namespace detail
} // namespace cc

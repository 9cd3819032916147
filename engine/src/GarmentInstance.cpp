#include "GarmentInstance.h"

#include "crowdcloth/cloth/ContactResponse.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace cc::detail {
namespace {

constexpr int kMorphFrames = 8;  ///< frames over which a level switch's render difference fades

/// Targets of bound points on a host-skinned body: the barycentric point of the host's vertices
/// plus the bind offset (no skeleton, so no rotation to carry it with).
void hostTargets(const SkinBinding& binding, const CharacterInstance& character, Span<Vec3> outTargets) {
    const auto& triangles = character.body->anchorMesh.triangles;
    for (std::size_t i = 0; i < binding.size(); ++i) {
        const BoundVertex& b = binding.vertices()[i];
        Vec3 p = b.offset;
        for (int k = 0; k < 3; ++k) p += b.barycentric[k] * character.skinnedPositions[triangles[b.triangle][k]];
        outTargets[i] = p;
    }
}

Status boundTargets(const SkinBinding& binding, CharacterInstance& character, Span<Vec3> outTargets) {
    if (character.body->hostSkinned) {
        if (Status s = character.updateSkin(); !s) return s;
        hostTargets(binding, character, outTargets);
        return Status::ok();
    }
    if (Status s = character.updatePose(); !s) return s;
    return binding.evaluate(character.body->anchorMesh, character.pose.skinMatrices(), outTargets, {}, {});
}

void weldCopies(const lod::ActiveMesh& active, cloth::ClothState& state) {
    for (const auto& [a, b] : active.welds) {
        const double ma = state.masses[a], mb = state.masses[b];
        const Vec3 x = (ma * state.positions[a] + mb * state.positions[b]) / (ma + mb);
        const Vec3 v = (ma * state.velocities[a] + mb * state.velocities[b]) / (ma + mb);
        state.positions[a] = state.positions[b] = x;
        state.velocities[a] = state.velocities[b] = v;
    }
}

} // namespace

Result<std::unique_ptr<GarmentInstance>> GarmentInstance::create(std::shared_ptr<const CookedAsset> asset,
                                                                 uint32_t assetIndex, CharacterInstance& character,
                                                                 CharacterId characterId, const GarmentDesc& desc) {
    if (!(std::isfinite(desc.importance) && desc.importance > 0.0))
        return Status::invalidArgument("GarmentDesc.importance must be > 0");
    if (desc.forceLevel < -1 || desc.forceLevel >= int(asset->levels.size()))
        return Status::invalidArgument("GarmentDesc.forceLevel must be -1 or a level of the asset (0.." +
                                       std::to_string(asset->levels.size() - 1) + ")");
    std::unique_ptr<GarmentInstance> g(new GarmentInstance());
    g->mForceLevel = desc.forceLevel;
    g->mAsset = std::move(asset);
    g->mAssetIndex = assetIndex;
    g->mCharacterId = characterId;
    g->mImportance = desc.importance;
    const ClothAssetDesc& d = g->mAsset->desc;
    g->mPlacement = garmentPlacement(*character.body, d.kind, d.width, d.length, d.thickness);
    if (Status s = g->bindAttachments(character); !s) return s;

    // Start at level 0 with every vertex carried by the body point nearest to it, so a skirt put
    // on mid-stride starts around the legs where they are.
    const CookedLevel& level0 = g->mAsset->levels[0];
    std::vector<Vec3> bindPositions(level0.active.mesh.positions.size());
    for (std::size_t i = 0; i < bindPositions.size(); ++i) bindPositions[i] = level0.active.mesh.positions[i] + g->mPlacement;
    SkinBindingSettings wide;
    wide.maxBindDistance = 10.0;
    auto carried = SkinBinding::bind(character.body->anchorMesh, bindPositions, wide);
    if (!carried.isOk()) return Status::invalidArgument("addGarment: " + carried.status().message());
    std::vector<Vec3> start(bindPositions.size());
    if (character.body->hostSkinned) {
        hostTargets(carried.value(), character, start); // the latest vertices the host handed in
    } else if (Status s = boundTargets(carried.value(), character, start); !s) {
        return s;
    }

    cloth::SimulationSettings settings;
    settings.parallel.maxThreads = 1;
    auto sim = cloth::ClothSimulation::create(level0.active.mesh, g->mAsset->material, settings);
    if (!sim.isOk()) return sim.status();
    g->mSim = std::move(sim).value();
    g->mSim->state().positions = start;
    g->mLevel = 0;
    g->mRenderIndices.reserve(3 * g->mAsset->renderTriangles.size());
    for (const auto& t : g->mAsset->renderTriangles) g->mRenderIndices.insert(g->mRenderIndices.end(), t.begin(), t.end());
    g->publish(character, true);
    return g;
}

Status GarmentInstance::bindAttachments(const CharacterInstance& character) {
    const lod::GarmentHierarchy& base = mAsset->levels[0].hierarchy;
    std::vector<Vec3> bindPositions;
    for (uint32_t id : mAsset->attachedVertices) bindPositions.push_back(base.position(id) + mPlacement);
    SkinBindingSettings settings;
    settings.maxBindDistance = 1.0;
    auto binding = SkinBinding::bind(character.body->anchorMesh, bindPositions, settings);
    if (!binding.isOk()) return Status::invalidArgument("addGarment: attachment " + binding.status().message());
    mAttachments = std::move(binding).value();
    mTargets.resize(mAttachments.size());
    return Status::ok();
}

Result<bool> GarmentInstance::configure(int level, const cloth::SimulationSettings& settings) {
    const cloth::SimulationSettings& now = mSim->settings();
    if (level == mLevel && settings.integrator == now.integrator &&
        settings.implicit.maxHalvings == now.implicit.maxHalvings && settings.strainLimit == now.strainLimit)
        return false;
    const CookedLevel& from = mAsset->levels[mLevel];
    const CookedLevel& to = mAsset->levels[level];
    // What is on screen now (including any fade still running from an earlier switch).
    std::vector<Vec3> before = mLocalRender;
    if (before.empty()) localRenderPositions(before);

    lod::GarmentHierarchy h = from.hierarchy;
    if (Status s = h.readState(from.active, mSim->state().positions, mSim->state().velocities); !s) return s;
    if (Status s = h.setUniformLevel(uint32_t(level)); !s) return s;
    std::vector<Vec3> positions, velocities;
    h.writeState(to.active, positions, velocities);
    auto sim = cloth::ClothSimulation::create(to.active.mesh, mAsset->material, settings);
    if (!sim.isOk()) return sim.status();
    mSim = std::move(sim).value();
    mSim->state().positions = std::move(positions);
    mSim->state().velocities = std::move(velocities);
    mLevel = level;

    std::vector<Vec3> after;
    localRenderPositions(after);
    mMorph.resize(after.size());
    for (std::size_t r = 0; r < after.size(); ++r) mMorph[r] = before[r] - after[r];
    mMorphFramesLeft = kMorphFrames;
    return true;
}

Status GarmentInstance::update(CharacterInstance& character, const GarmentUpdateContext& ctx,
                               GarmentUpdateReport& outReport) {
    using Clock = std::chrono::steady_clock;
    outReport = {};
    if (Status s = boundTargets(mAttachments, character, mTargets); !s) return s;
    cloth::ConstraintSet& constraints = mSim->constraints();
    const CookedLevel& level = mAsset->levels[mLevel];
    for (const AttachedVertex& a : level.attached)
        if (Status s = constraints.setTarget(a.sim, mTargets[a.slot]); !s) return s;

    // Body contacts as the collision module prescribes: planes from the still cloth against the
    // body's end pose before the solve, swept and proximity corrections after it.
    collision::BodyContactSettings contactSettings;
    contactSettings.query.thickness = mAsset->desc.thickness;
    contactSettings.query.margin = mAsset->desc.thickness;
    contactSettings.continuous = ctx.continuous;
    cloth::ContactResponse response;
    response.thickness = mAsset->desc.thickness;
    response.friction = cloth::Friction{mAsset->desc.friction, 0.8 * mAsset->desc.friction};
    const collision::Collider* colliders[1] = {ctx.collider};
    const Span<const collision::Collider* const> bodies(colliders, ctx.collider ? 1 : 0);
    mStepStart = mSim->state().positions;
    auto start = Clock::now();
    constraints.clearContactPlanes();
    if (ctx.collider) {
        if (Status s = mContactStage.gather(bodies, mStepStart, mStepStart, contactSettings, mContacts); !s) return s;
        if (Status s = cloth::applyContactPlanes(mContacts, response, constraints); !s) return s;
        outReport.contacts = uint32_t(mContacts.size());
    }
    double collisionMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();

    if (Status s = mSim->step(ctx.dt); !s) return s;

    start = Clock::now();
    cloth::ClothState& state = mSim->state();
    // Self-collision first: its impulses know nothing of the body, so the body's corrections have
    // the last word and no vertex ends inside the body.
    if (ctx.selfCollision) {
        if (mSelfLevel != mLevel) {
            collision::SelfCollisionSettings selfSettings;
            selfSettings.thickness = 0.5 * mAsset->desc.thickness;
            selfSettings.ccdGap = std::min(selfSettings.ccdGap, selfSettings.thickness);
            selfSettings.parallel.maxThreads = 1;
            auto made = collision::SelfCollision::create(level.active.mesh.triangles,
                                                         uint32_t(level.active.mesh.vertexCount()), selfSettings);
            if (!made.isOk()) return made.status();
            mSelf = std::move(made).value();
            mSelfLevel = mLevel;
        }
        mSelfMasses = state.masses;
        for (const AttachedVertex& a : level.attached) mSelfMasses[a.sim] = 0.0; // driven by the body
        collision::SelfCollisionStats selfStats;
        if (Status s = mSelf.resolve(mStepStart, state.positions, mSelfMasses, selfStats); !s) return s;
        for (std::size_t v = 0; v < state.positions.size(); ++v)
            state.velocities[v] = (state.positions[v] - mStepStart[v]) / ctx.dt;
        outReport.failSafes = selfStats.failSafeActivations;
    }
    if (ctx.collider) {
        if (Status s = mContactStage.gather(bodies, mStepStart, state.positions, contactSettings, mContacts); !s)
            return s;
        if (Status s = cloth::resolveContacts(mContacts, response, constraints, state); !s) return s;
    }
    collisionMs += std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    outReport.collisionMs = collisionMs;
    weldCopies(level.active, state);
    return Status::ok();
}

void GarmentInstance::localRenderPositions(std::vector<Vec3>& out) const {
    mAsset->levels[mLevel].render.apply(mSim->state().positions, out);
}

void GarmentInstance::publish(const CharacterInstance& character, bool stateChanged) {
    // The shape in the character's frame changes only when the garment was updated (or is still
    // fading a level switch); otherwise the frame only moves it with its character.
    if (stateChanged || mMorphFramesLeft > 0 || mLocalRender.empty()) {
        localRenderPositions(mLocalRender);
        if (mMorphFramesLeft > 0) {
            const double fade = double(mMorphFramesLeft) / kMorphFrames;
            for (std::size_t r = 0; r < mLocalRender.size(); ++r) mLocalRender[r] += fade * mMorph[r];
            --mMorphFramesLeft;
        }
        mNormals.assign(mLocalRender.size(), Vec3::Zero());
        for (const auto& t : mAsset->renderTriangles) {
            const Vec3 areaNormal = (mLocalRender[t[1]] - mLocalRender[t[0]]).cross(mLocalRender[t[2]] - mLocalRender[t[0]]);
            for (uint32_t v : t) mNormals[v] += areaNormal;  // area-weighted vertex normals
        }
        for (Vec3& normal : mNormals) {
            const double len = normal.norm();
            normal = len > 0.0 ? Vec3(normal / len) : Vec3::UnitY();
        }
    }
    const Mat3 rotation = character.rotation();
    const std::size_t n = mLocalRender.size();
    mRenderPositions.resize(3 * n);
    mRenderNormals.resize(3 * n);
    for (std::size_t r = 0; r < n; ++r) {
        const Vec3 p = rotation * mLocalRender[r] + character.position;
        const Vec3 normal = rotation * mNormals[r];
        for (int k = 0; k < 3; ++k) {
            mRenderPositions[3 * r + k] = float(p[k]);
            mRenderNormals[3 * r + k] = float(normal[k]);
        }
    }
}

RenderMeshView GarmentInstance::renderView() const {
    RenderMeshView view;
    view.positions = mRenderPositions.data();
    view.normals = mRenderNormals.data();
    view.vertexCount = uint32_t(mRenderPositions.size() / 3);
    view.indices = mRenderIndices.data();
    view.triangleCount = uint32_t(mRenderIndices.size() / 3);
    return view;
}

double GarmentInstance::specificKineticEnergy() const {
    const cloth::ClothState& s = mSim->state();
    double mass = 0.0;
    for (double m : s.masses) mass += m;
    return mass > 0.0 ? s.kineticEnergy() / mass : 0.0;
}

} // namespace cc::detail

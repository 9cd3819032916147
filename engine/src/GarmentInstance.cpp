#include "GarmentInstance.h"
#include "Stopwatch.h"

#include "crowdcloth/cloth/ContactResponse.h"
#include "crowdcloth/core/Hash.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace cc::detail {
namespace {

constexpr int kCorrectionLimitPasses = 32;    ///< sweeps of the strain limit after the body's pushes
constexpr double kSurfaceFraction = 0.05;     ///< of the thickness: where the last push puts a vertex
constexpr int kUntangleRounds = 2;    ///< edges taken round the body, each with the limit after
constexpr int kAlternatingRounds = 8; ///< at most, of the limit and the surface push in turn

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

/// Keeps welded copies together after per-vertex corrections (mass-weighted, so momentum stays).
void weldCopies(const lod::ActiveMesh& active, std::vector<Vec3>& positions, std::vector<Vec3>& velocities) {
    for (const auto& [a, b] : active.welds) {
        const double ma = active.masses[a], mb = active.masses[b];
        const Vec3 x = (ma * positions[a] + mb * positions[b]) / (ma + mb);
        const Vec3 v = (ma * velocities[a] + mb * velocities[b]) / (ma + mb);
        positions[a] = positions[b] = x;
        velocities[a] = velocities[b] = v;
    }
}

} // namespace

Status GarmentInstance::setForcedLevel(int level) {
    if (level < -1 || level >= int(mAsset->levels.size()))
        return Status::invalidArgument("a forced level must be -1 or a level of the asset (0.." +
                                       std::to_string(mAsset->levels.size() - 1) + "), not " + std::to_string(level));
    mForceLevel = level;
    return Status::ok();
}

Result<std::unique_ptr<GarmentInstance>> GarmentInstance::create(std::shared_ptr<const CookedAsset> asset,
                                                                 uint32_t assetIndex, CharacterInstance& character,
                                                                 CharacterId characterId, const GarmentDesc& desc) {
    if (!(std::isfinite(desc.importance) && desc.importance > 0.0))
        return Status::invalidArgument("GarmentDesc.importance must be > 0");
    if (!(desc.inertiaScale >= 0.0 && desc.inertiaScale <= 2.0))
        return Status::invalidArgument("GarmentDesc.inertiaScale must be in [0, 2]");
    std::unique_ptr<GarmentInstance> g(new GarmentInstance());
    g->mAsset = std::move(asset);
    if (Status s = g->setForcedLevel(desc.forceLevel); !s)
        return Status::invalidArgument("GarmentDesc.forceLevel: " + s.message());
    g->mAssetIndex = assetIndex;
    g->mCharacterId = characterId;
    g->mImportance = desc.importance;
    g->mInertiaScale = desc.inertiaScale;
    g->lastRootVelocity = character.velocity;
    g->lastYawRate = character.yawRate;
    // Cooked assets are fitted to the body and placed in its rest pose (GarmentFit): mPlacement stays 0.
    if (Status s = g->bindAttachments(character); !s) return s;

    // Every buffer at the size of the finest level, so switching levels never allocates.
    std::size_t vertices = 0, attachedNodes = 0;
    for (const CookedLevel& level : g->mAsset->levels) {
        vertices = std::max(vertices, level.active.simToVertex.size());
        attachedNodes = std::max<std::size_t>(attachedNodes, level.cloth->attachedNodeCount());
    }
    for (auto* buffer : {&g->mPositions, &g->mVelocities, &g->mSwapPositions, &g->mSwapVelocities, &g->mStepStart})
        buffer->reserve(vertices);
    g->mContacts.reserve(vertices);
    g->mNodeTargets.reserve(attachedNodes);
    for (auto* buffer : {&g->mLocalRender, &g->mNormals, &g->mMorph}) buffer->reserve(g->mAsset->renderVertexCount);
    g->mLevel = 0;
    if (Status s = g->bindRestPlacement(character); !s) return Status::invalidArgument("addGarment: " + s.message());
    if (Status s = g->placeAtRest(character); !s) return s;
    g->mRenderIndices.reserve(3 * g->mAsset->renderTriangles.size());
    for (const auto& t : g->mAsset->renderTriangles) g->mRenderIndices.insert(g->mRenderIndices.end(), t.begin(), t.end());
    g->publish(character);
    return g;
}

Status GarmentInstance::bindAttachments(const CharacterInstance& character) {
    const lod::GarmentHierarchy& base = mAsset->levels[0].hierarchy;
    std::vector<Vec3> bindPositions;
    for (uint32_t id : mAsset->attachedVertices) bindPositions.push_back(base.position(id) + mPlacement);
    SkinBindingSettings settings;
    settings.maxBindDistance = 1.0;
    auto binding = bindToBody(*character.body, bindPositions, settings);
    if (!binding.isOk()) return Status::invalidArgument("addGarment: attachment " + binding.status().message());
    mAttachments = std::move(binding).value();
    mTargets.resize(mAttachments.size());
    return Status::ok();
}

void GarmentInstance::transferOneLevel(int direction) {
    const CookedLevel& from = mAsset->levels[mLevel];
    if (direction > 0) {
        from.refine.apply(mPositions, mSwapPositions);
        from.refine.apply(mVelocities, mSwapVelocities);
        ++mLevel;
    } else {
        from.coarsenPositions.apply(mPositions, mSwapPositions);
        from.coarsenVelocities.apply(mVelocities, mSwapVelocities);
        --mLevel;
    }
    mPositions.swap(mSwapPositions);
    mVelocities.swap(mSwapVelocities);
}

Status GarmentInstance::bindRestPlacement(const CharacterInstance& character) {
    // Every vertex of level 0 carried by the torso's skin nearest to it, so a skirt put on
    // mid-stride starts around the legs where they are.
    const CookedLevel& level0 = mAsset->levels[0];
    std::vector<Vec3> bindPositions(level0.active.mesh.positions.size());
    for (std::size_t i = 0; i < bindPositions.size(); ++i) bindPositions[i] = level0.active.mesh.positions[i] + mPlacement;
    SkinBindingSettings wide;
    wide.maxBindDistance = 10.0;
    auto carried = bindToBody(*character.body, bindPositions, wide);
    if (!carried.isOk()) return carried.status();
    mRestCarry = std::move(carried).value();
    return Status::ok();
}

Status GarmentInstance::placeAtRest(CharacterInstance& character) {
    // Level 0's placement refined to the current level: the same shape at every level, and a
    // binding of a few dozen vertices (binding the finest level's took 10-20 ms).
    const int level = mLevel;
    mLevel = 0;
    mPositions.resize(mRestCarry.size());
    if (character.body->hostSkinned) {
        hostTargets(mRestCarry, character, mPositions); // the latest vertices the host handed in
    } else if (Status s = boundTargets(mRestCarry, character, mPositions); !s) {
        return s;
    }
    mVelocities.assign(mPositions.size(), Vec3::Zero());
    while (mLevel < level) transferOneLevel(1);
    mReleaseLeft = meanEdgeShortening() > kReleaseShortening ? kReleaseSeconds : 0.0;
    return Status::ok();
}

bool GarmentInstance::switchLevel(int level, bool fade) {
    if (level == mLevel) return false;
    // What is on screen now (including any fade still running from an earlier switch) is kept in
    // mMorph until the new level's render positions are known.
    refreshLocalRender();
    mMorph = mLocalRender;
    while (mLevel != level) transferOneLevel(level > mLevel ? 1 : -1);
    localRenderPositions(mLocalRender);
    for (std::size_t r = 0; r < mMorph.size(); ++r) mMorph[r] -= mLocalRender[r];
    mMorphFramesLeft = fade ? kMorphFrames : 0;
    mLocalDirty = true;
    return true;
}

collision::BodyContactSettings GarmentInstance::contactSettings() const {
    collision::BodyContactSettings settings;
    settings.query.thickness = mAsset->desc.thickness;
    settings.query.margin = mAsset->desc.thickness;
    settings.query.parallel.maxThreads = 1;  // garments already run in parallel
    settings.continuous = context.continuous;
    return settings;
}

Status GarmentInstance::prepare(CharacterInstance& character, UpdateScratch& scratch, GarmentUpdateReport& outReport) {
    collision::BodyContactStage& stage = scratch.contacts;
    outReport = {};
    if (Status s = boundTargets(mAttachments, character, mTargets); !s) return s;
    const CookedLevel& level = mAsset->levels[mLevel];
    mNodeTargets.resize(level.attachedSlot.size());
    for (std::size_t k = 0; k < level.attachedSlot.size(); ++k) mNodeTargets[k] = mTargets[level.attachedSlot[k]];
    const auto start = Clock::now();
    mSettled = false;
    // (A new garment starts from its fitted placement, which the fit keeps outside the body.)
    if (context.collider && !context.proxies && mSteppedLevel >= 0 && (!mSteppedOnMesh || mLevel > mSteppedLevel)) {
        if (Status s = settleOntoMesh(character, scratch, outReport); !s) return s;
    }
    mStepStart = mPositions;
    // Contact planes from the still cloth against the body's end pose, once for the whole update
    // (the body sweeps past the cloth; the substeps move each plane along its surface velocity).
    // Each vertex looks as far as its own motion may carry it (Bridson, Fedkiw & Anderson 2002
    // test proximity over the step's motion for the same reason): a plane it never reaches costs
    // nothing in the solve, one it reaches holds it there with its neighbours.
    mContacts.clear();
    if (context.collider) {
        collision::BodyContactSettings settings = contactSettings();
        if (context.contactLookahead > 0.0) {
            mMargins.resize(mStepStart.size());
            for (std::size_t v = 0; v < mStepStart.size(); ++v) {
                const double ahead = context.contactLookahead * context.dt * mVelocities[v].norm();
                mMargins[v] = ahead > mAsset->desc.thickness ? std::min(ahead, kMaxContactReach) : mAsset->desc.thickness;
            }
            settings.query.pointMargins = mMargins;
        }
        const collision::Collider* colliders[1] = {context.collider};
        if (Status s = stage.gather(colliders, mStepStart, mStepStart, settings, mContacts); !s) return s;
    }
    // Self-contacts as planes of the same solve (separating planes of each pair that can close
    // within the update): the solve keeps its layers apart with their neighbours answering, and
    // finish()'s continuous resolve is left the rare pair the planes missed.
    if (context.selfCollision) {
        const auto selfStart = Clock::now();
        if (Status s = prepareSelfCollision(); !s) return s;
        collision::SeparatingPlaneSettings planes;
        planes.thickness = mSelf.settings().thickness;
        planes.repulsionFraction = mSelf.settings().repulsionFraction;
        planes.lookahead = std::max(context.contactLookahead, 1.0);
        planes.acceleration = context.acceleration.norm();
        planes.solverOffset = mAsset->desc.thickness;  // the batch's contactThickness
        gatherNodes(mStepStart, mSelfStart);
        gatherNodes(mVelocities, mSelfVelocities);
        const std::size_t first = mContacts.size();
        if (Status s = mSelf.separatingPlanes(mSelfStart, mSelfVelocities, context.dt, planes, mContacts); !s)
            return s;
        // A node's plane holds the node in the solve, named by its first copy.
        const auto& vertexOfNode = mAsset->levels[mLevel].cloth->vertexOfNode();
        for (std::size_t c = first; c < mContacts.size(); ++c) mContacts[c].vertex = vertexOfNode[mContacts[c].vertex];
        outReport.selfCollisionMs = msSince(selfStart);
    }
    outReport.contacts = uint32_t(mContacts.size());
    outReport.collisionMs = msSince(start);
    return Status::ok();
}

void GarmentInstance::gatherNodes(const std::vector<Vec3>& values, std::vector<Vec3>& outNodes) const {
    const auto& nodeOfVertex = mAsset->levels[mLevel].cloth->nodeOfVertex();
    outNodes.assign(mAsset->levels[mLevel].cloth->nodeCount(), Vec3::Zero());
    // A node of one vertex (most) takes its value bit for bit.
    for (std::size_t v = 0; v < values.size(); ++v) {
        if (mSelfShare[v] == 1.0) outNodes[nodeOfVertex[v]] = values[v];
        else outNodes[nodeOfVertex[v]] += mSelfShare[v] * values[v];
    }
}

Status GarmentInstance::resolveSelfCollision(GarmentUpdateReport& inOutReport, uint32_t* outMoved) {
    gatherNodes(mStepStart, mSelfStart);
    gatherNodes(mPositions, mSelfEnd);
    mSwapPositions = mSelfEnd;  // the level switch's scratch, free here
    collision::SelfCollisionStats selfStats;
    if (Status s = mSelf.resolve(mSelfStart, mSelfEnd, mSelfMasses, selfStats); !s) return s;
    inOutReport.failSafes += selfStats.failSafeActivations;
    if (outMoved) mMoved.assign(mPositions.size(), 0);
    // Every copy goes where its node went; the corrections, and the copies' joining where the
    // body's pushes parted them, are impulses.
    const auto& nodeOfVertex = mAsset->levels[mLevel].cloth->nodeOfVertex();
    for (std::size_t v = 0; v < mPositions.size(); ++v) {
        const uint32_t n = nodeOfVertex[v];
        if (!(mPositions[v] == mSelfEnd[n])) {
            mVelocities[v] += (mSelfEnd[n] - mPositions[v]) / context.dt;
            mPositions[v] = mSelfEnd[n];
        }
        if (outMoved && !(mSelfEnd[n] == mSwapPositions[n])) {
            mMoved[v] = 1;
            ++*outMoved;
        }
    }
    return Status::ok();
}

Status GarmentInstance::prepareSelfCollision() {
    if (mSelfLevel == mLevel) return Status::ok();
    const CookedLevel& level = mAsset->levels[mLevel];
    const cloth::ClothLevel& nodes = *level.cloth;
    collision::SelfCollisionSettings settings;
    settings.thickness = 0.5 * mAsset->desc.thickness;
    settings.ccdGap = std::min(settings.ccdGap, settings.thickness);
    settings.proximityPass = false;  // the solve's separating planes keep pairs apart
    settings.parallel.maxThreads = 1;
    // The surface over the nodes: a seam's copies are one point, so the two sides of a seam are
    // neighbours (not a pair kept apart, and not parted by an average after the resolve).
    std::vector<std::array<uint32_t, 3>> triangles;
    triangles.reserve(level.active.mesh.triangles.size());
    const auto& nodeOfVertex = nodes.nodeOfVertex();
    for (const auto& tri : level.active.mesh.triangles) {
        const std::array<uint32_t, 3> t{nodeOfVertex[tri[0]], nodeOfVertex[tri[1]], nodeOfVertex[tri[2]]};
        if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) triangles.push_back(t);
    }
    auto made = collision::SelfCollision::create(triangles, nodes.nodeCount(), settings);
    if (!made.isOk()) return made.status();
    mSelf = std::move(made).value();
    mSelfLevel = mLevel;
    mSelfMasses.assign(nodes.nodeCount(), 0.0);  // attached nodes are driven by the body
    for (uint32_t n = 0; n < nodes.freeNodeCount(); ++n) mSelfMasses[n] = nodes.nodeMasses()[n];
    // Each copy's weight in its node's mean: its share of the node's mass.
    std::vector<double> nodeMass(nodes.nodeCount(), 0.0);
    std::vector<uint32_t> copies(nodes.nodeCount(), 0);
    for (std::size_t v = 0; v < nodeOfVertex.size(); ++v) {
        nodeMass[nodeOfVertex[v]] += level.active.masses[v];
        ++copies[nodeOfVertex[v]];
    }
    mSelfShare.resize(nodeOfVertex.size());
    for (std::size_t v = 0; v < nodeOfVertex.size(); ++v) {
        const uint32_t n = nodeOfVertex[v];
        mSelfShare[v] = copies[n] == 1     ? 1.0
                        : nodeMass[n] > 0.0 ? level.active.masses[v] / nodeMass[n]
                                            : 1.0 / copies[n];
    }
    return Status::ok();
}

Status GarmentInstance::limitAroundMoved(const cloth::SubstepSettings& strainSettings,
                                         bool* outLimited) {
    cloth::SubstepSettings limit = strainSettings;
    limit.strainLimitPasses = std::max(limit.strainLimitPasses, kCorrectionLimitPasses);
    int passes = 0;
    Status s = cloth::limitStrain(*mAsset->levels[mLevel].cloth, context.dt, limit, lane(),
                                  mMoved, mLimitWork, &passes);
    if (outLimited)
        *outLimited = passes > 1; // a first sweep that found every edge within the limit ends it
    return s;
}

cloth::SubstepLane GarmentInstance::lane() {
    cloth::SubstepLane lane;
    lane.positions = mPositions;
    lane.velocities = mVelocities;
    lane.targets = mNodeTargets;
    lane.contacts = mContacts;
    lane.contactCapacity = mContacts.capacity();
    lane.acceleration = context.acceleration;
    lane.frameAngularVelocity = context.angularVelocity;
    lane.frameAngularAcceleration = context.angularAcceleration;
    lane.fictitiousScale = mInertiaScale;
    lane.velocityDamping =
        mAsset->desc.velocityDamping + kReleaseDamping * mReleaseLeft / kReleaseSeconds;
    return lane;
}

cloth::SubstepSettings GarmentInstance::solverSettings(int substeps, int iterations, double strainLimit) const {
    cloth::SubstepSettings settings;
    settings.method = cloth::SubstepMethod::Newton;
    settings.substeps = substeps;
    settings.iterations = iterations;
    settings.strainLimit = strainLimit;
    settings.contactThickness = mAsset->desc.thickness;
    settings.compressionStiffness = compressionStiffness();
    settings.stiffnessDamping = mAsset->desc.damping;
    settings.friction = cloth::Friction{mAsset->desc.friction, 0.8 * mAsset->desc.friction};
    return settings;
}

Status GarmentInstance::finish(CharacterInstance& character, const cloth::SubstepSettings& strainSettings,
                               UpdateScratch& scratch, GarmentUpdateReport& inOutReport) {
    collision::BodyContactStage& stage = scratch.contacts;
    const auto start = Clock::now();
    const CookedLevel& level = mAsset->levels[mLevel];
    // Against capsules (a garment small on screen) the update's contact planes are the whole
    // response; the corrections after the solve are for garments seen close, against the mesh.
    if (context.collider && !context.proxies) {
        // Each vertex reaches as far as it moved: one that the solve carried deeper into the body
        // than the thickness (squeezed between two limbs, say) is still found inside and pushed
        // out. (One reach for all, the farthest move, visited every triangle near a swinging hem
        // for every vertex, and cost more than the solve.)
        auto reachAsFarAsMoved = [&]() {
            mMargins.resize(mPositions.size());
            for (std::size_t v = 0; v < mPositions.size(); ++v)
                mMargins[v] = std::clamp((mPositions[v] - mStepStart[v]).norm(),
                                         mAsset->desc.thickness, kMaxContactReach);
        };
        reachAsFarAsMoved();
        collision::BodyContactSettings settings = contactSettings();
        settings.query.pointMargins = mMargins;
        collision::BodyContactSettings reaching = settings; // the rounds' gathers below
        reaching.continuous = false;
        const collision::Collider* colliders[1] = {context.collider};
        if (Status s = stage.gather(colliders, mStepStart, mPositions, settings, mContacts); !s) return s;
        cloth::ContactResponse response;
        response.thickness = mAsset->desc.thickness;
        response.friction = cloth::Friction{mAsset->desc.friction, 0.8 * mAsset->desc.friction};
        uint32_t corrected = 0;
        mMoved.assign(mPositions.size(), 0);
        if (Status s = cloth::resolveContacts(mContacts, response, *level.cloth, mPositions, mVelocities, &corrected,
                                              mMoved);
            !s)
            return s;
        inOutReport.bodyCorrections = corrected;
        // A push out of one part of the body can end inside another (out of the pelvis, into the
        // thigh it overlaps): one more proximity pass, which knows which part a point is in.
        settings.continuous = false;
        settings.query.pointMargins = {};
        settings.query.margin = mAsset->desc.thickness;
        auto proximityPass = [&]() -> Status {
            if (Status s = stage.gather(colliders, mPositions, mPositions, settings, mContacts); !s)
                return s;
            return cloth::resolveContacts(mContacts, response, *level.cloth, mPositions,
                                          mVelocities, nullptr, mMoved);
        };
        // The strain limit again, with the pushed vertices held where the body put them: their
        // neighbours follow instead of a lone vertex standing out of the cloth. The body has the
        // last word, but only against entering it: a vertex the limit pulled inside goes back to
        // the surface, not to the full thickness, so the cloth stretches as little as the body
        // forces (a limb driving the hem through a stride). The contacts are gathered where the
        // limit left the cloth, each vertex reaching as far as it moved in the update: the planes
        // of the last push, kept, pulled vertices that had slid along the body back onto planes
        // no longer under them, and missed those the limit pulled deeper than the thickness (the
        // humanoid suite: 713 -> 603 of 3,060 updates over the limit, vertex checks inside the
        // body 194 -> 60). When the limit moved nothing, the gather is for nothing: the cape on
        // the walking mannequin never met its limit in 480 updates, and the gather was 0.13 of its
        // 1.2 ms an update.
        auto limitThenSurface = [&]() -> Status {
            bool limited = false;
            if (Status s = limitAroundMoved(strainSettings, &limited); !s) return s;
            if (!limited) return Status::ok();
            reachAsFarAsMoved();
            if (Status s = stage.gather(colliders, mPositions, mPositions, reaching, mContacts); !s)
                return s;
            cloth::ContactResponse surface = response;
            surface.thickness = kSurfaceFraction * response.thickness;
            return cloth::resolveContacts(mContacts, surface, *level.cloth, mPositions,
                                          mVelocities);
        };
        if (corrected > 0) {
            if (Status s = proximityPass(); !s) return s;
            if (strainSettings.strainLimit > 0.0) {
                if (Status s = limitThenSurface(); !s) return s;
            }
        }
        // With self-collision on, its resolve pays for these passes' moves (the circle skirt's
        // self-collision on the walking mannequin 3.7 -> 6.5 ms an update with both, 4.9 and 6.0
        // with either): there they stay off until the resolve takes them in its stride.
        const bool stretchPasses = strainSettings.strainLimit > 0.0 && !context.selfCollision;
        const int untangleRounds = stretchPasses ? kUntangleRounds : 0;
        const int alternatingRounds = stretchPasses ? kAlternatingRounds : 0;
        // Edges left stretched across a limb go round it (their moved ends may go into another
        // part: an arm's edge round into the torso), then the pushes and the limit once more.
        for (int round = 0; round < untangleRounds; ++round) {
            uint32_t untangled = 0;
            if (Status s = untangleEdges(strainSettings, scratch, untangled); !s) return s;
            if (untangled == 0) break;
            if (Status s = proximityPass(); !s) return s;
            if (Status s = limitThenSurface(); !s) return s;
        }
        // The limit and the body's surface pull the pushed cloth different ways (over a shoulder
        // the limit's chord goes in, the push brings it out): alternating the two projections
        // brings it nearer both (the humanoid suite: 954 -> 713 of 3,060 updates over the limit
        // with 8).
        for (int round = 0; round < alternatingRounds &&
                            maxEdgeStrain() > strainSettings.strainLimit + kStrainSlack;
             ++round) {
            if (Status s = limitThenSurface(); !s) return s;
        }
    }
    // Self-collision's fail-safe last, over the whole update's motion (the solve and the body's
    // pushes): a push out of the body that drove one layer through another is caught here. Its
    // corrections are impulses (a moved vertex's velocity changes by its correction over the step);
    // the strain limit then brings the neighbours of what it moved along, and a second resolve
    // checks the limit's own moves, so the update ends free of crossings.
    if (context.selfCollision) {
        const auto selfStart = Clock::now();
        if (Status s = prepareSelfCollision(); !s) return s;
        uint32_t moved = 0;
        if (Status s = resolveSelfCollision(inOutReport, &moved); !s) return s;
        if (moved > 0 && strainSettings.strainLimit > 0.0) {
            if (Status s = limitAroundMoved(strainSettings); !s) return s;
            if (Status s = resolveSelfCollision(inOutReport, nullptr); !s) return s;
        }
        inOutReport.selfCollisionMs += msSince(selfStart);
    }
    if (mSettled) {
        if (Status s = restartIfTangled(character, scratch, inOutReport); !s) return s;
    }
    if ((context.collider && !context.proxies) || context.selfCollision) weldCopies(level.active, mPositions, mVelocities);
    inOutReport.collisionMs += msSince(start);
    const auto& masses = level.active.masses;
    double mass = 0.0, energy = 0.0;
    for (std::size_t v = 0; v < mVelocities.size(); ++v) {
        mass += masses[v];
        energy += 0.5 * masses[v] * mVelocities[v].squaredNorm();
    }
    mSpecificKineticEnergy = mass > 0.0 ? energy / mass : 0.0;
    mSteppedLevel = mLevel;
    mSteppedOnMesh = context.collider && !context.proxies;
    mReleaseLeft = std::max(0.0, mReleaseLeft - context.dt);
    mLocalDirty = true;
    return Status::ok();
}

void GarmentInstance::localRenderPositions(std::vector<Vec3>& out) const {
    mAsset->levels[mLevel].render.apply(mPositions, out);
}

void GarmentInstance::advanceFrame() {
    if (mMorphFramesLeft > 0) {
        --mMorphFramesLeft;
        mLocalDirty = true;
    }
}

void GarmentInstance::refreshLocalRender() {
    if (!mLocalDirty && !mLocalRender.empty()) return;
    localRenderPositions(mLocalRender);
    if (mMorphFramesLeft > 0) {
        const double fade = double(mMorphFramesLeft) / kMorphFrames;
        for (std::size_t r = 0; r < mLocalRender.size(); ++r) mLocalRender[r] += fade * mMorph[r];
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
    mLocalDirty = false;
    mWorldDirty = true;
}

void GarmentInstance::publish(const CharacterInstance& character) {
    refreshLocalRender();
    if (!mWorldDirty && character.position == mPublishedPosition && character.yaw == mPublishedYaw &&
        !mRenderPositions.empty())
        return;
    mPublishedPosition = character.position;
    mPublishedYaw = character.yaw;
    mWorldDirty = false;
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

double GarmentInstance::attachmentError() const {
    double worst = 0.0;
    for (const AttachedVertex& a : mAsset->levels[mLevel].attached)
        if (a.slot < mTargets.size()) worst = std::max(worst, (mPositions[a.sim] - mTargets[a.slot]).norm());
    return worst;
}

double GarmentInstance::compressionStiffness() const {
    return mAsset->desc.compressionStiffness * (1.0 - mReleaseLeft / kReleaseSeconds);
}

namespace {

/// Calls f(length / rest length) for every strain-limited edge of `level` at `positions`.
template <typename F>
void forEachEdgeRatio(const cloth::ClothLevel& level, const std::vector<Vec3>& positions, F&& f) {
    for (const cloth::LimitedEdge& e : level.limitedEdges()) {
        const Vec3& a = positions[level.vertexOfNode()[e.a]];
        const Vec3& b = positions[level.vertexOfNode()[e.b]];
        f((b - a).norm() / e.restLength);
    }
}

} // namespace

double GarmentInstance::meanEdgeShortening() const {
    const cloth::ClothLevel& level = *mAsset->levels[mLevel].cloth;
    double sum = 0.0;
    forEachEdgeRatio(level, mPositions, [&](double ratio) { sum += std::max(0.0, 1.0 - ratio); });
    return level.limitedEdges().empty() ? 0.0 : sum / double(level.limitedEdges().size());
}

double GarmentInstance::maxEdgeStrain() const {
    double worst = 0.0;
    forEachEdgeRatio(*mAsset->levels[mLevel].cloth, mPositions,
                     [&](double ratio) { worst = std::max(worst, ratio - 1.0); });
    return worst;
}

uint64_t GarmentInstance::hash() const {
    const uint64_t h = hashBytes(mPositions.data(), mPositions.size() * sizeof(Vec3));
    return hashBytes(mVelocities.data(), mVelocities.size() * sizeof(Vec3), h);
}

void setInertialForces(GarmentInstance& g, const CharacterInstance& c, const Vec3& gravity, double sinceUpdate,
                       double longestStep) {
    GarmentUpdateContext& context = g.context;
    const double h = context.dt;
    const bool resumed = sinceUpdate > longestStep * (1.0 + 1e-9);
    const Vec3 velocityChange = resumed ? Vec3::Zero() : Vec3(c.velocity - g.lastRootVelocity);
    const double yawRateChange = resumed ? 0.0 : c.yawRate - g.lastYawRate;
    const double s = g.inertiaScale();
    // Into the frame at its mean heading over the step (the velocity change turned with it).
    const double meanYaw = c.yaw - 0.5 * h * (c.yawRate - 0.5 * yawRateChange);
    const Mat3 toLocal = Eigen::AngleAxisd(-meanYaw, Vec3::UnitY()).toRotationMatrix();
    context.acceleration = toLocal * (gravity - s * velocityChange / h);
    context.angularVelocity = Vec3(0.0, c.yawRate - 0.5 * yawRateChange, 0.0);  // mean over the step
    context.angularAcceleration = Vec3(0.0, yawRateChange / h, 0.0);
    g.lastRootVelocity = c.velocity;
    g.lastYawRate = c.yawRate;
}

} // namespace cc::detail

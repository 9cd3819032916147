#pragma once

#include <memory>
#include <string>
#include <vector>

#include "CharacterInstance.h"
#include "CookedAsset.h"
#include "crowdcloth/World.h"
#include "crowdcloth/character/SkinBinding.h"
#include "crowdcloth/cloth/ClothSimulation.h"
#include "crowdcloth/collision/BodyContactStage.h"
#include "crowdcloth/collision/SelfCollision.h"
#include "crowdcloth/core/Contact.h"
#include "crowdcloth/lod/CrowdScheduler.h"

namespace cc::detail {

/// What a garment update needs from the world this frame.
struct GarmentUpdateContext {
    double dt = 0.0;                                ///< [s] time since the garment's last update
    const collision::Collider* collider = nullptr;  ///< the body at the end of the step; null = none
    bool continuous = false;                        ///< swept tests against the body (fast limbs)
    bool selfCollision = false;
};

/// What the last update did besides the solve.
struct GarmentUpdateReport {
    uint32_t contacts = 0;
    uint32_t failSafes = 0;
    double collisionMs = 0.0;  ///< [ms] contacts and self-collision
};

/// One garment on one character: its level, its simulation in the character's frame, its
/// attachment to the body and its published render mesh.
class GarmentInstance {
public:
    /// Places the asset on the character's body and starts at level 0, at rest in the body's
    /// current pose.
    static Result<std::unique_ptr<GarmentInstance>> create(std::shared_ptr<const CookedAsset> asset,
                                                           uint32_t assetIndex, CharacterInstance& character,
                                                           CharacterId characterId, const GarmentDesc& desc);

    const CookedAsset& asset() const { return *mAsset; }
    uint32_t assetIndex() const { return mAssetIndex; }
    CharacterId character() const { return mCharacterId; }
    double importance() const { return mImportance; }
    int forcedLevel() const { return mForceLevel; }
    int level() const { return mLevel; }
    const cloth::ClothSimulation& simulation() const { return *mSim; }

    lod::GarmentSchedule schedule;  ///< this frame's decision
    GarmentStats stats;
    double lastUpdateTime = 0.0;    ///< [s] world time of the last update
    std::string lastError;          ///< why the last failed update failed

    /// Moves the state to another uniform level through the 4-8 hierarchy (mass and momentum
    /// conserved) and/or to another solver; the render mesh fades out the difference so nothing
    /// pops. Returns whether anything changed.
    Result<bool> configure(int level, const cloth::SimulationSettings& settings);
    /// Where the bounding sphere's centre sits in the character's frame [m].
    Vec3 localCentre() const { return mAsset->centroid + mPlacement; }
    /// One simulation update over ctx.dt with the character's body as it is this frame.
    Status update(CharacterInstance& character, const GarmentUpdateContext& ctx, GarmentUpdateReport& outReport);
    /// Writes the world-space render mesh (positions and normals as floats); `stateChanged` says
    /// whether the simulation moved since the last publish.
    void publish(const CharacterInstance& character, bool stateChanged);

    RenderMeshView renderView() const;
    /// Kinetic energy per unit mass [J/kg]: the garment sleeps when this is tiny and unseen.
    double specificKineticEnergy() const;
    uint64_t hash() const { return mSim->stateHash(); }

private:
    GarmentInstance() = default;
    Status bindAttachments(const CharacterInstance& character);
    Status evaluateAttachments(const CharacterInstance& character, std::vector<Vec3>& outTargets) const;
    void localRenderPositions(std::vector<Vec3>& out) const;

    std::shared_ptr<const CookedAsset> mAsset;
    uint32_t mAssetIndex = 0;
    CharacterId mCharacterId{};
    double mImportance = 1.0;
    int mForceLevel = -1;
    Vec3 mPlacement = Vec3::Zero();         ///< asset space -> body bind space
    int mLevel = 0;
    std::unique_ptr<cloth::ClothSimulation> mSim;
    SkinBinding mAttachments;               ///< the asset's attachment line, bound to the body
    std::vector<Vec3> mTargets;             ///< scratch: attachment targets (character space)
    std::vector<Vec3> mMorph;               ///< render offsets left by a level switch, fading
    int mMorphFramesLeft = 0;
    std::vector<Vec3> mLocalRender;         ///< scratch
    std::vector<Vec3> mNormals;             ///< scratch
    std::vector<float> mRenderPositions, mRenderNormals;
    collision::BodyContactStage mContactStage;
    std::vector<Contact> mContacts;
    std::vector<Vec3> mStepStart;           ///< positions before the solve
    collision::SelfCollision mSelf;         ///< for the current level, made on first need
    int mSelfLevel = -1;
    std::vector<double> mSelfMasses;        ///< 0 for vertices driven by the body
    std::vector<uint32_t> mRenderIndices;
};

} // namespace cc::detail

#pragma once

#include <memory>
#include <string>
#include <vector>

#include "CharacterInstance.h"
#include "CookedAsset.h"
#include "crowdcloth/World.h"
#include "crowdcloth/character/SkinBinding.h"
#include "crowdcloth/cloth/SubstepSolver.h"
#include "crowdcloth/collision/BodyContactStage.h"
#include "crowdcloth/collision/SelfCollision.h"
#include "crowdcloth/core/Contact.h"
#include "crowdcloth/lod/CrowdScheduler.h"

namespace cc::detail {

class SnapshotReader;
class SnapshotWriter;

/// What a garment update needs from the world this frame.
struct GarmentUpdateContext {
    double dt = 0.0;                                ///< [s] the update's step: the time since the
                                                    ///< garment's last update, on the step grid
    double carried = 0.0;                           ///< [s] elapsed time the step left to the next
    const collision::Collider* collider = nullptr;  ///< the body at the end of the step; null = none
    bool continuous = false;                        ///< swept tests against the body (fast limbs)
    bool proxies = false;                           ///< the collider is capsules, not the mesh
    bool selfCollision = false;
    Vec3 acceleration = Vec3(0.0, -9.81, 0.0);      ///< [m/s^2] gravity less the root's acceleration,
                                                    ///< in the character's frame
    Vec3 angularVelocity = Vec3::Zero();            ///< [rad/s] of the character's frame, over the step
    Vec3 angularAcceleration = Vec3::Zero();        ///< [rad/s^2]
    /// How far ahead each vertex looks for the update's contact planes, in multiples of the
    /// distance its velocity carries it over the step (at least the thickness): cloth falling or
    /// swinging onto the body meets a plane inside the solve, where its neighbours respond,
    /// instead of being pushed out after it where the strain limit cannot follow. 0 = planes only
    /// within the thickness of the body.
    double contactLookahead = 2.0;
    double strainLimit = 0.1;  ///< [-] the World's, for the settle onto the body mesh (prepare())
};

/// What a garment's update borrows for the length of one call (the World pools them, about one per
/// thread): the body contacts' scratch, and the settle's (MeshSettle.cpp) for the rare update that
/// brings a state onto the body mesh. Kept with each garment, the settle's alone took 70-100 KB per
/// garment for a few updates in its life.
struct UpdateScratch {
    collision::BodyContactStage contacts;
    std::vector<Vec3> velocities;          ///< kept across the settle's moves
    std::vector<Vec3> sides;               ///< per vertex: the side of the body it is on
    std::vector<double> sideDepths;        ///< per vertex: the depth of the contact its side is from
    std::vector<Vec3> sideSums;            ///< per vertex: its neighbours' sides, summed (one sweep)
    std::vector<Vec3> directions;          ///< per vertex: its ray out of the body
    std::vector<collision::RayTrace> traces;      ///< and what it met
    std::vector<collision::RayTrace> sideTraces;  ///< the rays of the vertices inside, along their sides
    std::vector<uint32_t> vertices;        ///< the vertices a settle round moves out of the body,
    std::vector<Vec3> origins;             ///< and where they are
    std::vector<uint32_t>
        stretchedEdges; ///< untangleEdges: edges over the limit, then those through the body
    std::vector<Vec3> escapeOrigins;    ///< rays across the edges through the body,
    std::vector<Vec3> escapeDirections; ///< from the middle of each crossing
    std::vector<Vec3> nodeMoves;        ///< per node: the untangle's moves, summed
    std::vector<double> nodeMoveCounts; ///< per node: how many edges moved it
};

/// What the last update did besides the solve.
struct GarmentUpdateReport {
    uint32_t contacts = 0;         ///< contact planes of the solve, the body's and self-contacts'
    uint32_t failSafes = 0;
    uint32_t bodyCorrections = 0;  ///< vertices the body pushed out after the solve
    bool restarted = false;        ///< found tangled with the body, started again from its placement
    double collisionMs = 0.0;  ///< [ms] contacts and self-collision
    double selfCollisionMs = 0.0;  ///< [ms] of collisionMs: self-collision alone
};

/// One garment on one character: its level, its state in the character's frame (positions and
/// velocities per simulation vertex of its level, in arrays sized for the finest level at
/// creation), its attachment to the body and its published render mesh. The cooked asset holds
/// everything the levels share; a level switch moves the state through the cooked transfers and
/// allocates nothing.
///
/// An update runs in three parts so that garments of one asset and level can share the solve:
/// prepare() (targets and contact planes against the posed body), the batched stepSubsteps() on
/// lane(), finish() (position corrections against the body, self-collision).
class GarmentInstance {
public:
    static constexpr int kMorphFrames = 8;  ///< frames over which a level switch's render difference fades

    /// Places the asset on the character's body and starts at level 0, at rest in the body's
    /// current pose.
    static Result<std::unique_ptr<GarmentInstance>> create(std::shared_ptr<const CookedAsset> asset,
                                                           uint32_t assetIndex, CharacterInstance& character,
                                                           CharacterId characterId, const GarmentDesc& desc);

    const CookedAsset& asset() const { return *mAsset; }
    uint32_t assetIndex() const { return mAssetIndex; }
    CharacterId character() const { return mCharacterId; }
    double importance() const { return mImportance; }
    double inertiaScale() const { return mInertiaScale; }
    int forcedLevel() const { return mForceLevel; }
    /// -1 (scheduled) or a level of the asset.
    Status setForcedLevel(int level);
    int level() const { return mLevel; }
    const CookedLevel& cookedLevel() const { return mAsset->levels[mLevel]; }
    uint32_t vertexCount() const { return uint32_t(mPositions.size()); }
    /// Where the bounding sphere's centre sits in the character's frame [m].
    Vec3 localCentre() const { return mAsset->centroid + mPlacement; }

    lod::GarmentSchedule schedule;  ///< this frame's decision
    GarmentStats stats;
    double lastUpdateTime = 0.0;    ///< [s] world time of the last update
    Vec3 lastRootVelocity = Vec3::Zero();  ///< [m/s] the character's root velocity at the last update
    double lastYawRate = 0.0;       ///< [rad/s] and its heading's rate
    std::string lastError;          ///< why the last failed update failed
    GarmentUpdateContext context;   ///< this frame's update inputs (set before prepare())

    /// Moves the state to another uniform level through the cooked transfers (mass and momentum
    /// conserved); the render mesh fades out the difference so nothing pops (unless !fade: a copy
    /// no one watches). Returns whether the level changed.
    bool switchLevel(int level, bool fade = true);
    /// Attachment targets and contact planes for an update against the character's body as it is
    /// this frame (context set).
    Status prepare(CharacterInstance& character, UpdateScratch& scratch, GarmentUpdateReport& outReport);
    /// The solver's view of this garment for the update prepare() made ready.
    cloth::SubstepLane lane();
    /// The substep solver's settings for this garment's asset at the given effort: the World's
    /// batches and the shadow check's copies step with the same ones.
    cloth::SubstepSettings solverSettings(int substeps, int iterations, double strainLimit) const;
    /// After the solve: self-collision if asked, then (against the body mesh) the body's swept and
    /// proximity corrections and the strain limit of `strainSettings` around the vertices they
    /// pushed; after a settle, the restart of a garment the solve found tangled.
    Status finish(CharacterInstance& character, const cloth::SubstepSettings& strainSettings, UpdateScratch& scratch,
                  GarmentUpdateReport& inOutReport);
    /// Brings the world-space render mesh (positions and normals as floats) up to date: the shape
    /// in the character's frame is rebuilt only if the state changed (or a level switch is still
    /// fading), the world placement only if that or the character moved. Render meshes are built
    /// on demand (World::renderMesh): a garment nobody draws costs nothing.
    void publish(const CharacterInstance& character);
    /// One frame passed: a level switch's render difference fades by one step.
    void advanceFrame();

    RenderMeshView renderView() const;
    /// Kinetic energy per unit mass [J/kg] after the last update: the garment sleeps when this is
    /// tiny and unseen.
    double specificKineticEnergy() const { return mSpecificKineticEnergy; }
    /// Largest (length / rest length - 1) over the level's strain-limited edges.
    double maxEdgeStrain() const;
    /// The asset's compression stiffness, less while a compressed placement is released
    /// (mReleaseLeft).
    double compressionStiffness() const;
    /// [m] largest distance of an attached vertex from its target after the last update.
    double attachmentError() const;
    uint64_t hash() const;

    /// Snapshots (WorldSnapshot.cpp): the state that carries to the next frame (level, positions
    /// and velocities, a level switch's fade, schedule, stats and clocks; not the attachment
    /// targets, which each update makes anew), into a garment create() made for the same asset and
    /// character.
    void saveState(SnapshotWriter& out) const;
    Status restoreState(SnapshotReader& in);
    /// A second garment on the same character in this one's state (the shadow check's reference).
    Result<std::unique_ptr<GarmentInstance>> clone(CharacterInstance& character) const;

private:
    GarmentInstance() = default;
    static constexpr double kMaxContactReach = 0.25;  ///< [m] the farthest a contact query looks for the body
    /// Over the strain limit by more than this, an edge is stretched: the after-solve passes look
    /// at it.
    static constexpr double kStrainSlack = 0.01;
    // A compressed placement's release (mReleaseLeft): how long [s], the air's damping added at its
    // start [1/s], the mean shortening [-] that asks for it.
    static constexpr double kReleaseSeconds = 1.0;
    static constexpr double kReleaseDamping = 50.0;
    static constexpr double kReleaseShortening = 0.15;
    Status bindAttachments(const CharacterInstance& character);
    /// Mean of (1 - length / rest length) over the level's strain-limited edges, where shorter:
    /// the compression the state holds.
    double meanEdgeShortening() const;
    /// The strain limit with the vertices flagged in mMoved held (at least kCorrectionLimitPasses);
    /// `outLimited`: whether it moved any vertex.
    Status limitAroundMoved(const cloth::SubstepSettings& strainSettings,
                            bool* outLimited = nullptr);
    /// Edges over the strain limit that pass through the body with both ends outside (a limb
    /// between two vertices) move round it: their free ends go along the nearest way out of the
    /// body from the middle of the crossing, flagged in mMoved. EdgeUntangle.cpp.
    Status untangleEdges(const cloth::SubstepSettings& strainSettings, UpdateScratch& scratch,
                         uint32_t& outMoved);
    /// One level finer (+1) or coarser (-1) through the cooked transfers, positions and velocities.
    void transferOneLevel(int direction);
    /// Before an update against the body mesh when the last update was not (capsules, asleep) or
    /// was at a coarser level (not a new garment's first: its fitted placement is outside): the
    /// state goes back to the level it was stepped at and out of the mesh there, then is refined
    /// and settled again, each vertex inside leaving the body on its neighbours' side; a state
    /// still tangled with the body starts again from its placement (outReport.restarted).
    /// MeshSettle.cpp.
    Status settleOntoMesh(CharacterInstance& character, UpdateScratch& scratch, GarmentUpdateReport& outReport);
    /// After the update that followed a settle: a garment the solve stretched to twice its length
    /// was tangled with the body in a way the settle cannot see (a coarse hem between the legs,
    /// outside the body but through it), and starts again from its placement (inOutReport.restarted).
    Status restartIfTangled(CharacterInstance& character, UpdateScratch& scratch, GarmentUpdateReport& inOutReport);
    /// The strain past which a settled garment counts as tangled with the body.
    double tangledStrain() const;
    /// One level of the settle: the vertices inside the body go out (along their side where it has
    /// an exit, else to the nearest surface), the strain limit after each round, velocities kept;
    /// outStillInside counts what the last round left inside.
    Status settleLevel(UpdateScratch& scratch, uint32_t& outStillInside);
    /// scratch.sides: per vertex, the side of the body it is on (outside ones near the body, the
    /// nearest part's outward normal; inside ones, their neighbours'); zero where unknown. Reads
    /// scratch.traces' inside counts.
    Status sideNormals(UpdateScratch& scratch);
    /// mRestCarry for the character's body (create()).
    Status bindRestPlacement(const CharacterInstance& character);
    /// The fitted placement, carried by the torso's skin to the character's pose, at the current
    /// level and at rest (a new garment, and one whose state was found tangled with the body).
    Status placeAtRest(CharacterInstance& character);
    /// Makes mSelf (and mSelfMasses) for the current level if it is for another: over the solver's
    /// nodes, where a seam's or a tube's wrap's copies are one point.
    Status prepareSelfCollision();
    /// Per node, the mass-weighted mean of its vertices' `values` (the copies the body's pushes
    /// may have parted), into `outNodes`.
    void gatherNodes(const std::vector<Vec3>& values, std::vector<Vec3>& outNodes) const;
    /// mSelf's resolve from the step's start to the positions now, its corrections as impulses;
    /// with outMoved, flags the vertices it moved in mMoved and counts them. Every copy of a node
    /// ends where the node does.
    Status resolveSelfCollision(GarmentUpdateReport& inOutReport, uint32_t* outMoved);
    void localRenderPositions(std::vector<Vec3>& out) const;
    void refreshLocalRender();
    collision::BodyContactSettings contactSettings() const;

    std::shared_ptr<const CookedAsset> mAsset;
    uint32_t mAssetIndex = 0;
    CharacterId mCharacterId{};
    double mImportance = 1.0;
    double mInertiaScale = 1.0;
    int mForceLevel = -1;
    Vec3 mPlacement = Vec3::Zero();         ///< asset space -> body bind space
    int mLevel = 0;
    int mSteppedLevel = -1;       ///< the level of the last update; -1 = none yet (snapshotted)
    bool mSteppedOnMesh = false;  ///< the last update collided with the body mesh (snapshotted)
    bool mSettled = false;        ///< this update's prepare() settled the state onto the mesh
    /// [s] left of the release of a placement (snapshotted). A fitted grid too coarse for the
    /// folds its pattern needs holds the length as compression: placed at level 0, a circle
    /// skirt's or dress's edges are 25-49 % shorter than cut on average (the mannequin and the
    /// shared humanoids), a poncho's 12-17 %, an A-line skirt's or dress's 3-23 %, a cape's 3-17 %.
    /// Against compression stiffness the cloth's weight is nothing (a metre-wide strip of a circle
    /// skirt weighs 0.7 N; 30 % short at 0.1 x 5,000 N/m it pushes with 150): released at once it
    /// springs out flat in a few frames, up round the arms (CesiumMan's circle skirt ended round
    /// its chest; on the still mannequin its hem rose 19 cm at 12 m/s). A placement that holds more
    /// than kReleaseShortening is released over kReleaseSeconds: its compression stiffness rises
    /// from 0 and the air's damping falls from kReleaseDamping, both linearly; the skirt then hangs
    /// (its hem rose 7 mm, at most 2.5 m/s). A garment updated less often takes fewer updates.
    double mReleaseLeft = 0.0;
    std::vector<Vec3> mPositions, mVelocities;   ///< [m], [m/s] per simulation vertex, character frame
    std::vector<Vec3> mSwapPositions, mSwapVelocities;  ///< level-switch scratch
    SkinBinding mAttachments;               ///< the asset's attachment line, bound to the body
    SkinBinding mRestCarry;                 ///< level 0's fitted placement, bound to the torso's skin
    std::vector<Vec3> mTargets;             ///< per attachment slot (character space)
    std::vector<Vec3> mNodeTargets;         ///< per attached node of the current level
    std::vector<Vec3> mMorph;               ///< render offsets left by a level switch, fading
    int mMorphFramesLeft = 0;
    std::vector<Vec3> mLocalRender;         ///< render positions in the character's frame
    std::vector<Vec3> mNormals;
    std::vector<float> mRenderPositions, mRenderNormals;
    Vec3 mPublishedPosition = Vec3::Zero();  ///< the character root the render mesh was placed at
    double mPublishedYaw = 0.0;
    double mSpecificKineticEnergy = 0.0;    ///< [J/kg] measured after each update
    bool mLocalDirty = true;                ///< the state changed since mLocalRender was built
    bool mWorldDirty = true;                ///< mLocalRender changed since the world placement
    std::vector<Contact> mContacts;
    std::vector<uint8_t> mMoved;            ///< per vertex: pushed by the body this update
    std::vector<double> mMargins;           ///< per vertex: how far a contact query looks for the body
    cloth::SubstepWorkspace mLimitWork;     ///< the strain limit after the body's corrections
    std::vector<Vec3> mStepStart;           ///< positions before the solve
    collision::SelfCollision mSelf;         ///< for the current level's nodes, made on first need
    int mSelfLevel = -1;
    std::vector<double> mSelfMasses;        ///< per node; 0 for nodes driven by the body
    std::vector<double> mSelfShare;         ///< per vertex: its weight in its node's mean (1 alone)
    std::vector<Vec3> mSelfStart, mSelfEnd, mSelfVelocities;  ///< per node
    std::vector<uint32_t> mRenderIndices;
};

/// Garments simulate in their character's frame, which moves with the root and turns about +Y:
/// gravity less the root's acceleration, and the turning frame's Coriolis, centrifugal and Euler
/// forces (applied by the solver), act on the cloth, scaled by the garment's inertia scale. The
/// accelerations are the root velocity's change since the garment's last update over this step,
/// so a garment updated every n-th frame feels the whole change once. A garment that slept or
/// waited longer than any step was carried rigidly meanwhile: it feels no change from before.
void setInertialForces(GarmentInstance& g, const CharacterInstance& c, const Vec3& gravity, double sinceUpdate,
                       double longestStep);

} // namespace cc::detail

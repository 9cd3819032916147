#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <vector>

#include "CharacterInstance.h"
#include "CookedAsset.h"
#include "FactorCache.h"
#include "GarmentInstance.h"
#include "HandlePool.h"
#include "ShadowCheck.h"
#include "ScratchPool.h"
#include "TaskPool.h"
#include "crowdcloth/World.h"
#include "crowdcloth/collision/CollisionDevice.h"
#include "crowdcloth/lod/CostModel.h"
#include "crowdcloth/lod/CrowdScheduler.h"

namespace cc::detail {

/// The World behind the public handle (public classes hold no data, STYLE.md §2).
class WorldImpl final : public World {
public:
    static Result<WorldImpl*> create(const WorldDesc& desc);

    Result<AssetId> addClothAsset(const ClothAssetDesc& desc);
    Status setErrorTable(AssetId design, const ErrorTable& table);
    Status loadErrorTable(AssetId design, const char* directory);
    Result<BodyId> addBody(BodyAsset body);
    // Bodies and fitted garments (WorldBodies.cpp).
    Status setBodyLandmarks(BodyId id, const BodyLandmarkDesc& landmarks);
    Result<BodyLandmarkDesc> bodyLandmarks(BodyId id) const;
    Result<uint32_t> bodyClipCount(BodyId id) const;
    Result<ClothAssetDesc> garmentFit(GarmentId id) const;
    Result<const char*> bodyClipName(BodyId id, uint32_t index) const;
    Result<CharacterId> addCharacter(const CharacterDesc& desc);
    Status removeCharacter(CharacterId id);
    Status setCharacterRoot(CharacterId id, const double position[3], double yaw);
    Status setCharacterPlaybackRate(CharacterId id, double playbackRate);
    Status setCharacterSkinnedVertices(CharacterId id, const float* positions, uint32_t count, uint32_t stride);
    Result<GarmentId> addGarment(AssetId asset, CharacterId character, const GarmentDesc& desc);
    Status removeGarment(GarmentId id);
    Status setGarmentLevel(GarmentId id, int32_t forceLevel);
    Status setCameras(const CameraDesc* cameras, uint32_t count);
    Status setFrameBudget(double milliseconds);
    Status step(double dt);
    // The step in phases of concurrent tasks, for a host's job system (World.h); step() runs them.
    Status beginStep(double dt);
    uint32_t stepTaskCount() const;
    Status runStepTask(uint32_t index);
    bool nextStepPhase();
    Status endStep();
    bool stepOpen() const { return mStepPhase != StepPhase::Idle; }  ///< between beginStep and endStep
    Status setShadowCheck(const ShadowCheckDesc& desc) { return mShadow.configure(desc); }
    const std::vector<ShadowCheckResult>& shadowCheckResults() const { return mShadow.results(); }
    Result<RenderMeshView> renderMesh(GarmentId id) const;
    Result<GarmentStats> garmentStats(GarmentId id) const;
    Result<RenderMeshView> characterMesh(CharacterId id);
    const FrameStats& frameStats() const { return mFrameStats; }
    std::string statsJson() const;
    uint64_t stateHash() const;
    // Snapshots (WorldSnapshot.cpp).
    Result<std::vector<uint8_t>> saveState() const;
    Status restoreState(const void* data, std::size_t size, RestoreMode mode);

private:
    WorldImpl(const WorldDesc& desc, std::unique_ptr<collision::CollisionDevice> device);
    struct AssetRecord {
        std::shared_ptr<const CookedAsset> asset;
        std::shared_ptr<const ErrorTable> errors;  ///< its design's measured errors; null = the formula
    };
    /// Spare mesh colliders a body keeps (each holds ~1.5 MB for a 6k-triangle body): enough for
    /// the characters that move in and out of the camera's near field at once.
    static constexpr std::size_t kMaxSpareColliders = 8;
    struct BodyRecord {
        std::shared_ptr<const BodyAsset> body;
        std::shared_ptr<const collision::BodyTopology> topology;  ///< its mesh's, cooked with its first character
        /// Mesh colliders of this body that no character needs now (see recycleMeshColliders).
        std::vector<std::unique_ptr<collision::BodyCollider>> spareColliders;
    };
    /// A garment design as added: cooked per body on first use (GarmentFit), each fitted asset
    /// then an asset of its own (own levels, cost profile), shared by every wearer of that body.
    struct DesignRecord {
        ClothAssetDesc desc;
        std::vector<std::pair<std::shared_ptr<const BodyAsset>, AssetId>> fitted;
        std::shared_ptr<const ErrorTable> errors;  ///< setErrorTable's, handed to every fitted asset
    };
    /// The body's collision topology and first spare colliders, made with its first character.
    Status prepareBodyTopology(BodyRecord& body);
    /// The design's asset fitted to `body`, cooked on first use.
    Result<AssetId> fittedAsset(DesignRecord& design, const std::shared_ptr<const BodyAsset>& body);
    /// Garments stepped together: one asset, level, factor and settings; ordered by id.
    struct Batch {
        const CookedLevel* level = nullptr;
        const cloth::SubstepFactor* factor = nullptr;
        cloth::SubstepSettings settings;
        double dt = 0.0;
        std::vector<std::size_t> items;  ///< into mItems, at most cloth::kMaxSubstepLanes
        std::vector<cloth::SubstepLane> lanes;
        std::vector<cloth::SubstepLaneReport> reports;
    };

    int threadCount() const;
    /// Runs task(i) for i in [0, count) on the host's task runner or OpenMP.
    template <typename Task>
    void runTasks(std::size_t count, Task& task);
    Status scheduleFrame(double dt);
    /// Level switch, attachment targets and contact planes of one garment due this frame.
    void prepareGarment(const GarmentRef& item);
    /// One batch: the shared solve, then each garment's corrections and render mesh.
    void simulateBatch(Batch& batch);
    void fail(GarmentInstance& g, const Status& status);
    /// Mesh colliders follow the camera: idle ones go back to their body's spares; this frame's
    /// updates that need one take a spare, or keep their capsules while one is built in the
    /// Simulate phase (host-skinned bodies build theirs first thing in the Prepare phase). Serial.
    void recycleMeshColliders();
    /// A Simulate-phase task: the mesh collider a character will need from the next frame on.
    void buildMeshCollider(CharacterInstance& c);
    /// Returns a character's mesh collider to its body's spares (or frees it when they are full).
    void spareMeshCollider(CharacterInstance& c);

    WorldDesc mDesc;
    lod::CostModel mCostModel;
    std::unique_ptr<collision::CollisionDevice> mDevice;
    HandlePool<AssetRecord> mAssets;
    HandlePool<DesignRecord> mDesigns;
    HandlePool<BodyRecord> mBodies;
    HandlePool<CharacterInstance> mCharacters;
    HandlePool<GarmentInstance> mGarments;
    std::vector<lod::SchedulerCamera> mCameras;
    FrameStats mFrameStats;
    double mTime = 0.0;
    double mStepDt = 0.0;  ///< [s] the open (or last) step's dt
    ShadowCheck mShadow;
    double mBudgetScale = 1.0;  ///< closed-loop share of the nominal CPU budget (learned costs)
    /// Where an open step stands: Prepare and Simulate are phases of concurrent tasks (bodies and
    /// contacts per garment, then solver batches); the batches are formed between them, serially.
    enum class StepPhase { Idle, Prepare, Simulate, Finish };
    StepPhase mStepPhase = StepPhase::Idle;
    std::chrono::steady_clock::time_point mFrameStart, mPhaseStart;
    /// One flag per task of the open phase, set by the task as it starts: a task the host runs
    /// twice is refused, one it never runs is run by nextStepPhase (a host's bug must not leave a
    /// garment half stepped, nor step it twice).
    std::unique_ptr<std::atomic<uint8_t>[]> mTaskRan;
    uint32_t mTaskRanCapacity = 0;
    uint32_t mTasksSkipped = 0;  ///< this step's tasks the host left to nextStepPhase
    void openPhaseTasks();
    void runSkippedTasks();

    // Per-frame scratch, kept to avoid allocating in the frame loop.
    std::vector<GarmentRef> mItems;
    std::vector<lod::GarmentProfile> mProfiles;
    std::vector<uint32_t> mProfileOfAsset;  ///< asset index1 -> profile slot this frame
    std::vector<lod::GarmentRequest> mRequests;
    std::vector<lod::GarmentSchedule> mSchedules;
    lod::SchedulerWorkspace mSchedulerWork;
    std::unique_ptr<TaskPool> mPool;  ///< the frame's workers when the host hands in no task runner
    std::vector<std::size_t> mWork;          ///< items updated or seen this frame
    std::vector<std::size_t> mUpdates;       ///< items updated this frame
    std::vector<CharacterInstance*> mColliderBuilds;  ///< mesh colliders built this frame (Simulate)
    std::vector<Batch> mBatches;             ///< this frame's solver batches (storage kept)
    struct BatchKey {
        uint32_t asset;
        int level;
        double substep;  ///< [s]
        int substeps, iterations;
        double compression; ///< [-] compression stiffness (lower while a placement is released)
        std::size_t item;
    };
    std::vector<BatchKey> mBatchKeys;
    std::size_t mBatchCount = 0;
    ScratchPool<cloth::SubstepWorkspace> mWorkspaces;       ///< the batches' solver scratch, per solve
    ScratchPool<UpdateScratch> mUpdateScratch;  ///< the garments' contact and settle scratch, per call
    FactorCache mFactors;
};

} // namespace cc::detail

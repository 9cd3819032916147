#pragma once
// The shadow check (issue 14): the scheduler's predicted screen error against a measured one, in
// the crowd as it runs. A garment seen and just updated is followed: a reference copy of it runs
// at its asset's finest level under the reference effort, continuously, against colliders of its
// own. After a warm-up (the copy settles from the garment's coarser state into the finest level's
// own), windows are restarted from the reference's state (TESTPLAN point 3): one copy restricted to
// the garment's level and run as the scheduler runs the garment (effort, update interval,
// collision detail), one at the finest level at half the reference's substeps (how far the
// reference itself is resolved); at a window's end both are compared with the reference on
// screen. The copies read the character (its pose and skin, which every reader computes alike)
// and write nothing the crowd reads.

#include <memory>
#include <vector>

#include "FactorCache.h"
#include "GarmentInstance.h"
#include "crowdcloth/World.h"
#include "crowdcloth/collision/BodyCollider.h"
#include "crowdcloth/collision/CapsuleCollider.h"
#include "crowdcloth/collision/CollisionDevice.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/lod/CrowdScheduler.h"

namespace cc::detail {

/// A live garment and its character, as the World's frame lists them.
struct GarmentRef {
    GarmentId id;
    GarmentInstance* garment;
    CharacterInstance* character;
};

/// What the shadow check needs from the frame that just ended.
struct ShadowFrame {
    double time = 0.0;          ///< [s] world time at the end of the frame
    double dt = 0.0;            ///< [s] the frame's step
    double longestStep = 0.0;   ///< [s] the longest update a garment may take (inertial forces)
    Vec3 gravity = Vec3(0.0, -9.81, 0.0);
    double strainLimit = 0.1;
    bool selfCollision = false; ///< the World lets the scheduler turn it on
    collision::CollisionDevice* device = nullptr;
    FactorCache* factors = nullptr;  ///< the World's: the copies step with the crowd's factors
    uint64_t frame = 0;              ///< the World's frame counter (the cache's use marks)
    Span<const lod::SchedulerCamera> cameras;
};

class ShadowCheck {
public:
    /// Windows each followed garment gets before another garment is followed.
    static constexpr int kWindowsPerGarment = 4;

    /// New settings; running windows are dropped.
    Status configure(const ShadowCheckDesc& desc);
    bool enabled() const { return mDesc.garments > 0; }
    /// Drops every followed garment (a restore replaced them).
    void clear();
    /// After a frame: steps the references and open windows, measures the windows that end, opens
    /// windows, and starts following garments updated and seen this frame (round robin by handle).
    /// `items` are the World's garments. Serial.
    void step(const ShadowFrame& frame, Span<const GarmentRef> items);
    const std::vector<ShadowCheckResult>& results() const { return mResults; }

private:
    /// How the scheduler ran the garment when a window opened: what the window's copy repeats.
    struct Configuration {
        int level = 0;
        int substeps = 1, iterations = 1;
        bool continuous = false, proxies = false, selfCollision = false;
        double predictedErrorPx = 0.0;
        double screenRadiusPx = 0.0;
        uint32_t updateInterval = 1;
    };
    struct Follow {
        GarmentId id{};
        std::unique_ptr<GarmentInstance> reference;  ///< null = this slot follows nothing
        std::unique_ptr<GarmentInstance> copy;       ///< the window's garment as scheduled
        std::unique_ptr<GarmentInstance> twin;       ///< the window's reference at half the substeps
        Configuration configuration;
        int warmupFramesLeft = 0;
        int windowFramesLeft = 0;  ///< 0 = no window open
        int windowsLeft = 0;
        std::shared_ptr<const collision::BodyTopology> topology;  ///< of the mesh collider below
        std::unique_ptr<collision::BodyCollider> mesh;            ///< kept between garments
        double meshTime = 0.0;     ///< [s] world time of its pose
        collision::CapsuleCollider capsules;                      ///< the copy's, when it runs on them
        bool capsulesMade = false;
        double capsulesTime = 0.0;
        cloth::SubstepWorkspace workspace;         ///< scratch of the updates below
        UpdateScratch update;
    };
    void drop(Follow& f);
    bool startFollowing(Follow& f, const GarmentRef& item, const ShadowFrame& frame);
    bool openWindow(Follow& f, const GarmentRef& item);
    /// One update of `g` over `dt` at its level, `substeps` x `iterations`, against `collider`, with
    /// `scratch`'s workspace and update scratch.
    bool update(GarmentInstance& g, Follow& scratch, double dt, int substeps, int iterations,
                const collision::Collider* collider, bool continuous, CharacterInstance& character,
                const ShadowFrame& frame);
    bool advance(Follow& f, const GarmentRef& item, const ShadowFrame& frame);
    void measure(Follow& f, const CharacterInstance& character, const ShadowFrame& frame);

    ShadowCheckDesc mDesc;
    std::vector<Follow> mFollows;
    std::vector<ShadowCheckResult> mResults;
    std::vector<collision::Capsule> mCapsuleScratch;
    uint32_t mCursor = 0;  ///< handle index of the garment followed last
};

} // namespace cc::detail

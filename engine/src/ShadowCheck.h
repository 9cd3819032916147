#pragma once
// The shadow check (issue 14): the scheduler's predicted screen error against a measured one. A
// garment just updated is copied; the copy is stepped every frame at its asset's finest level
// under the reference effort, against its own mesh collider with continuous tests, for a window;
// then the garment as shown and the copy are compared on screen. The copy reads the character (its
// pose and skin, which every reader computes alike) and writes nothing the crowd reads.

#include <memory>
#include <vector>

#include "GarmentInstance.h"
#include "crowdcloth/World.h"
#include "crowdcloth/collision/BodyCollider.h"
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
    Span<const lod::SchedulerCamera> cameras;
};

class ShadowCheck {
public:
    /// New settings; running windows are dropped.
    Status configure(const ShadowCheckDesc& desc);
    bool enabled() const { return mDesc.garments > 0; }
    /// Drops running windows (a restore replaced the garments they follow).
    void clear();
    /// After a frame: steps the running windows, measures those that end, and starts windows on
    /// garments updated and seen this frame (round robin by handle). `items` are the World's
    /// garments, in handle order. Serial.
    void step(const ShadowFrame& frame, Span<const GarmentRef> items);
    const std::vector<ShadowCheckResult>& results() const { return mResults; }

private:
    struct Window {
        GarmentId id{};
        std::unique_ptr<GarmentInstance> copy;  ///< the reference
        std::unique_ptr<GarmentInstance> twin;  ///< its check: half the substeps (null without selfCheck)
        int framesLeft = 0;
        std::shared_ptr<const collision::BodyTopology> topology;  ///< of the collider below
        std::unique_ptr<collision::BodyCollider> collider;        ///< kept between windows
        double colliderTime = 0.0;  ///< [s] world time of the collider's pose
        cloth::SubstepWorkspace workspace;
    };
    /// One frame's update of a copy at `substeps` x the reference's iterations; false if it failed.
    bool stepCopy(GarmentInstance& copy, cloth::SubstepWorkspace& workspace, int substeps, CharacterInstance& character,
                  const ShadowFrame& frame);
    struct CachedFactor {
        const CookedAsset* asset;
        double substep;
        std::shared_ptr<const cloth::SubstepFactor> factor;
    };
    /// Steps a window's copies by one frame; false if one failed.
    bool advance(Window& w, CharacterInstance& character, const ShadowFrame& frame);
    bool start(Window& w, const GarmentRef& item, const ShadowFrame& frame);
    void measure(const Window& w, GarmentInstance& garment, const CharacterInstance& character,
                 const ShadowFrame& frame);
    Result<const cloth::SubstepFactor*> factorFor(const CookedAsset& asset, double substep);

    ShadowCheckDesc mDesc;
    std::vector<Window> mWindows;
    std::vector<CachedFactor> mFactors;
    std::vector<ShadowCheckResult> mResults;
    uint32_t mCursor = 0;  ///< handle index of the garment the last window started on
};

} // namespace cc::detail

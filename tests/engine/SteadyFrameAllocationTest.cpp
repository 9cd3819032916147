// A crowd in its steady state steps without touching the heap: every per-frame buffer (schedule,
// batches, contacts, solver workspaces, render meshes) is kept from frame to frame, so a frame's
// time does not include the allocator, and a long run does not fragment the host's heap.
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/WorldPtr.h"
#include "support/AllocationCounter.h"
#include "support/CrowdScenes.h"

namespace cc {
namespace {

using test::WorldPtr;

class SteadyFrame : public ::testing::TestWithParam<bool> {};

TEST_P(SteadyFrame, ACrowdStepsWithoutAllocating) {
    const bool selfCollision = GetParam();
    WorldDesc desc;
    desc.selfCollision = selfCollision;
    desc.fixedCostModel = true;
    desc.maxThreads = 1;
    // A budget that never binds and no slack to spend: every garment's level, rate and collision
    // detail then follow its screen size alone, not this machine's timing (the closed loop scales
    // the budget by measured frame times), so the run visits the same states wherever it runs.
    desc.frameBudgetMs = 1000.0;
    desc.spendSlack = false;
    WorldPtr world(World::create(desc).value());
    const AssetId cape = world->addClothAsset({}).value();
    const test::WalkingCrowd crowd = test::addWalkingCrowd(*world, cape, 8);
    const CameraDesc camera = test::cameraLookingAt(Vec3(7, 1.6, -8), Vec3(7, 1, 2));
    ASSERT_TRUE(world->setCameras(&camera, 1).isOk());
    const double dt = 1.0 / 60.0;
    auto frame = [&](int f) {
        test::walkCrowd(*world, crowd, f * dt);
        if (selfCollision) {  // a camera following the first character's back, close enough for it
            const Vec3 back = crowd.starts[0] + Vec3(0.0, 0.0, crowd.speed * f * dt);
            const CameraDesc close = test::cameraLookingAt(back + Vec3(0.3, 1.3, -1.6), back + Vec3(0, 1.2, 0));
            ASSERT_TRUE(world->setCameras(&close, 1).isOk());
        }
        ASSERT_TRUE(world->step(dt).isOk());
        for (GarmentId g : crowd.garments) ASSERT_TRUE(world->renderMesh(g).isOk());
    };
    // Warm up: every garment has been at the levels and rates it keeps (the walk is periodic).
    for (int f = 1; f <= 180; ++f) frame(f);
    // Embree's BVH builds of the bodies re-posed each frame allocate inside Embree (rebuilding at
    // low quality is faster than refitting, measured): counted apart, and bounded.
    auto own = [] { return test::allocationCount() - test::embreeAllocationCount(); };
    test::classifyEmbreeAllocations(true);
    const long before = own(), embreeBefore = test::embreeAllocationCount();
    int allocatingFrames = 0, selfCollidingUpdates = 0;
    for (int f = 181; f <= 240; ++f) {
        const long start = own();
        frame(f);
        if (own() != start) ++allocatingFrames;
        for (GarmentId g : crowd.garments) {
            const GarmentStats stats = world->garmentStats(g).value();
            selfCollidingUpdates += stats.updated && stats.selfCollision;
        }
    }
    const long allocations = own() - before, embree = test::embreeAllocationCount() - embreeBefore;
    test::classifyEmbreeAllocations(false);
    std::printf("steady frames (self-collision %s): %ld allocations over 60 frames (%d frames allocated), %ld in "
                "Embree; %d garment updates with self-collision\n",
                selfCollision ? "allowed" : "off", allocations, allocatingFrames, embree, selfCollidingUpdates);
    // With it allowed, the near garment runs it (separating planes and the continuous pass).
    if (selfCollision) {
        EXPECT_GT(selfCollidingUpdates, 0);
    }
    EXPECT_EQ(allocations, 0) << allocatingFrames << " of 60 frames allocated";
    EXPECT_LT(embree, 60 * 8 * 10) << "a few strings per body rebuilt (510 measured), not a growing pile";
}

INSTANTIATE_TEST_SUITE_P(SelfCollision, SteadyFrame, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& param) { return param.param ? "Allowed" : "Off"; });

} // namespace
} // namespace cc

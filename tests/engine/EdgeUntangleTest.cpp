// The body's limbs do not stay between the two ends of a cloth edge
// (GarmentInstance::untangleEdges): the body's contacts hold vertices, so a limb that slips between
// two of them leaves the edge stretched across it, each end pushed out on its own face. Checked
// independently of the collision module: each render edge against the posed body's triangles, brute
// force.
//
// Measured (2026-12-07, the dress on the running mannequin, 2 s at 60 Hz, its finest level, after
// the first half second): edges through the body per update, mean 72.9 without the untangle, 4.4
// with it; updates over the strain limit 77 -> 19 of 90. Over the humanoid suite
// (HumanoidGarmentTest.cpp, 40 cases): 1,414 -> 954 of 3,060 updates over the limit.
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/BodyInside.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

using test::WorldPtr;

TEST(EdgeUntangle, ARunnersLegsDoNotStayBetweenTheEndsOfItsDresssEdges) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    WorldPtr world(World::create(desc).value());
    ClothAssetDesc asset;
    asset.kind = GarmentKind::Dress;
    const AssetId cloth = world->addClothAsset(asset).value();
    CharacterDesc cd;
    cd.body = world->addMannequinBody({}).value();
    cd.clip = "run";
    const CharacterId runner = world->addCharacter(cd).value();
    GarmentDesc gd;
    gd.forceLevel = int32_t(asset.levelCount) - 1;
    const GarmentId dress = world->addGarment(cloth, runner, gd).value();

    const double dt = 1.0 / 60.0, speed = 4.6; // [m/s] the run clip's stride, in place
    constexpr int kFrames = 120, kSettle = 30, kEvery = 3;
    int updates = 0, over = 0, checks = 0, through = 0;
    for (int f = 1; f <= kFrames; ++f) {
        const double z = speed * f * dt, position[3] = {0.0, 0.0, z};
        ASSERT_TRUE(world->setCharacterRoot(runner, position, 0.0).isOk());
        const CameraDesc camera = test::cameraLookingAt(Vec3(-1.2, 1.4, z - 2.2), Vec3(0, 1.0, z));
        ASSERT_TRUE(world->setCameras(&camera, 1).isOk());
        ASSERT_TRUE(world->step(dt).isOk());
        const GarmentStats stats = world->garmentStats(dress).value();
        ASSERT_FALSE(stats.failed) << "frame " << f;
        ASSERT_TRUE(stats.updated);
        if (f <= kSettle) continue;
        ++updates;
        over += stats.maxStrain > desc.strainLimit + 0.01;
        if (f % kEvery != 0) continue;
        ++checks;
        through += test::edgesThroughBody(world->renderMesh(dress).value(),
                                          world->characterMesh(runner).value());
    }
    const double meanThrough = double(through) / checks;
    std::printf("dress on the running mannequin: %.1f render edges through the body per update "
                "(mean of %d), %d of "
                "%d updates over the strain limit\n",
                meanThrough, checks, over, updates);
    EXPECT_LT(meanThrough, 15.0) << "edges left across the legs (72.9 without the untangle)";
    EXPECT_LE(over, updates / 2) << "updates over the strain limit (77 of 90 without the untangle)";
}

} // namespace
} // namespace cc

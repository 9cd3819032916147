// Body-mesh colliders follow the camera: a character that comes near takes a spare collider of its
// body or, when none is left, keeps its capsules for a frame while one is built beside the solver
// batches. Either way its garments meet the body mesh within a few frames, and nothing fails.
#include <string>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

using test::WorldPtr;

bool meetsTheMesh(const GarmentStats& s) {
    return s.collision == CollisionKind::Mesh || s.collision == CollisionKind::MeshContinuous;
}

TEST(MeshColliders, EachCharacterTheCameraVisitsMeetsItsBodyMeshWithinAFewFrames) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    desc.frameBudgetMs = 1e3;
    WorldPtr world(World::create(desc).value());
    const AssetId cape = world->addClothAsset({}).value();
    // One body for all: more characters come near (in turn, each for less than a collider's idle
    // time) than the body has prebuilt spares, so later ones wait for a build.
    const int count = 8;
    const test::WalkingCrowd crowd = test::addWalkingCrowd(*world, cape, count, 1);
    const double dt = 1.0 / 60.0;
    const int framesPerVisit = 20;
    int frame = 0;
    for (int visit = 0; visit < count; ++visit) {
        int firstMeshFrame = -1;
        for (int k = 0; k < framesPerVisit; ++k, ++frame) {
            const double t = frame * dt;
            test::walkCrowd(*world, crowd, t);
            const Vec3 at = crowd.starts[visit] + Vec3(0.0, 1.2, crowd.speed * t);
            const CameraDesc camera = test::cameraLookingAt(at + Vec3(0.0, 0.2, 2.0), at);
            ASSERT_TRUE(world->setCameras(&camera, 1).isOk());
            ASSERT_TRUE(world->step(dt).isOk());
            const FrameStats& fs = world->frameStats();
            ASSERT_EQ(fs.failed, 0u) << "frame " << frame << ": " << world->statsJson().substr(0, 400);
            const GarmentStats s = world->garmentStats(crowd.garments[visit]).value();
            if (firstMeshFrame < 0 && s.updated && meetsTheMesh(s)) firstMeshFrame = k;
            if (firstMeshFrame >= 0 && s.updated) {
                EXPECT_TRUE(meetsTheMesh(s)) << "character " << visit << " lost its mesh at visit frame " << k;
            }
            if (firstMeshFrame < 0 && s.updated) {
                EXPECT_EQ(s.collision, CollisionKind::Proxies) << "waiting for its collider: the capsules";
            }
        }
        ASSERT_GE(firstMeshFrame, 0) << "character " << visit << " never met its body mesh";
        EXPECT_LE(firstMeshFrame, 3) << "character " << visit;
    }
}

} // namespace
} // namespace cc

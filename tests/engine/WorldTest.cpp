#include <cmath>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/CrowdScenes.h"

namespace cc {
namespace {

struct WorldDeleter {
    void operator()(World* w) const { World::destroy(w); }
};
using WorldPtr = std::unique_ptr<World, WorldDeleter>;

WorldPtr makeWorld(WorldDesc desc = {}) { return WorldPtr(World::create(desc).value()); }

TEST(World, CapeFollowsAWalkingMannequin) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    WorldPtr world = makeWorld(desc);
    const AssetId cape = world->addClothAsset({}).value();
    const auto crowd = test::addWalkingCrowd(*world, cape, 1);
    const double dt = 1.0 / 60.0;
    for (int frame = 1; frame <= 120; ++frame) {
        test::walkCrowd(*world, crowd, frame * dt);
        const Vec3 c = crowd.starts[0] + Vec3(0, 1.2, crowd.speed * frame * dt);
        const CameraDesc camera = test::cameraLookingAt(c + Vec3(-1.5, 0.3, -3.0), c);
        ASSERT_TRUE(world->setCameras(&camera, 1).isOk());
        const Status s = world->step(dt);
        ASSERT_TRUE(s.isOk()) << s.message();
        const GarmentStats stats = world->garmentStats(crowd.garments[0]).value();
        ASSERT_FALSE(stats.failed) << "frame " << frame;
    }
    const GarmentStats stats = world->garmentStats(crowd.garments[0]).value();
    std::printf("%s\n", world->statsJson().c_str());
    EXPECT_GT(stats.level, 0);
    const RenderMeshView mesh = world->renderMesh(crowd.garments[0]).value();
    ASSERT_GT(mesh.vertexCount, 0u);
    double minY = 1e9, maxY = -1e9, minZ = 1e9;
    for (uint32_t v = 0; v < mesh.vertexCount; ++v) {
        for (int k = 0; k < 3; ++k) ASSERT_TRUE(std::isfinite(mesh.positions[3 * v + k]));
        minY = std::min<double>(minY, mesh.positions[3 * v + 1]);
        maxY = std::max<double>(maxY, mesh.positions[3 * v + 1]);
        minZ = std::min<double>(minZ, mesh.positions[3 * v + 2]);
    }
    std::printf("cape y [%g, %g], min z %g, character z %g\n", minY, maxY, minZ, crowd.starts[0].z() + 2.0 * crowd.speed);
}

} // namespace
} // namespace cc

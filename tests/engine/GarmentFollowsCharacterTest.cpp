// Every garment's render mesh is where its character is, in every frame: stepped or not, seen or
// not, asleep or not, and across a teleport (the demo once showed capes and skirts standing on the
// plaza with no body inside them, left behind by garments updated every 16th frame).
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/WorldPtr.h"
#include "support/CrowdScenes.h"

namespace cc {
namespace {

using test::WorldPtr;

struct Box {
    Vec3 lo = Vec3::Constant(1e30), hi = Vec3::Constant(-1e30);
    void add(const float* p) {
        const Vec3 v(p[0], p[1], p[2]);
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    bool overlaps(const Box& o) const { return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all(); }
};

Box bounds(const RenderMeshView& mesh) {
    Box b;
    for (uint32_t v = 0; v < mesh.vertexCount; ++v) b.add(mesh.positions + 3 * v);
    return b;
}

/// Every garment's render bounds overlap its wearer's body bounds; `what` names the frame.
void expectEveryGarmentOnItsBody(World& world, const test::WalkingCrowd& crowd, const std::string& what) {
    for (std::size_t i = 0; i < crowd.garments.size(); ++i) {
        const Box garment = bounds(world.renderMesh(crowd.garments[i]).value());
        const Box body = bounds(world.characterMesh(crowd.characters[i]).value());
        const GarmentStats stats = world.garmentStats(crowd.garments[i]).value();
        ASSERT_TRUE(garment.overlaps(body)) << what << ": garment " << i << " (updated " << stats.updated
                                            << ", interval " << stats.updateInterval << ") at " << garment.lo.transpose()
                                            << " .. " << garment.hi.transpose() << ", its body at "
                                            << body.lo.transpose() << " .. " << body.hi.transpose();
    }
}

TEST(GarmentFollowsCharacter, InEveryFrameAcrossATeleportWhetherSteppedOrNot) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    WorldPtr world(World::create(desc).value());
    const AssetId cape = world->addClothAsset({}).value();
    const test::WalkingCrowd crowd = test::addWalkingCrowd(*world, cape, 8);
    // Before any step or root set: the garments are where their characters were added.
    expectEveryGarmentOnItsBody(*world, crowd, "before the first step");
    // A camera far away and looking away: garments update rarely (up to every 16th frame) or sleep.
    const CameraDesc camera = test::cameraLookingAt(Vec3(0, 50, -200), Vec3(0, 50, -400));
    ASSERT_TRUE(world->setCameras(&camera, 1).isOk());
    const double dt = 1.0 / 60.0;
    bool sawNotUpdated = false;
    Vec3 offset = Vec3::Zero();
    double yaw = 0.0;
    for (int frame = 1; frame <= 90; ++frame) {
        if (frame == 40) {  // a cut: every character jumps 100 m and turns round
            offset = Vec3(100.0, 0.0, 100.0);
            yaw = 3.14159265358979;
        }
        for (std::size_t i = 0; i < crowd.characters.size(); ++i) {
            const Vec3 p = crowd.starts[i] + offset + Vec3(0.0, 0.0, crowd.speed * frame * dt);
            const double position[3] = {p.x(), p.y(), p.z()};
            ASSERT_TRUE(world->setCharacterRoot(crowd.characters[i], position, yaw).isOk());
        }
        ASSERT_TRUE(world->step(dt).isOk());
        for (GarmentId g : crowd.garments) sawNotUpdated |= !world->garmentStats(g).value().updated;
        expectEveryGarmentOnItsBody(*world, crowd, "frame " + std::to_string(frame));
    }
    EXPECT_TRUE(sawNotUpdated) << "the test must cover garments that were not stepped";
}

} // namespace
} // namespace cc

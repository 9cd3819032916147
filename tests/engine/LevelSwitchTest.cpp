// Level switches move a garment's state through the cooked transfers: mass and momentum are kept,
// and once every level's buffers exist nothing is allocated or rebuilt (issue 9).
#include <gtest/gtest.h>

#include "CookedAsset.h"
#include "GarmentFit.h"
#include "GarmentInstance.h"
#include "support/AllocationCounter.h"

namespace cc::detail {
namespace {

struct Scene {
    std::shared_ptr<const BodyAsset> body;
    CharacterInstance character;
    std::shared_ptr<const CookedAsset> asset;
    std::unique_ptr<GarmentInstance> garment;

    explicit Scene(GarmentKind kind) : body(std::make_shared<const BodyAsset>(makeMannequinBody({}).value())) {
        character.body = body;
        character.pose = CharacterPose(body->mannequin.character);
        EXPECT_TRUE(character.updatePose().isOk());
        ClothAssetDesc desc;
        desc.kind = kind;
        asset = std::make_shared<const CookedAsset>(cookFittedGarment(desc, *body).value());  // as the World does
        garment = GarmentInstance::create(asset, 1, character, CharacterId{1, 1}, {}).value();
    }
};

TEST(LevelSwitch, AllocatesNothingOnceEveryLevelHasBeenVisited) {
    for (GarmentKind kind : {GarmentKind::Cape, GarmentKind::Skirt}) {
        Scene scene(kind);
        GarmentInstance& g = *scene.garment;
        const int finest = int(scene.asset->levels.size()) - 1;
        ASSERT_TRUE(g.switchLevel(finest));
        ASSERT_TRUE(g.switchLevel(0));
        const long before = test::allocationCount();
        for (int level : {finest, 1, 3, 0, 2, finest, 0}) {
            ASSERT_TRUE(g.switchLevel(level));
            EXPECT_EQ(g.level(), level);
            EXPECT_EQ(g.vertexCount(), scene.asset->levels[level].active.simToVertex.size());
            g.publish(scene.character);
        }
        EXPECT_EQ(test::allocationCount() - before, 0) << "kind " << int(kind);
    }
}

TEST(LevelSwitch, RefineThenCoarsenRestoresTheState) {
    // Refining interpolates new midpoints and keeps the old vertices; coarsening back drops the
    // midpoints and returns their momentum, which for a state refined from the coarse one is the
    // coarse state itself.
    Scene scene(GarmentKind::Skirt);
    GarmentInstance& g = *scene.garment;
    for (int level = 1; level < int(scene.asset->levels.size()); ++level) {
        const uint64_t coarse = g.hash();
        ASSERT_TRUE(g.switchLevel(level));
        ASSERT_TRUE(g.switchLevel(level - 1));
        EXPECT_EQ(g.hash(), coarse) << "level " << level;
        ASSERT_TRUE(g.switchLevel(level));  // go on from the finer level
    }
}

TEST(LevelSwitch, KeepsMassAndMomentum) {
    // Lumped masses sum to the cloth's mass at every level, and a switch moves momentum exactly
    // (lod's split and merge rules), whatever the velocity field.
    Scene scene(GarmentKind::Skirt);
    GarmentInstance& g = *scene.garment;
    auto momentum = [&] {
        const auto& masses = g.cookedLevel().active.masses;
        cloth::SubstepLane lane = g.lane();
        Vec3 p = Vec3::Zero();
        double m = 0.0;
        for (std::size_t v = 0; v < masses.size(); ++v) p += masses[v] * lane.velocities[v], m += masses[v];
        return std::make_pair(p, m);
    };
    // A smooth velocity field (welded copies share a position, so they get the same velocity).
    cloth::SubstepLane lane = g.lane();
    for (std::size_t v = 0; v < lane.positions.size(); ++v) {
        const Vec3& x = lane.positions[v];
        lane.velocities[v] = Vec3(0.3 + x.y(), -0.2 * x.x(), 0.5 * x.z() * x.x());
    }
    const auto [p0, m0] = momentum();
    for (int level : {1, 4, 2, 0, 3}) {
        ASSERT_TRUE(g.switchLevel(level));
        const auto [p, m] = momentum();
        EXPECT_NEAR(m, m0, 1e-12 * m0) << "level " << level;
        EXPECT_LT((p - p0).norm(), 1e-12 * p0.norm()) << "level " << level;
    }
}

} // namespace
} // namespace cc::detail

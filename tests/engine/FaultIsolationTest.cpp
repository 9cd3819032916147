// Bad input for one character (NaN or absurd roots, steps, garments) gets a clear error naming
// it and never reaches the others: their garments stay bit for bit what a clean run gives.
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/WorldPtr.h"
#include "support/CrowdScenes.h"

namespace cc {
namespace {

using test::WorldPtr;

constexpr int kCharacters = 5;
constexpr int kVictim = 2;
constexpr double kFrameDt = 1.0 / 60.0;

struct Scene {
    WorldPtr world;
    test::WalkingCrowd crowd;
    AssetId cape{};
};

/// Five walkers in capes at fixed levels (so the budget cannot couple them), seen close.
Scene makeScene() {
    WorldDesc desc;
    desc.fixedCostModel = true;
    Scene s{WorldPtr(World::create(desc).value()), {}};
    const AssetId cape = s.cape = s.world->addClothAsset({}).value();
    s.crowd = test::addWalkingCrowd(*s.world, cape, kCharacters);
    for (GarmentId& g : s.crowd.garments) {
        EXPECT_TRUE(s.world->removeGarment(g).isOk());
        GarmentDesc gd;
        gd.forceLevel = 2;
        g = s.world->addGarment(cape, s.crowd.characters[&g - s.crowd.garments.data()], gd).value();
    }
    const CameraDesc camera = test::cameraLookingAt(Vec3(3, 1.5, -6), Vec3(3, 1, 0));
    EXPECT_TRUE(s.world->setCameras(&camera, 1).isOk());
    return s;
}

std::vector<float> renderPositions(World& world, GarmentId g) {
    const RenderMeshView m = world.renderMesh(g).value();
    return std::vector<float>(m.positions, m.positions + 3 * m.vertexCount);
}

bool finite(const std::vector<float>& v) {
    for (float x : v)
        if (!std::isfinite(x)) return false;
    return true;
}

TEST(FaultIsolation, BadInputForOneCharacterIsRefusedByNameAndLeavesTheOthersBitIdentical) {
    Scene clean = makeScene(), faulty = makeScene();
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (int frame = 1; frame <= 60; ++frame) {
        test::walkCrowd(*clean.world, clean.crowd, frame * kFrameDt);
        test::walkCrowd(*faulty.world, faulty.crowd, frame * kFrameDt);
        World& w = *faulty.world;
        const CharacterId victim = faulty.crowd.characters[kVictim];
        if (frame % 10 == 3) {
            const double badPositions[][3] = {{nan, 0, 0}, {0, inf, 0}, {1e300, 0, 0}, {0, 0, -1e12}};
            for (const auto& p : badPositions) {
                const Status s = w.setCharacterRoot(victim, p, 0.0);
                EXPECT_FALSE(s.isOk()) << p[0] << " " << p[1] << " " << p[2];
                EXPECT_NE(s.message().find("setCharacterRoot"), std::string::npos) << s.message();
            }
            const double p[3] = {0, 0, 0};
            EXPECT_FALSE(w.setCharacterRoot(victim, p, nan).isOk());
            EXPECT_FALSE(w.setCharacterRoot(victim, nullptr, 0.0).isOk());
            for (double dt : {nan, -kFrameDt, 0.0, 1.0, inf}) {
                const Status s = w.step(dt);
                EXPECT_FALSE(s.isOk()) << dt;
                EXPECT_NE(s.message().find("dt"), std::string::npos) << s.message();
            }
            GarmentDesc bad;
            bad.importance = nan;
            const auto garment = w.addGarment(faulty.cape, victim, bad);
            ASSERT_FALSE(garment.isOk());
            EXPECT_NE(garment.status().message().find("importance"), std::string::npos) << garment.status().message();
            EXPECT_FALSE(w.addGarment(AssetId{}, victim, {}).isOk()) << "stale asset";
            ClothAssetDesc absurd;
            absurd.stretchStiffness = -1.0;
            const auto asset = w.addClothAsset(absurd);
            ASSERT_FALSE(asset.isOk());
            EXPECT_NE(asset.status().message().find("stretchStiffness"), std::string::npos) << asset.status().message();
        }
        ASSERT_TRUE(clean.world->step(kFrameDt).isOk());
        ASSERT_TRUE(w.step(kFrameDt).isOk());
        for (int i = 0; i < kCharacters; ++i) {
            const std::vector<float> a = renderPositions(*clean.world, clean.crowd.garments[i]);
            const std::vector<float> b = renderPositions(w, faulty.crowd.garments[i]);
            ASSERT_TRUE(finite(b)) << "garment " << i << " frame " << frame;
            ASSERT_EQ(a.size(), b.size());
            ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0)
                << "garment " << i << " differs from the clean run at frame " << frame;
        }
    }
    EXPECT_EQ(clean.world->stateHash(), faulty.world->stateHash());
}

} // namespace
} // namespace cc

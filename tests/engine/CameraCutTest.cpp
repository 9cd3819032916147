// A camera cut brings a garment seen far away (level 0 against the capsules, updated every few
// frames) to full screen (the finest level against the body mesh, every frame) in one frame. Far
// away the coarse cloth lies partly inside the body mesh, tangled with it (a cape's hem between
// the legs); close up it must not: checked independently of the solver (winding numbers over the
// posed body) and by the strain limit.
#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/BodyInside.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

using test::WorldPtr;

struct InsideCount {
    int vertices = 0;
    double deepest = 0.0;  ///< [m]
};

InsideCount insideTheBody(World& world, GarmentId garment, CharacterId character) {
    const RenderMeshView cloth = world.renderMesh(garment).value();
    const RenderMeshView body = world.characterMesh(character).value();
    InsideCount count;
    for (uint32_t v = 0; v < cloth.vertexCount; ++v) {
        const Vec3 p = test::vertexOf(cloth.positions, v);
        if (test::windingNumber(body, p) < 0.5) continue;
        ++count.vertices;
        count.deepest = std::max(count.deepest, test::distanceToSurface(body, p));
    }
    return count;
}

struct CutResult {
    InsideCount before, after;  ///< far away at the cut; the most after it
    double worstStrain = 0.0;   ///< after the cut
    int restarts = 0;
};

/// A garment on the walking mannequin seen from 40 m for 3 s, then close up for 1 s. `finest`:
/// forced to its finest level throughout (only the collision changes at the cut), else the level
/// the tolerance needs (level 0 far away, with no slack spent).
CutResult runCut(GarmentKind kind, bool finest) {
    constexpr int kCut = 180, kAfter = 60;  // [frames]
    CutResult r;
    WorldDesc desc;
    desc.fixedCostModel = true;
    desc.spendSlack = false;  // far away, the level the tolerance needs: a crowd has no slack
    WorldPtr world(World::create(desc).value());
    ClothAssetDesc asset;
    asset.kind = kind;
    const AssetId assetId = world->addClothAsset(asset).value();
    CharacterDesc cd;
    cd.body = world->addMannequinBody({}).value();
    cd.clip = "walk";
    const CharacterId character = world->addCharacter(cd).value();
    GarmentDesc gd;
    if (finest) gd.forceLevel = int(asset.levelCount) - 1;
    const GarmentId garment = world->addGarment(assetId, character, gd).value();
    const double dt = 1.0 / 60.0, speed = 1.35;
    for (int f = 1; f <= kCut + kAfter; ++f) {
        const double z = speed * f * dt, position[3] = {0.0, 0.0, z};
        EXPECT_TRUE(world->setCharacterRoot(character, position, 0.0).isOk());
        const bool close = f > kCut;
        const CameraDesc camera = close ? test::cameraLookingAt(Vec3(-1.2, 1.4, z - 2.2), Vec3(0, 1.0, z))
                                        : test::cameraLookingAt(Vec3(-40, 6, z - 40), Vec3(0, 1.0, z));
        EXPECT_TRUE(world->setCameras(&camera, 1).isOk());
        EXPECT_TRUE(world->step(dt).isOk());
        const GarmentStats stats = world->garmentStats(garment).value();
        EXPECT_FALSE(stats.failed) << test::kindName(kind) << " frame " << f;
        if (f == kCut) {
            EXPECT_EQ(stats.level, finest ? int(asset.levelCount) - 1 : 0);
            EXPECT_EQ(stats.collision, CollisionKind::Proxies) << "far away: the capsules";
            r.before = insideTheBody(*world, garment, character);
        }
        if (!close) continue;
        EXPECT_EQ(stats.level, int(asset.levelCount) - 1) << "close up: the finest level";
        EXPECT_TRUE(stats.updated && stats.collision >= CollisionKind::Mesh);
        r.restarts += stats.restarted;
        r.worstStrain = std::max(r.worstStrain, stats.maxStrain);
        if (f == kCut + 1 || f % 10 == 0) {
            const InsideCount now = insideTheBody(*world, garment, character);
            r.after.vertices = std::max(r.after.vertices, now.vertices);
            r.after.deepest = std::max(r.after.deepest, now.deepest);
        }
    }
    std::printf("%s%s: far away %d render vertices inside the body (deepest %.0f mm); after the cut at most %d "
                "(deepest %.1f mm), %d restart(s), max strain %.1f %%\n",
                test::kindName(kind), finest ? " (finest level)" : "", r.before.vertices, 1e3 * r.before.deepest,
                r.after.vertices, 1e3 * r.after.deepest, r.restarts, 100.0 * r.worstStrain);
    return r;
}

const double kThickness = ClothAssetDesc{}.thickness;
/// What a garment's walk close up reaches anyway: the dress (hung under the arms, which swing
/// into its sides) 45-58 % from its start; the rest stay within 30 %.
constexpr double kStrainBound = 0.6;

TEST(CameraCut, FromLevelZeroTheTangledGarmentStartsAgainOutsideTheBody) {
    for (GarmentKind kind : test::kGarmentKinds) {
        const CutResult r = runCut(kind, false);
        // What makes the case: far away level 0 lies inside the body (measured: 57-334 of 312-572
        // render vertices, 68-95 mm deep), tangled with it beyond what a settle undoes.
        EXPECT_GT(r.before.vertices, 10) << test::kindName(kind);
        EXPECT_LE(r.restarts, 1) << test::kindName(kind) << ": started again at most once, at the cut";
        EXPECT_LE(r.after.deepest, kThickness) << test::kindName(kind);
        // Measured: cape 6.5 % and poncho 19 % (both started again), skirt 3.0 % (started again),
        // dress 47 % (settled; its walk close up from the start reaches 45-58 %); without the
        // settle 430, 120, 190 and 300 %, for seconds.
        EXPECT_LE(r.worstStrain, kStrainBound) << test::kindName(kind);
    }
}

TEST(CameraCut, FromTheCapsulesAtTheFinestLevelTheGarmentSettlesOntoTheMesh) {
    // Only the collision changes at the cut: what the capsules let into the mesh (they are not the
    // mesh) is settled out, and the garment goes on where it was.
    for (GarmentKind kind : test::kGarmentKinds) {
        const CutResult r = runCut(kind, true);
        EXPECT_EQ(r.restarts, 0) << test::kindName(kind);
        EXPECT_LE(r.after.deepest, kThickness) << test::kindName(kind);
        EXPECT_LE(r.worstStrain, kStrainBound) << test::kindName(kind);
    }
}

} // namespace
} // namespace cc

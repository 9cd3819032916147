// A camera cut brings a garment seen far away (level 0 against the capsules, updated every few
// frames) to full screen (the finest level against the body mesh, every frame) in one frame. Far
// away the coarse cloth lies partly inside the body mesh, tangled with it (a cape's hem between
// the legs); close up it must not: checked independently of the solver (winding numbers over the
// posed body) and by the strain limit. A garment refined on the mesh (a camera coming nearer) goes
// on from where it was instead of starting again from its placement.
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

/// One garment of `kind` on the walking mannequin (fixed costs), at `forceLevel` (-1: the level
/// the scheduler gives it).
struct WalkScene {
    WorldPtr world;
    CharacterId character;
    GarmentId garment;
};

WalkScene walkScene(GarmentKind kind, int forceLevel, bool spendSlack) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    desc.spendSlack = spendSlack;
    WalkScene scene{WorldPtr(World::create(desc).value()), {}, {}};
    ClothAssetDesc asset;
    asset.kind = kind;
    const AssetId assetId = scene.world->addClothAsset(asset).value();
    CharacterDesc cd;
    cd.body = scene.world->addMannequinBody({}).value();
    cd.clip = "walk";
    scene.character = scene.world->addCharacter(cd).value();
    GarmentDesc gd;
    gd.forceLevel = forceLevel;
    scene.garment = scene.world->addGarment(assetId, scene.character, gd).value();
    return scene;
}

/// A garment on the walking mannequin seen from 40 m for 3 s, then close up for 1 s. `finest`:
/// forced to its finest level throughout (only the collision changes at the cut), else the level
/// the tolerance needs (level 0 far away, with no slack spent).
CutResult runCut(GarmentKind kind, bool finest) {
    constexpr int kCut = 180, kAfter = 60; // [frames]
    CutResult r;
    // Far away, the level the tolerance needs (no slack spent: a crowd has none).
    WalkScene scene = walkScene(kind, finest ? int(ClothAssetDesc{}.levelCount) - 1 : -1, false);
    World* world = scene.world.get();
    const CharacterId character = scene.character;
    const GarmentId garment = scene.garment;
    const ClothAssetDesc asset{};
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

/// A garment on the walking mannequin stepped against the mesh one level below its finest, then,
/// from frame `refine` on, at the finest (a camera coming nearer): restarts and the worst strain
/// over the second after.
struct RefineResult {
    int restarts = 0;
    double worstStrain = 0.0;
};

RefineResult runRefine(GarmentKind kind, int refine) {
    WalkScene scene = walkScene(kind, int(ClothAssetDesc{}.levelCount) - 2, true);
    World* world = scene.world.get();
    const CharacterId character = scene.character;
    const GarmentId garment = scene.garment;
    const ClothAssetDesc asset{};
    const double dt = 1.0 / 60.0, speed = 1.35;
    RefineResult r;
    for (int f = 1; f <= refine + 60; ++f) {
        if (f == refine) {
            EXPECT_TRUE(world->setGarmentLevel(garment, int(asset.levelCount) - 1).isOk());
        }
        const double z = speed * f * dt, position[3] = {0.0, 0.0, z};
        EXPECT_TRUE(world->setCharacterRoot(character, position, 0.0).isOk());
        const CameraDesc camera = test::cameraLookingAt(Vec3(-1.2, 1.4, z - 2.2), Vec3(0, 1.0, z));
        EXPECT_TRUE(world->setCameras(&camera, 1).isOk());
        EXPECT_TRUE(world->step(dt).isOk());
        const GarmentStats stats = world->garmentStats(garment).value();
        EXPECT_FALSE(stats.failed) << test::kindName(kind) << " frame " << f;
        EXPECT_GE(stats.collision, CollisionKind::Mesh) << "close up: the body mesh";
        if (f < refine) continue;
        r.restarts += stats.restarted;
        r.worstStrain = std::max(r.worstStrain, stats.maxStrain);
    }
    return r;
}

TEST(CameraCut, RefinedOnTheMeshTheGarmentGoesOnWhereItWas) {
    // Refined on the mesh, a garment's settle leaves the strain of its pushes (capes 31-58 %),
    // which the next solve's limit takes back; judged a tangle at three times the limit, a cape
    // went back to its flat placement after 4 of these 8 refines (and after half of 16 in steps of
    // 8 frames).
    const double limit = WorldDesc{}.strainLimit;
    for (GarmentKind kind : test::kGarmentKinds) {
        int restarts = 0;
        double worst = 0.0;
        for (int refine = 40; refine <= 152; refine += 16) {
            const RefineResult r = runRefine(kind, refine);
            restarts += r.restarts;
            worst = std::max(worst, r.worstStrain);
        }
        std::printf("%s refined on the mesh at 8 moments of a walk: %d restart(s), max strain over "
                    "the second "
                    "after %.0f %%\n",
                    test::kindName(kind), restarts, 100.0 * worst);
        if (kind == GarmentKind::Cape || kind == GarmentKind::Skirt) {
            EXPECT_EQ(restarts, 0) << test::kindName(kind);
            EXPECT_LE(worst, limit + 0.01)
                << test::kindName(kind) << ": back within the strain limit";
        } else {
            // The dress and the poncho can be caught round the arms: measured 1 and 2 restarts (2
            // and 2 before), from vertices the settle left inside or the strain after the solve.
            EXPECT_LE(restarts, 5) << test::kindName(kind);
        }
    }
}

} // namespace
} // namespace cc

// Self-collision through the World (issue 10): garments that fold onto themselves on a walking
// mannequin, at their finest level and seen close, with self-collision on. Checked independently
// of the solver by an exact count of intersecting triangle pairs of the simulated surface, and
// its cost against the garment's own solve.
#include <algorithm>
#include <cstdio>
#include <map>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "self_collision/TriangleIntersections.h"
#include "support/BodyInside.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

using test::WorldPtr;

/// The render mesh with welded copies (seams, a tube's wrap) merged into one vertex: copies lie on
/// each other, and the exact count would read the triangles beside a seam as touching.
void weldedSurface(const RenderMeshView& mesh, std::vector<Vec3>& outPositions,
                   std::vector<std::array<uint32_t, 3>>& outTriangles) {
    std::map<std::array<float, 3>, uint32_t> index;
    std::vector<uint32_t> remap(mesh.vertexCount);
    outPositions.clear();
    for (uint32_t v = 0; v < mesh.vertexCount; ++v) {
        const std::array<float, 3> key{mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
        auto [it, added] = index.emplace(key, uint32_t(outPositions.size()));
        if (added) outPositions.push_back(Vec3(key[0], key[1], key[2]));
        remap[v] = it->second;
    }
    outTriangles.clear();
    for (uint32_t t = 0; t < mesh.triangleCount; ++t) {
        const std::array<uint32_t, 3> tri{remap[mesh.indices[3 * t]], remap[mesh.indices[3 * t + 1]],
                                          remap[mesh.indices[3 * t + 2]]};
        if (tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2]) outTriangles.push_back(tri);
    }
}

struct SelfRun {
    int frames = 0, selfFrames = 0, worstIntersecting = 0, framesIntersecting = 0, failSafeFrames = 0;
    double maxStrain = 0.0, solveMs = 0.0, collisionMs = 0.0, selfMs = 0.0;
    double deepest = 0.0;  ///< [m] deepest garment vertex inside the posed body, after 0.5 s
};

/// `seconds` of a walk at 60 Hz, the garment at its finest level, the camera 1.3 m away.
SelfRun walk(const ClothAssetDesc& asset, bool selfCollision, double seconds) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    desc.selfCollision = selfCollision;
    WorldPtr world(World::create(desc).value());
    const auto crowd = test::addWalkingCrowd(*world, world->addClothAsset(asset).value(), 1, 1);
    const GarmentId garment = crowd.garments[0];
    EXPECT_TRUE(world->setGarmentLevel(garment, int32_t(asset.levelCount) - 1).isOk());
    SelfRun run;
    std::vector<Vec3> positions;
    std::vector<std::array<uint32_t, 3>> triangles;
    const double dt = 1.0 / 60;
    for (int frame = 1; frame <= int(seconds / dt); ++frame) {
        test::walkCrowd(*world, crowd, frame * dt);
        const Vec3 root = crowd.starts[0] + Vec3(0, 0, crowd.speed * frame * dt);
        const CameraDesc camera = test::cameraLookingAt(root + Vec3(-0.6, 1.0, 1.1), root + Vec3(0, 0.8, 0));
        EXPECT_TRUE(world->setCameras(&camera, 1).isOk());
        const Status stepped = world->step(dt);
        EXPECT_TRUE(stepped.isOk()) << stepped.message();
        const GarmentStats stats = world->garmentStats(garment).value();
        EXPECT_FALSE(stats.failed) << "frame " << frame;
        if (stats.failed || !stepped.isOk()) break;
        ++run.frames;
        run.selfFrames += stats.selfCollision && stats.updated;
        run.maxStrain = std::max(run.maxStrain, stats.maxStrain);
        run.failSafeFrames += stats.failSafes > 0;
        run.collisionMs += stats.collisionMs;
        run.selfMs += stats.selfCollisionMs;
        EXPECT_LE(stats.selfCollisionMs, stats.collisionMs) << "frame " << frame << ": a part of the contacts' time";
        EXPECT_EQ(stats.selfCollisionMs > 0.0, stats.selfCollision && stats.updated) << "frame " << frame;
        run.solveMs += stats.measuredMs - stats.collisionMs;
        weldedSurface(world->renderMesh(garment).value(), positions, triangles);
        const int crossing = test::countIntersectingPairs(positions, triangles);
        run.worstIntersecting = std::max(run.worstIntersecting, crossing);
        run.framesIntersecting += crossing > 0;
        if (frame < 30 || frame % 12 != 0) continue;  // after half a second, five times a second
        const RenderMeshView posed = world->characterMesh(crowd.characters[0]).value();
        for (const Vec3& p : positions)
            if (test::windingNumber(posed, p) >= 0.5) run.deepest = std::max(run.deepest, test::distanceToSurface(posed, p));
    }
    return run;
}

void print(const char* name, const SelfRun& r) {
    std::printf("[ self-collision in the World: %s ] %d frames (%d with self-collision), intersecting pairs: worst %d, "
                "in %d frames; impact zones in %d frames; max strain %.1f %%; deepest inside the body %.1f mm; per frame: solve %.2f ms, contacts and self-collision %.2f ms (self-collision %.2f)\n",
                name, r.frames, r.selfFrames, r.worstIntersecting, r.framesIntersecting, r.failSafeFrames, 100 * r.maxStrain, 1e3 * r.deepest,
                r.solveMs / std::max(1, r.frames), r.collisionMs / std::max(1, r.frames), r.selfMs / std::max(1, r.frames));
}

struct SelfCollisionCase {
    const char* name;
    GarmentKind kind;
    GarmentCut cut;
};

void PrintTo(const SelfCollisionCase& c, std::ostream* os) { *os << c.name; }

class SelfCollisionInTheWorld : public ::testing::TestWithParam<SelfCollisionCase> {};

TEST_P(SelfCollisionInTheWorld, AFoldingGarmentStaysFreeOfSelfIntersections) {
    ClothAssetDesc asset;
    asset.kind = GetParam().kind;
    asset.cut = GetParam().cut;
    const double seconds = 2.0;
    const SelfRun off = walk(asset, false, seconds);
    const SelfRun on = walk(asset, true, seconds);
    print((std::string(GetParam().name) + ", off").c_str(), off);
    print((std::string(GetParam().name) + ", on").c_str(), on);
    ASSERT_EQ(on.frames, int(seconds * 60));
    EXPECT_EQ(on.selfFrames, on.frames) << "a forced finest level seen close keeps self-collision on";
    EXPECT_EQ(on.worstIntersecting, 0);
    EXPECT_LT(on.maxStrain, std::max(0.5, 1.5 * off.maxStrain)) << "no blow-up";
    // The continuous pass comes after the body's pushes, so the body no longer has the last word:
    // a vertex held between the body and a layer of its own cloth may stay a little deeper.
    // Measured: circle skirt 0 -> 19.8 mm, dress 0 -> 11.4, cape 0 -> 0 (thickness 10 mm). (The
    // circle skirt hangs in folds round the thighs since its placement is relaxed and its
    // compression soft; before, it flew up round the torso and measured 3.8 -> 11.8 mm. Pinning
    // the vertices the body holds, so that the resolve moves only the outer layer, left pairs it
    // could not separate: 13,000 % strain. A last push out of the body after the resolve brought
    // crossings back in 56 of 120 frames.)
    EXPECT_LE(on.deepest, std::max(asset.thickness, off.deepest) + 1.5 * asset.thickness);
}

INSTANTIATE_TEST_SUITE_P(
    Garments, SelfCollisionInTheWorld,
    ::testing::Values(SelfCollisionCase{"circle skirt", GarmentKind::Skirt, GarmentCut::Circle},
                      SelfCollisionCase{"dress", GarmentKind::Dress, GarmentCut::ALine},
                      SelfCollisionCase{"half-circle cape", GarmentKind::Cape, GarmentCut::Circle}),
    [](const ::testing::TestParamInfo<SelfCollisionCase>& param) {
        std::string name = param.param.name;
        for (char& c : name)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return name;
    });

} // namespace
} // namespace cc

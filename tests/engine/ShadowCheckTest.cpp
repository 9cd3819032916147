// The shadow check (World::setShadowCheck): a measurement of the scheduler's error that must read
// zero where the garment already runs as the reference does, more where it runs coarser, and
// change nothing in the crowd it measures.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "crowdcloth/crowdcloth.h"
#include "support/CWorldScenes.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

constexpr double kShadowFrameDt = 1.0 / 60.0;

/// A reference of 16 substeps x 8 iterations (the defaults' 64 x 40 costs 20x more; what is
/// tested does not depend on it), checked against itself at 8 substeps.
ShadowCheckDesc referenceCheck(uint32_t garments) {
    ShadowCheckDesc check;
    check.garments = garments;
    check.substeps = 16;
    check.iterations = 8;
    return check;
}

struct CheckedRun {
    std::vector<ShadowCheckResult> results;
    uint64_t hash = 0;
    int levels = 0;  ///< the asset's level count
};

/// `count` capes on mannequins walking at `speed` m/s (continuous tests against the body from
/// 1.5 m/s), a camera 2.5 m behind the first; the shadow check from frame 30 when `check` has
/// garments. `forceLevel` -1 schedules the levels; `effort` sets the World's at the finest level.
CheckedRun walkChecked(int count, double speed, int forceLevel, uint32_t substeps, uint32_t iterations, const ShadowCheckDesc& check,
         int frames = 120) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    desc.maxThreads = 1;
    desc.substeps = substeps;
    desc.solverIterations = iterations;
    test::WorldPtr world(World::create(desc).value());
    ClothAssetDesc cape;
    cape.levelCount = 3;
    const AssetId asset = world->addClothAsset(cape).value();
    test::WalkingCrowd crowd = test::addWalkingCrowd(*world, asset, count);
    crowd.speed = speed;
    if (forceLevel >= 0) {
        for (GarmentId g : crowd.garments) EXPECT_TRUE(world->setGarmentLevel(g, forceLevel).isOk());
    }
    CheckedRun run;
    run.levels = int(cape.levelCount);
    for (int frame = 1; frame <= frames; ++frame) {
        if (frame == 30) {
            const Status s = world->setShadowCheck(check);
            EXPECT_TRUE(s.isOk()) << s.message();
        }
        test::walkCrowd(*world, crowd, frame * kShadowFrameDt);
        const Vec3 chest = crowd.starts[0] + Vec3(0, 1.2, crowd.speed * frame * kShadowFrameDt);
        const CameraDesc camera = test::cameraLookingAt(chest + Vec3(-0.3, 0.2, -2.5), chest);
        EXPECT_TRUE(world->setCameras(&camera, 1).isOk());
        const Status s = world->step(kShadowFrameDt);
        EXPECT_TRUE(s.isOk()) << s.message();
        const auto& results = world->shadowCheckResults();
        run.results.insert(run.results.end(), results.begin(), results.end());
    }
    run.hash = world->stateHash();
    return run;
}

TEST(ShadowCheck, AGarmentRunAsTheReferenceMeasuresNoErrorAndACoarseOneSome) {
    // Finest level, the reference's effort, continuous tests (running at 2 m/s): the garment is
    // the reference, the window must read zero. Level 0 at the World's default effort must not.
    const CheckedRun same = walkChecked(1, 2.0, 2, 16, 8, referenceCheck(1), 150);
    const CheckedRun coarse = walkChecked(1, 2.0, 0, 4, 4, referenceCheck(1), 150);
    ASSERT_GE(same.results.size(), 4u) << "a 30-frame warm-up, then 15-frame windows, over 120 frames";
    ASSERT_EQ(coarse.results.size(), same.results.size());
    for (const ShadowCheckResult& r : same.results) {
        EXPECT_EQ(r.level, 2);
        EXPECT_EQ(r.referenceLevel, 2);
        EXPECT_EQ(r.updateInterval, 1u);
        EXPECT_EQ(r.measuredMaxMetres, 0.0);  // bit for bit: the same solve on the same body
        EXPECT_EQ(r.measuredErrorPx, 0.0);
        EXPECT_EQ(r.measuredRmsPx, 0.0);
        // The reference at half its substeps is another solve: it differs, boundedly, its typical
        // vertex less than its worst.
        EXPECT_GT(r.referenceCheckPx, 0.0);
        EXPECT_LT(r.referenceCheckPx, 1000.0);
        EXPECT_GT(r.referenceCheckRmsPx, 0.0);
        EXPECT_LE(r.referenceCheckRmsPx, r.referenceCheckPx);
    }
    double worst = 0.0;
    for (const ShadowCheckResult& r : coarse.results) {
        EXPECT_EQ(r.level, 0);
        EXPECT_EQ(r.referenceLevel, 2);
        EXPECT_TRUE(std::isfinite(r.measuredErrorPx));
        // Pixels and metres agree: a camera 2.5 m away sees 720 / (2 x 2.5 tan 30 deg) = 249 px
        // per metre face-on; no vertex moves further on screen than that allows (with the near
        // side of the cape 2 m away, 1.3x).
        EXPECT_LE(r.measuredErrorPx, 1.3 * 249.0 * r.measuredMaxMetres + 1e-9);
        EXPECT_LE(r.measuredRmsPx, r.measuredErrorPx);
        EXPECT_LE(r.measuredRmsPx, 1.3 * 249.0 * r.measuredRmsMetres + 1e-9);
        worst = std::max(worst, r.measuredMaxMetres);
    }
    EXPECT_GT(worst, 1e-3) << "the coarsest level of a running cape is within a millimetre of the finest";
}

TEST(ShadowCheck, TheCrowdItMeasuresRunsBitForBitAsWithoutIt) {
    const CheckedRun off = walkChecked(6, 1.2, -1, 4, 4, referenceCheck(0), 120);
    const CheckedRun on = walkChecked(6, 1.2, -1, 4, 4, referenceCheck(3), 120);
    EXPECT_TRUE(off.results.empty());
    EXPECT_GE(on.results.size(), 6u);
    EXPECT_EQ(on.hash, off.hash);
    // Round robin: more than one garment checked.
    std::vector<uint32_t> checked;
    for (const ShadowCheckResult& r : on.results) checked.push_back(r.garment.index1);
    std::sort(checked.begin(), checked.end());
    EXPECT_GT(std::unique(checked.begin(), checked.end()) - checked.begin(), 1);
}

TEST(ShadowCheck, AbsurdSettingsAreRefusedNamingTheField) {
    test::WorldPtr world(World::create({}).value());
    const std::pair<ShadowCheckDesc, const char*> bad[] = {
        {[] { ShadowCheckDesc d; d.garments = 65; return d; }(), "garments"},
        {[] { ShadowCheckDesc d; d.windowSeconds = std::nan(""); return d; }(), "windowSeconds"},
        {[] { ShadowCheckDesc d; d.windowSeconds = 0.0; return d; }(), "windowSeconds"},
        {[] { ShadowCheckDesc d; d.substeps = 1; return d; }(), "substeps"},  // its check needs half
        {[] { ShadowCheckDesc d; d.iterations = 101; return d; }(), "iterations"},
    };
    for (const auto& [desc, field] : bad) {
        const Status s = world->setShadowCheck(desc);
        EXPECT_FALSE(s.isOk()) << field;
        EXPECT_NE(s.message().find(field), std::string::npos) << s.message();
    }
    EXPECT_TRUE(world->setShadowCheck(referenceCheck(2)).isOk());
}

TEST(ShadowCheck, AGarmentRemovedMidWindowIsDroppedWithoutAResult) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    test::WorldPtr world(World::create(desc).value());
    const test::WalkingCrowd crowd = test::addWalkingCrowd(*world, world->addClothAsset({}).value(), 1);
    const CameraDesc camera = test::cameraLookingAt(Vec3(-0.3, 1.4, -2.5), Vec3(0, 1.2, 0));
    ASSERT_TRUE(world->setCameras(&camera, 1).isOk());
    ASSERT_TRUE(world->setShadowCheck(referenceCheck(1)).isOk());
    ASSERT_TRUE(world->step(kShadowFrameDt).isOk());  // a window starts on the garment just updated
    ASSERT_TRUE(world->removeGarment(crowd.garments[0]).isOk());
    for (int frame = 0; frame < 30; ++frame) {
        ASSERT_TRUE(world->step(kShadowFrameDt).isOk());
        EXPECT_TRUE(world->shadowCheckResults().empty());
    }
}

TEST(ShadowCheck, TheCApiTurnsItOnAndCopiesItsResults) {
    cc_cloth_asset_desc ad;
    cc_cloth_asset_desc_init(&ad);
    ad.level_count = 2;
    test::CWorldScene scene;
    ASSERT_EQ(test::makeCWorldScene(ad, test::cameraLookingAt(Vec3(-0.3, 1.4, -2.5), Vec3(0, 1.2, 0)), scene), CC_OK);
    cc_world* world = scene.world;
    const cc_garment_id garment = scene.garment;

    EXPECT_EQ(cc_world_set_shadow_check(world, 1, 0.0, 4, 2), CC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(cc_world_last_error(world)).find("windowSeconds"), std::string::npos);
    ASSERT_EQ(cc_world_set_shadow_check(world, 1, 0.05, 4, 2), CC_OK);
    uint32_t count = 0, windows = 0;
    EXPECT_EQ(cc_world_get_shadow_check_results(world, nullptr, 1, &count), CC_INVALID_ARGUMENT);
    EXPECT_EQ(cc_world_get_shadow_check_results(world, nullptr, 0, nullptr), CC_INVALID_ARGUMENT);
    for (int f = 0; f < 60; ++f) {
        ASSERT_EQ(cc_world_step(world, kShadowFrameDt), CC_OK) << cc_world_last_error(world);
        cc_shadow_check_result result{};
        ASSERT_EQ(cc_world_get_shadow_check_results(world, &result, 1, &count), CC_OK);
        ASSERT_LE(count, 1u);
        if (count == 0) continue;
        ++windows;
        EXPECT_EQ(result.garment.index1, garment.index1);
        EXPECT_EQ(result.reference_level, 1);
        EXPECT_TRUE(std::isfinite(result.measured_error_px) && result.measured_error_px >= 0.0);
        EXPECT_GE(result.reference_check_px, 0.0);
        EXPECT_TRUE(result.measured_rms_px >= 0.0 && result.measured_rms_px <= result.measured_error_px);
        EXPECT_TRUE(result.reference_check_rms_px >= 0.0 && result.reference_check_rms_px <= result.reference_check_px);
    }
    // A window starts on a frame the garment updates; standing, it updates every few frames.
    EXPECT_GE(windows, 2u);
    cc_world_destroy(world);
}

} // namespace
} // namespace cc

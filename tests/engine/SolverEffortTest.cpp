// WorldDesc::effortAt: the finest level gets the desc's substeps and iterations, coarser levels
// less, never none; a frame longer or shorter than 1/60 s more or fewer substeps of the same
// length. WorldDesc::applyPreset and cc_world_desc_apply_preset: three ordered choices of speed
// against accuracy that leave the host's other settings alone, refuse what is not a preset, and
// step a walking crowd stably; a far garment gets a coarser level under Fast than under Quality.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "crowdcloth/crowdcloth.h"
#include "support/CrowdScenes.h"
#include "support/WorldPtr.h"

namespace cc {
namespace {

WorldDesc presetDesc(QualityPreset preset) {
    WorldDesc desc;
    EXPECT_TRUE(desc.applyPreset(preset).isOk());
    return desc;
}

TEST(SolverEffort, FinestLevelGetsTheDescsEffortCoarserLevelsLessButAtLeastOne) {
    WorldDesc desc;
    desc.substeps = 8, desc.solverIterations = 3;
    const uint32_t levels = 5;
    const WorldDesc::Effort finest = desc.effortAt(levels - 1, levels);
    EXPECT_EQ(finest.substeps, 8u);
    EXPECT_EQ(finest.iterations, 3u);
    // One iteration fewer per level below the finest, half the substeps every second level.
    const uint32_t substeps[] = {2, 2, 4, 4, 8}, iterations[] = {1, 1, 1, 2, 3};
    for (uint32_t l = 0; l < levels; ++l) {
        const WorldDesc::Effort e = desc.effortAt(l, levels);
        EXPECT_EQ(e.substeps, substeps[l]) << "level " << l;
        EXPECT_EQ(e.iterations, iterations[l]) << "level " << l;
    }
    desc.substeps = 1, desc.solverIterations = 1;
    for (uint32_t l = 0; l < levels; ++l) {
        EXPECT_EQ(desc.effortAt(l, levels).substeps, 1u);
        EXPECT_EQ(desc.effortAt(l, levels).iterations, 1u);
    }
}

TEST(SolverEffort, ALongerFrameGetsSubstepsOfTheSameLength) {
    WorldDesc desc;
    desc.substeps = 4, desc.solverIterations = 3;
    const uint32_t levels = 5;
    for (uint32_t l = 0; l < levels; ++l) {
        const WorldDesc::Effort at60 = desc.effortAt(l, levels);
        EXPECT_EQ(desc.effortAt(l, levels, 1.0 / 60.0).substeps, at60.substeps) << "level " << l;
        // Frame times jittering about 1/60 s keep their substeps (and the factors built for them).
        EXPECT_EQ(desc.effortAt(l, levels, 1.0 / 59.0).substeps, at60.substeps) << "level " << l;
        EXPECT_EQ(desc.effortAt(l, levels, 1.0 / 61.0).substeps, at60.substeps) << "level " << l;
        const WorldDesc::Effort at30 = desc.effortAt(l, levels, 1.0 / 30.0);
        EXPECT_EQ(at30.substeps, 2 * at60.substeps) << "level " << l;
        EXPECT_EQ(at30.iterations, at60.iterations) << "iterations are per substep: level " << l;
        EXPECT_NEAR((1.0 / 30.0) / at30.substeps, (1.0 / 60.0) / at60.substeps, 1e-15)
            << "level " << l;
        EXPECT_EQ(desc.effortAt(l, levels, 1.0 / 15.0).substeps, 4 * at60.substeps)
            << "level " << l;
        // Shorter frames: fewer, never none.
        EXPECT_EQ(desc.effortAt(l, levels, 1.0 / 120.0).substeps, std::max(1u, at60.substeps / 2))
            << "level " << l;
        EXPECT_EQ(desc.effortAt(l, levels, 1e-6).substeps, 1u) << "level " << l;
    }
    desc.substeps = 64; // the most a desc names: a long frame stays within it
    EXPECT_EQ(desc.effortAt(levels - 1, levels, 0.1).substeps, 64u);
}

/// The substeps a cape's update ran at its finest level on the walking mannequin, at `rate` [Hz].
uint32_t substepsOfAnUpdate(double rate) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    test::WorldPtr world(World::create(desc).value());
    const auto crowd = test::addWalkingCrowd(*world, world->addClothAsset({}).value(), 1);
    EXPECT_TRUE(
        world->setGarmentLevel(crowd.garments[0], int32_t(ClothAssetDesc{}.levelCount) - 1).isOk());
    uint32_t substeps = 0;
    for (int frame = 1; frame <= 3; ++frame) {
        test::walkCrowd(*world, crowd, frame / rate);
        const Status s = world->step(1.0 / rate);
        EXPECT_TRUE(s.isOk()) << s.message();
        const GarmentStats stats = world->garmentStats(crowd.garments[0]).value();
        EXPECT_TRUE(stats.updated && !stats.failed) << "frame " << frame;
        substeps = stats.substeps;
    }
    return substeps;
}

TEST(SolverEffort, TheWorldRunsAHostsLongerFrameInMoreSubsteps) {
    const uint32_t finest = WorldDesc{}.substeps;
    EXPECT_EQ(substepsOfAnUpdate(60.0), finest);
    EXPECT_EQ(substepsOfAnUpdate(30.0), 2 * finest);
    EXPECT_EQ(substepsOfAnUpdate(120.0), finest / 2);
}

TEST(QualityPreset, PresetsAreOrderedAndLeaveTheRestOfTheDescAlone) {
    const WorldDesc fast = presetDesc(QualityPreset::Fast), balanced = presetDesc(QualityPreset::Balanced),
                    quality = presetDesc(QualityPreset::Quality);
    for (const WorldDesc* d : {&fast, &balanced, &quality}) EXPECT_TRUE(d->validate().isOk());
    EXPECT_GT(fast.pixelTolerance, balanced.pixelTolerance);
    EXPECT_GT(balanced.pixelTolerance, quality.pixelTolerance);
    EXPECT_LE(fast.substeps * fast.solverIterations, balanced.substeps * balanced.solverIterations);
    EXPECT_LE(balanced.substeps * balanced.solverIterations, quality.substeps * quality.solverIterations);
    EXPECT_LT(fast.substeps * fast.solverIterations, quality.substeps * quality.solverIterations);

    WorldDesc host;
    host.maxThreads = 3, host.frameBudgetMs = 7.0, host.strainLimit = 0.25, host.batchSize = 2;
    ASSERT_TRUE(host.applyPreset(QualityPreset::Quality).isOk());
    EXPECT_EQ(host.maxThreads, 3u);
    EXPECT_EQ(host.frameBudgetMs, 7.0);
    EXPECT_EQ(host.strainLimit, 0.25);
    EXPECT_EQ(host.batchSize, 2u);
    EXPECT_EQ(host.substeps, quality.substeps);

    WorldDesc untouched;
    const Status refused = untouched.applyPreset(QualityPreset(7));
    EXPECT_FALSE(refused.isOk());
    EXPECT_NE(refused.message().find("QualityPreset 7"), std::string::npos) << refused.message();
    EXPECT_EQ(untouched.substeps, WorldDesc{}.substeps) << "a refused preset changes nothing";
}

TEST(QualityPreset, TheCApiSetsTheSameValuesAndRefusesWhatIsNotAPreset) {
    for (int32_t p : {CC_PRESET_FAST, CC_PRESET_BALANCED, CC_PRESET_QUALITY}) {
        cc_world_desc wd;
        cc_world_desc_init(&wd);
        wd.max_threads = 2;
        ASSERT_EQ(cc_world_desc_apply_preset(&wd, p), CC_OK) << cc_world_create_error();
        const WorldDesc x = presetDesc(QualityPreset(uint32_t(p)));
        EXPECT_EQ(wd.pixel_tolerance, x.pixelTolerance);
        EXPECT_EQ(wd.substeps, x.substeps);
        EXPECT_EQ(wd.solver_iterations, x.solverIterations);
        EXPECT_EQ(wd.max_threads, 2u);
    }
    cc_world_desc wd;
    cc_world_desc_init(&wd);
    for (int32_t bad : {-1, 3, 1 << 30}) {
        EXPECT_EQ(cc_world_desc_apply_preset(&wd, bad), CC_INVALID_ARGUMENT);
        EXPECT_NE(std::string(cc_world_create_error()).find(std::to_string(bad)), std::string::npos)
            << cc_world_create_error();
    }
    EXPECT_EQ(cc_world_desc_apply_preset(nullptr, CC_PRESET_FAST), CC_INVALID_ARGUMENT);
    cc_world_desc unstamped{};
    EXPECT_EQ(cc_world_desc_apply_preset(&unstamped, CC_PRESET_FAST), CC_INVALID_ARGUMENT);
    EXPECT_NE(std::string(cc_world_create_error()).find("cc_world_desc_init"), std::string::npos);
}

/// Level and stats of one cape on a walking mannequin seen from `distance` metres, after 1 s.
GarmentStats walkSeenFrom(QualityPreset preset, double distance) {
    WorldDesc desc = presetDesc(preset);
    desc.fixedCostModel = true;
    desc.spendSlack = false;  // the tolerance alone chooses the level
    desc.maxThreads = 1;
    test::WorldPtr world(World::create(desc).value());
    const auto crowd = test::addWalkingCrowd(*world, world->addClothAsset({}).value(), 1);
    GarmentStats last;
    double maxStrain = 0.0;
    for (int frame = 1; frame <= 60; ++frame) {
        test::walkCrowd(*world, crowd, frame / 60.0);
        const Vec3 chest = crowd.starts[0] + Vec3(0, 1.2, crowd.speed * frame / 60.0);
        const CameraDesc camera = test::cameraLookingAt(chest + Vec3(-0.3, 0.2, -distance), chest);
        EXPECT_TRUE(world->setCameras(&camera, 1).isOk());
        const Status s = world->step(1.0 / 60.0);
        EXPECT_TRUE(s.isOk()) << s.message();
        last = world->garmentStats(crowd.garments[0]).value();
        EXPECT_FALSE(last.failed) << "frame " << frame;
        if (last.updated) maxStrain = std::max(maxStrain, last.maxStrain);
    }
    const RenderMeshView mesh = world->renderMesh(crowd.garments[0]).value();
    for (uint32_t k = 0; k < 3 * mesh.vertexCount; ++k) EXPECT_TRUE(std::isfinite(mesh.positions[k]));
    last.maxStrain = maxStrain;
    return last;
}

TEST(QualityPreset, EveryPresetStepsAWalkStablyAndFasterOnesChooseCoarserLevels) {
    bool coarserSomewhere = false;
    for (double distance : {3.0, 12.0, 40.0}) {
        const GarmentStats fast = walkSeenFrom(QualityPreset::Fast, distance);
        const GarmentStats balanced = walkSeenFrom(QualityPreset::Balanced, distance);
        const GarmentStats quality = walkSeenFrom(QualityPreset::Quality, distance);
        for (const GarmentStats* s : {&fast, &balanced, &quality})
            // Bounded (a blow-up reads thousands of per cent): under Balanced's 2 x 1 effort at the
            // finest level a swinging hand pinches the hem against the hip for a frame, up to 24 %.
            EXPECT_LT(s->maxStrain, 0.3) << "at " << distance << " m";
        EXPECT_LE(fast.level, balanced.level) << distance << " m";
        EXPECT_LE(balanced.level, quality.level) << distance << " m";
        coarserSomewhere = coarserSomewhere || fast.level < quality.level;
    }
    EXPECT_TRUE(coarserSomewhere) << "a 4 px tolerance never chose a coarser level than 0.5 px";
}

} // namespace
} // namespace cc

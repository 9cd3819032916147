#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "CApiWorld.h"
#include "crowdcloth/World.h"
#include "crowdcloth/crowdcloth.h"
#include "support/CrowdScenes.h"

namespace cc {
namespace {

/// Runs `count` tasks on `threads` host std::threads (the calling one among them) that take the
/// indices from the top down, so the order differs from OpenMP's.
template <typename Task>
void runOnHostThreads(int threads, uint32_t count, const Task& task) {
    std::atomic<uint32_t> taken{0};
    auto worker = [&] {
        for (uint32_t t = taken++; t < count; t = taken++) task(count - 1 - t);
    };
    std::vector<std::thread> others;
    for (int k = 1; k < threads; ++k) others.emplace_back(worker);
    worker();
    for (std::thread& t : others) t.join();
}

/// Every frame's state hash of a walking crowd, stepped by `stepFrame`.
template <typename StepFrame>
std::vector<uint64_t> crowdHashes(const StepFrame& stepFrame) {
    WorldDesc desc;
    desc.fixedCostModel = true;
    desc.budgetThreads = 2;
    desc.frameBudgetMs = 2.0;
    desc.batchSize = 2;
    World* world = World::create(desc).value();
    ClothAssetDesc cape;
    cape.levelCount = 3;
    const auto crowd = test::addWalkingCrowd(*world, world->addClothAsset(cape).value(), 6);
    std::vector<uint64_t> hashes;
    for (int frame = 1; frame <= 20; ++frame) {
        test::walkCrowd(*world, crowd, frame / 60.0);
        const CameraDesc camera = test::cameraLookingAt(Vec3(4.0, 1.0, crowd.speed * frame / 60.0),
                                                        Vec3(-2.0, 1.0, -8.0));
        EXPECT_TRUE(world->setCameras(&camera, 1).isOk());
        stepFrame(*world);
        hashes.push_back(world->stateHash());
    }
    EXPECT_GT(world->frameStats().batches, 1u)
        << "the scene has several batches to run concurrently";
    World::destroy(world);
    return hashes;
}

TEST(HostJobs, TasksOnOneTwoAndFourHostThreadsGiveTheStepHash) {
    const auto reference = crowdHashes([](World& w) { ASSERT_TRUE(w.step(1.0 / 60.0).isOk()); });
    for (int threads : {1, 2, 4}) {
        const auto hashes = crowdHashes([threads](World& w) {
            ASSERT_TRUE(w.beginStep(1.0 / 60.0).isOk());
            int phases = 0;
            do {
                ++phases;
                runOnHostThreads(threads, w.stepTaskCount(),
                                 [&](uint32_t i) { EXPECT_TRUE(w.runStepTask(i).isOk()); });
            } while (w.nextStepPhase());
            EXPECT_EQ(phases, 2);
            ASSERT_TRUE(w.endStep().isOk());
        });
        EXPECT_EQ(hashes, reference) << threads << " host threads";
    }
}

TEST(HostJobs, TheCApiGivesTheStepHash) {
    const auto reference = crowdHashes([](World& w) { ASSERT_TRUE(w.step(1.0 / 60.0).isOk()); });
    const auto hashes = crowdHashes([](World& w) {
        cc_world c{&w, {}, {}, {}}; // the C handle over this world
        ASSERT_EQ(cc_world_begin_step(&c, 1.0 / 60.0), CC_OK) << c.lastError;
        do {
            runOnHostThreads(2, cc_world_step_task_count(&c),
                             [&](uint32_t i) { EXPECT_EQ(cc_world_run_step_task(&c, i), CC_OK); });
        } while (cc_world_next_step_phase(&c));
        ASSERT_EQ(cc_world_end_step(&c), CC_OK) << c.lastError;
    });
    EXPECT_EQ(hashes, reference);
}

TEST(HostJobs, ASloppyHostNeitherBreaksNorDoublesTheStep) {
    // A host that forgets the first task of each phase and runs the last twice: the second run is
    // refused, nextStepPhase runs the forgotten one, the state is bit for bit step()'s, and
    // endStep says what the host did.
    const auto reference = crowdHashes([](World& w) { ASSERT_TRUE(w.step(1.0 / 60.0).isOk()); });
    const auto hashes = crowdHashes([](World& w) {
        ASSERT_TRUE(w.beginStep(1.0 / 60.0).isOk());
        uint32_t skipped = 0;
        do {
            const uint32_t n = w.stepTaskCount();
            if (n == 0) continue;
            runOnHostThreads(2, n - 1, [&](uint32_t i) { EXPECT_TRUE(w.runStepTask(i + 1).isOk()); });
            EXPECT_NE(w.runStepTask(n - 1).message().find("already run"), std::string::npos);
            ++skipped;
        } while (w.nextStepPhase());
        const Status end = w.endStep();
        if (skipped == 0) {
            EXPECT_TRUE(end.isOk());
        } else {
            EXPECT_EQ(end.code(), StatusCode::InvalidOperation);
            EXPECT_NE(end.message().find(std::to_string(skipped) + " of its tasks were left unrun"), std::string::npos)
                << end.message();
        }
    });
    EXPECT_EQ(hashes, reference);
}

TEST(HostJobs, CallsOutOfOrderAreRefusedNamingWhy) {
    World* world = World::create({}).value();
    const AssetId cape = world->addClothAsset({}).value();
    CharacterDesc cd;
    cd.body = world->addMannequinBody({}).value();
    GarmentDesc updatedEveryFrame;
    updatedEveryFrame.forceLevel = 1;
    ASSERT_TRUE(world->addGarment(cape, world->addCharacter(cd).value(), updatedEveryFrame).isOk());
    EXPECT_NE(world->endStep().message().find("no step begun"), std::string::npos);
    EXPECT_EQ(world->stepTaskCount(), 0u);
    ASSERT_TRUE(world->beginStep(1.0 / 60.0).isOk());
    EXPECT_EQ(world->stepTaskCount(), 1u);
    EXPECT_NE(world->step(1.0 / 60.0).message().find("still open"), std::string::npos);
    EXPECT_NE(world->runStepTask(1).message().find("index 1 is not below stepTaskCount() = 1"),
              std::string::npos);
    EXPECT_NE(world->endStep().message().find("still to run"), std::string::npos);
    ASSERT_TRUE(world->runStepTask(0).isOk());
    while (world->nextStepPhase())
        for (uint32_t i = 0; i < world->stepTaskCount(); ++i)
            ASSERT_TRUE(world->runStepTask(i).isOk());
    EXPECT_TRUE(world->endStep().isOk());
    EXPECT_TRUE(world->step(1.0 / 60.0).isOk());
    World::destroy(world);
}

} // namespace
} // namespace cc

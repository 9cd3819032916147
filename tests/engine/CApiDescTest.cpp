#include <atomic>
#include <string>

#include <gtest/gtest.h>

#include "CApiWorld.h"
#include "crowdcloth/World.h"
#include "crowdcloth/crowdcloth.h"

namespace cc {
namespace {

bool contains(const char* text, const char* part) {
    return std::string(text).find(part) != std::string::npos;
}

TEST(CApiDesc, UnstampedAndOtherLayoutsAreRefusedNamingWhy) {
    cc_world* world = nullptr;
    cc_world_desc wd{};
    EXPECT_EQ(cc_world_create(&wd, &world), CC_INVALID_ARGUMENT);
    EXPECT_TRUE(contains(cc_world_create_error(),
                         "world desc was not initialised with cc_world_desc_init()"))
        << cc_world_create_error();
    cc_world_desc_init(&wd);
    wd.version = CC_DESC_MAGIC | 0xffffu;
    EXPECT_EQ(cc_world_create(&wd, &world), CC_INVALID_ARGUMENT);
    EXPECT_TRUE(contains(cc_world_create_error(), "newer headers")) << cc_world_create_error();
    wd.version = CC_DESC_MAGIC | 2u;
    EXPECT_EQ(cc_world_create(&wd, &world), CC_INVALID_ARGUMENT);
    EXPECT_TRUE(contains(cc_world_create_error(), "older headers")) << cc_world_create_error();
    EXPECT_EQ(world, nullptr);
    cc_world_desc_init(&wd);
    wd.substeps = 0;
    EXPECT_EQ(cc_world_create(&wd, &world), CC_INVALID_ARGUMENT);
    EXPECT_TRUE(contains(cc_world_create_error(), "WorldDesc.substeps")) << cc_world_create_error();

    cc_world_desc_init(&wd);
    ASSERT_EQ(cc_world_create(&wd, &world), CC_OK);
    EXPECT_STREQ(cc_world_create_error(), "");
    cc_cloth_asset_desc ad;
    cc_cloth_asset_desc_init(&ad);
    ad.version = CC_DESC_MAGIC | 0xffffu;
    cc_asset_id asset;
    EXPECT_EQ(cc_world_add_cloth_asset(world, &ad, &asset), CC_INVALID_ARGUMENT);
    EXPECT_TRUE(contains(cc_world_last_error(world),
                         "cloth asset desc has layout 65535 from newer headers"))
        << cc_world_last_error(world);
    cc_camera_desc cameras[2];
    cc_camera_desc_init(&cameras[0]);
    cameras[1] = cameras[0];
    cameras[1].version = 0;
    EXPECT_EQ(cc_world_set_cameras(world, cameras, 2), CC_INVALID_ARGUMENT);
    EXPECT_TRUE(contains(cc_world_last_error(world), "camera desc 1 was not initialised"))
        << cc_world_last_error(world);
    cc_world_destroy(world);
}

/// A C job system that runs the tasks in reverse order on the calling thread and counts its calls.
void runBackwards(void* calls, uint32_t count, cc_task_fn task, void* context) {
    ++*static_cast<std::atomic<int>*>(calls);
    for (uint32_t i = count; i-- > 0;) task(context, i);
}

/// Every world field set from C gives the world the C++ desc with the same fields makes.
TEST(CApiDesc, EveryWorldFieldReachesTheWorld) {
    std::atomic<int> calls{0};
    cc_world_desc c;
    cc_world_desc_init(&c);
    c.fixed_cost_model = 1;
    c.budget_threads = 2;
    c.frame_budget_ms = 3.0;
    c.pixel_tolerance = 0.5;
    c.gravity[1] = -5.0;
    c.task_runner = runBackwards;
    c.task_runner_user_data = &calls;
    c.max_update_interval = 4;
    c.substeps = 2;
    c.solver_iterations = 3;
    c.batch_size = 2;
    c.strain_limit = 0.05;
    c.self_collision = 0;
    c.spend_slack = 0;
    WorldDesc cpp;
    cpp.fixedCostModel = true;
    cpp.budgetThreads = 2;
    cpp.frameBudgetMs = 3.0;
    cpp.pixelTolerance = 0.5;
    cpp.gravity[1] = -5.0;
    cpp.maxUpdateInterval = 4;
    cpp.substeps = 2;
    cpp.solverIterations = 3;
    cpp.batchSize = 2;
    cpp.strainLimit = 0.05;
    cpp.selfCollision = false;
    cpp.spendSlack = false;

    cc_world* cWorld = nullptr;
    ASSERT_EQ(cc_world_create(&c, &cWorld), CC_OK) << cc_world_create_error();
    World* cppWorld = World::create(cpp).value();
    for (World* world : {cWorld->world, cppWorld}) {
        const AssetId cape = world->addClothAsset({}).value();
        CharacterDesc cd;
        cd.body = world->addMannequinBody({}).value();
        for (int i = 0; i < 3; ++i) {
            cd.position[0] = 1.5 * i;
            ASSERT_TRUE(world->addGarment(cape, world->addCharacter(cd).value(), {}).isOk());
        }
    }
    for (int frame = 0; frame < 20; ++frame) {
        ASSERT_EQ(cc_world_step(cWorld, 1.0 / 60.0), CC_OK) << cc_world_last_error(cWorld);
        ASSERT_TRUE(cppWorld->step(1.0 / 60.0).isOk());
    }
    EXPECT_GT(calls.load(), 0) << "the C task runner was used";
    cc_frame_stats fs;
    ASSERT_EQ(cc_world_get_frame_stats(cWorld, &fs), CC_OK);
    EXPECT_EQ(fs.batches, cppWorld->frameStats().batches);
    EXPECT_EQ(fs.budget_cpu_ms, cppWorld->frameStats().budgetCpuMs);
    uint64_t cHash = 0;
    ASSERT_EQ(cc_world_state_hash(cWorld, &cHash), CC_OK);
    EXPECT_EQ(cHash, cppWorld->stateHash());
    World::destroy(cppWorld);
    cc_world_destroy(cWorld);
}

} // namespace
} // namespace cc

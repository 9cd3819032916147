// Defined behaviour at the edges of a World's life: no characters, dt at its bounds, a thousand
// characters joining and leaving in one frame, and calls made while a host's step is open.

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/World.h"
#include "support/CrowdScenes.h"

namespace cc {
namespace {

constexpr double kDt = 1.0 / 60.0;

struct WorldDeleter {
    void operator()(World* w) const { World::destroy(w); }
};
using WorldPtr = std::unique_ptr<World, WorldDeleter>;

WorldPtr makeWorld() {
    WorldDesc desc;
    desc.fixedCostModel = true;  // the schedule depends on the scene only, not on the clock
    desc.frameBudgetMs = 4.0;
    return WorldPtr(World::create(desc).value());
}

AssetId addCape(World& world) {
    ClothAssetDesc cape;
    cape.levelCount = 3;
    return world.addClothAsset(cape).value();
}

void lookAtCrowd(World& world) {
    const CameraDesc camera = test::cameraLookingAt(Vec3(6.0, 1.5, 6.0), Vec3(6.0, 1.0, -4.0));
    ASSERT_TRUE(world.setCameras(&camera, 1).isOk());
}

/// Every vertex of the garment's render mesh is finite and within `reach` metres of its character.
void expectFiniteNear(World& world, GarmentId garment, const Vec3& root, double reach) {
    const auto mesh = world.renderMesh(garment);
    ASSERT_TRUE(mesh.isOk()) << mesh.status().message();
    const RenderMeshView& m = mesh.value();
    for (uint32_t v = 0; v < m.vertexCount; ++v) {
        const float* p = m.positions + 3 * std::size_t(v);
        ASSERT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) << "vertex " << v;
        ASSERT_LT((Vec3(p[0], p[1], p[2]) - root).norm(), reach) << "vertex " << v;
    }
}

TEST(WorldLifecycle, AWorldWithoutCharactersOrGarmentsSteps) {
    WorldPtr world = makeWorld();
    ASSERT_TRUE(world->step(kDt).isOk()) << "nothing at all";
    addCape(*world);
    lookAtCrowd(*world);
    ASSERT_TRUE(world->step(kDt).isOk()) << "an asset and a camera, nobody wearing it";
    CharacterDesc c;
    c.body = world->addMannequinBody({}).value();
    const CharacterId bare = world->addCharacter(c).value();
    ASSERT_TRUE(world->step(kDt).isOk()) << "a character without garments";
    EXPECT_EQ(world->frameStats().garments, 0u);
    EXPECT_EQ(world->frameStats().failed, 0u);
    ASSERT_TRUE(world->removeCharacter(bare).isOk());
    ASSERT_TRUE(world->step(kDt).isOk()) << "everyone gone again";
    EXPECT_EQ(world->frameStats().garments, 0u);
}

TEST(WorldLifecycle, DtAtItsBoundsStepsAndBeyondThemIsRefusedChangingNothing) {
    WorldPtr world = makeWorld();
    const auto crowd = test::addWalkingCrowd(*world, addCape(*world), 3);
    lookAtCrowd(*world);
    for (int frame = 1; frame <= 10; ++frame) {
        test::walkCrowd(*world, crowd, frame * kDt);
        ASSERT_TRUE(world->step(kDt).isOk());
    }
    const uint64_t before = world->stateHash();
    const double inf = std::numeric_limits<double>::infinity();
    for (double dt : {0.0, -kDt, std::numeric_limits<double>::min(), std::nextafter(1e-6, 0.0), std::nextafter(0.1, 1.0),
                      1.0, inf, std::numeric_limits<double>::quiet_NaN()}) {
        const Status s = world->step(dt);
        EXPECT_EQ(s.code(), StatusCode::InvalidArgument) << "dt " << dt;
        EXPECT_NE(s.message().find("dt"), std::string::npos) << s.message();
        EXPECT_EQ(world->stateHash(), before) << "a refused step changed the state (dt " << dt << ")";
    }
    // The bounds themselves: the longest step a garment may take, and the shortest.
    double t = 10 * kDt;
    for (double dt : {0.1, 0.1, 1e-6, 1e-6, kDt}) {
        t += dt;
        test::walkCrowd(*world, crowd, t);
        ASSERT_TRUE(world->step(dt).isOk()) << "dt " << dt;
        EXPECT_EQ(world->frameStats().failed, 0u) << "dt " << dt << ": " << world->statsJson().substr(0, 600);
        for (std::size_t i = 0; i < crowd.garments.size(); ++i)
            expectFiniteNear(*world, crowd.garments[i], crowd.starts[i] + Vec3(0.0, 0.0, crowd.speed * t), 3.0);
    }
}

/// Characters with garments that join a World together: one body, one cape, in rows beyond the
/// walkers of test::addWalkingCrowd.
struct Joiners {
    std::vector<CharacterId> characters;
    std::vector<GarmentId> garments;

    static Joiners join(World& world, BodyId body, AssetId cape, int count, double x0) {
        Joiners j;
        for (int i = 0; i < count; ++i) {
            CharacterDesc c;
            c.body = body;
            c.clipTime = 0.01 * i;
            const int row = i / 40; // forty to a row
            c.position[0] = x0 + 2.0 * (i % 40);
            c.position[2] = -40.0 - 2.0 * row;
            j.characters.push_back(world.addCharacter(c).value());
            j.garments.push_back(world.addGarment(cape, j.characters.back(), {}).value());
        }
        return j;
    }
    void leave(World& world) const {
        for (CharacterId c : characters) ASSERT_TRUE(world.removeCharacter(c).isOk());
        EXPECT_FALSE(world.renderMesh(garments.front()).isOk()) << "a left character's garment went with it";
    }
};

TEST(WorldLifecycle, AThousandCharactersJoiningAndLeavingInOneFrameLeaveNoTrace) {
    // Two worlds with the same five walkers; in one, a thousand characters with garments join and
    // leave between two steps: the walkers' state stays bit-identical to the quiet world's.
    WorldPtr quiet = makeWorld(), busy = makeWorld();
    const auto quietCrowd = test::addWalkingCrowd(*quiet, addCape(*quiet), 5);
    const AssetId busyCape = addCape(*busy);
    const auto busyCrowd = test::addWalkingCrowd(*busy, busyCape, 5);
    const BodyId joinersBody = busy->addMannequinBody({}).value();
    ASSERT_TRUE(quiet->addMannequinBody({}).isOk());  // the worlds differ only in the joiners
    lookAtCrowd(*quiet);
    lookAtCrowd(*busy);
    for (int frame = 1; frame <= 6; ++frame) {
        if (frame == 6) Joiners::join(*busy, joinersBody, busyCape, 1000, 0.0).leave(*busy);
        test::walkCrowd(*quiet, quietCrowd, frame * kDt);
        ASSERT_TRUE(quiet->step(kDt).isOk());
        test::walkCrowd(*busy, busyCrowd, frame * kDt);
        ASSERT_TRUE(busy->step(kDt).isOk());
    }
    EXPECT_EQ(busy->frameStats().garments, 5u);
    EXPECT_EQ(busy->stateHash(), quiet->stateHash()) << "joining and leaving in one frame left a trace";
}

TEST(WorldLifecycle, ACrowdLeavingWhileAnotherJoinsInOneFrameGoesOnStepping) {
    // A crowd joins and is stepped; in one frame it leaves and another joins (reusing its handles,
    // colliders and scratch); then everyone but the walkers leaves. 250 each: under the sanitizers
    // every stepped garment costs 25 times what it does here.
    WorldPtr world = makeWorld();
    const AssetId cape = addCape(*world);
    const auto walkers = test::addWalkingCrowd(*world, cape, 5);
    const BodyId body = world->addMannequinBody({}).value();
    lookAtCrowd(*world);
    auto stepTo = [&](int frame) {
        test::walkCrowd(*world, walkers, frame * kDt);
        ASSERT_TRUE(world->step(kDt).isOk());
        EXPECT_EQ(world->frameStats().failed, 0u) << "frame " << frame;
    };
    for (int frame = 1; frame <= 3; ++frame) stepTo(frame);
    const Joiners first = Joiners::join(*world, body, cape, 250, 0.0);
    stepTo(4);
    stepTo(5);
    EXPECT_EQ(world->frameStats().garments, 255u);
    first.leave(*world);
    const Joiners second = Joiners::join(*world, body, cape, 250, 100.0);
    stepTo(6);
    EXPECT_EQ(world->frameStats().garments, 255u);
    for (std::size_t i = 0; i < second.garments.size(); i += 31) {
        const std::size_t row = i / 40; // as Joiners::join placed them
        expectFiniteNear(*world, second.garments[i], Vec3(100.0 + 2.0 * (i % 40), 0.0, -40.0 - 2.0 * row), 3.0);
    }
    second.leave(*world);
    stepTo(7);
    EXPECT_EQ(world->frameStats().garments, 5u);
    for (std::size_t i = 0; i < walkers.garments.size(); ++i)
        expectFiniteNear(*world, walkers.garments[i], walkers.starts[i] + Vec3(0.0, 0.0, walkers.speed * 7 * kDt), 3.0);
}

TEST(WorldLifecycle, CallsWhileAStepIsOpenAreRefusedNamingThemAndChangeNothing) {
    // A host running the step's tasks itself (beginStep ... endStep) that removes a character or
    // adds a garment between phases would pull state from under the tasks: refused, and the step
    // ends exactly as step() would have.
    WorldPtr reference = makeWorld(), hosted = makeWorld();
    const auto referenceCrowd = test::addWalkingCrowd(*reference, addCape(*reference), 4);
    const AssetId cape = addCape(*hosted);
    const auto crowd = test::addWalkingCrowd(*hosted, cape, 4);
    lookAtCrowd(*reference);
    lookAtCrowd(*hosted);
    for (int frame = 1; frame <= 3; ++frame) {
        test::walkCrowd(*reference, referenceCrowd, frame * kDt);
        ASSERT_TRUE(reference->step(kDt).isOk());
        test::walkCrowd(*hosted, crowd, frame * kDt);
        ASSERT_TRUE(hosted->step(kDt).isOk());
    }
    test::walkCrowd(*reference, referenceCrowd, 4 * kDt);
    ASSERT_TRUE(reference->step(kDt).isOk());
    test::walkCrowd(*hosted, crowd, 4 * kDt);

    World& w = *hosted;
    auto expectRefused = [](const Status& s, const char* call) {
        EXPECT_EQ(s.code(), StatusCode::InvalidOperation) << call;
        EXPECT_NE(s.message().find(std::string("World::") + call), std::string::npos) << s.message();
        EXPECT_NE(s.message().find("step is open"), std::string::npos) << s.message();
    };
    auto everyCallIsRefused = [&] {
        const double position[3] = {50.0, 0.0, 50.0};
        CharacterDesc c;
        expectRefused(w.removeCharacter(crowd.characters[0]), "removeCharacter");
        expectRefused(w.removeGarment(crowd.garments[1]), "removeGarment");
        expectRefused(w.addCharacter(c).status(), "addCharacter");
        expectRefused(w.addGarment(cape, crowd.characters[2], {}).status(), "addGarment");
        expectRefused(w.addClothAsset({}).status(), "addClothAsset");
        expectRefused(w.addMannequinBody({}).status(), "addMannequinBody");
        expectRefused(w.setCharacterRoot(crowd.characters[3], position, 1.0), "setCharacterRoot");
        expectRefused(w.setCharacterPlaybackRate(crowd.characters[3], 2.0), "setCharacterPlaybackRate");
        expectRefused(w.setCameras(nullptr, 0), "setCameras");
        expectRefused(w.setFrameBudget(100.0), "setFrameBudget");
        expectRefused(w.renderMesh(crowd.garments[0]).status(), "renderMesh");
        expectRefused(w.garmentStats(crowd.garments[0]).status(), "garmentStats");
        expectRefused(w.characterMesh(crowd.characters[0]).status(), "characterMesh");
    };
    ASSERT_TRUE(w.beginStep(kDt).isOk());
    everyCallIsRefused();
    do {
        for (uint32_t i = 0, n = w.stepTaskCount(); i < n; ++i) ASSERT_TRUE(w.runStepTask(i).isOk());
        everyCallIsRefused();  // between phases too
    } while (w.nextStepPhase());
    ASSERT_TRUE(w.endStep().isOk());
    EXPECT_EQ(w.stateHash(), reference->stateHash()) << "the refused calls changed the step";
    EXPECT_EQ(w.frameStats().garments, 4u);

    // After endStep() the same calls are allowed again.
    ASSERT_TRUE(w.removeCharacter(crowd.characters[0]).isOk());
    ASSERT_TRUE(w.renderMesh(crowd.garments[1]).isOk());
    test::walkCrowd(w, crowd, 5 * kDt);
    ASSERT_TRUE(w.step(kDt).isOk());
    EXPECT_EQ(w.frameStats().garments, 3u);
}

} // namespace
} // namespace cc

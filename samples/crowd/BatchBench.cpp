#include <cstdio>
#include <vector>

#include "Studies.h"

namespace crowd {
namespace {

struct BatchRun {
    double msPerFrame = 0.0;      ///< [ms] wall time of the simulate phase, one thread
    double vertexSteps = 0.0;     ///< simulated vertices updated per frame
    uint32_t batches = 0, failed = 0;
    uint64_t hash = 0;
    bool ok = true;
};

/// `count` walking mannequins on a grid, each in a cape forced to `level`, seen from far enough
/// that the scheduler collides them with their capsules; one thread.
BatchRun run(int count, int level, uint32_t batchSize, int frames, bool finestEffort = false) {
    BatchRun r;
    cc::WorldDesc desc;
    if (finestEffort) {  // level 3 of 5 then takes what the finest level takes by default: 4 x 4
        desc.substeps = 8;
        desc.solverIterations = 5;
    }
    desc.maxThreads = 1;
    desc.fixedCostModel = true;
    desc.batchSize = batchSize;
    desc.frameBudgetMs = 1e9;
    desc.maxUpdateInterval = 1;
    WorldPtr world(cc::World::create(desc).value());
    cc::ClothAssetDesc cape;
    cape.width = 0.6;
    const cc::AssetId asset = world->addClothAsset(cape).value();
    const cc::BodyId body = world->addMannequinBody({}).value();
    std::vector<cc::CharacterId> characters;
    std::vector<cc::GarmentId> garments;
    const int side = 16;
    for (int c = 0; c < count; ++c) {
        cc::CharacterDesc cd;
        cd.body = body;
        cd.clipTime = 0.037 * c;  // out of step, so no two garments move alike
        characters.push_back(world->addCharacter(cd).value());
        cc::GarmentDesc gd;
        gd.forceLevel = level;
        garments.push_back(world->addGarment(asset, characters.back(), gd).value());
    }
    double totalMs = 0.0, vertices = 0.0;
    const int warmup = 30;
    for (int f = 1; f <= warmup + frames; ++f) {
        for (int c = 0; c < count; ++c) {
            const int row = c / side;
            const double position[3] = {1.5 * (c % side), 0.0, 1.5 * row + 1.35 * f / 60.0};
            (void)world->setCharacterRoot(characters[c], position, 0.0);
        }
        cc::CameraDesc camera;
        lookAt(Eigen::Vector3d(12.0, 60.0, -40.0), Eigen::Vector3d(12.0, 0.0, 12.0), 16.0 / 9.0, camera.viewProjection);
        (void)world->setCameras(&camera, 1);
        if (!world->step(1.0 / 60.0).isOk()) {
            r.ok = false;
            return r;
        }
        const cc::FrameStats& fs = world->frameStats();
        r.failed += fs.failed;
        if (f <= warmup) continue;
        totalMs += fs.simulateMs;
        for (cc::GarmentId g : garments) {
            const cc::GarmentStats s = world->garmentStats(g).value();
            if (s.updated) vertices += s.vertexCount;
        }
        r.batches = fs.batches;
    }
    r.msPerFrame = totalMs / frames;
    r.vertexSteps = vertices / frames;
    r.hash = world->stateHash();
    return r;
}

} // namespace

int runBatchBench() {
    const int count = 256, level = 3, frames = 120;
    std::printf("# %d capes at level %d of 5 on walking mannequins (capsule contacts), one thread, %d frames at 60 Hz;\n"
                "# level 3 takes 2 substeps x 3 CG iterations per update (WorldDesc defaults)\n",
                count, level, frames);
    std::printf("%-10s %10s %14s %22s %10s\n", "batch", "batches", "ms/frame", "vertex-steps/s/core", "failed");
    BatchRun alone, batched;
    for (uint32_t size : {1u, 4u, 8u}) {
        const BatchRun r = run(count, level, size, frames);
        if (!r.ok) return 1;
        std::printf("%-10u %10u %14.2f %22.0f %10u\n", size, r.batches, r.msPerFrame, 1e3 * r.vertexSteps / r.msPerFrame,
                    r.failed);
        if (size == 1) alone = r;
        if (size == 4) batched = r;
        if (r.hash != alone.hash) std::printf("  state hash differs from the unbatched run!\n");
    }
    // The same garments with the finest level's solver effort (4 substeps x 4 CG iterations)
    // instead of level 3's own (2 x 3).
    const BatchRun full = run(count, level, 4, frames, true);
    if (!full.ok) return 1;
    std::printf("%-10s %10u %14.2f %22.0f %10u   (4 substeps x 4 CG, the finest level's effort)\n", "4", full.batches,
                full.msPerFrame, 1e3 * full.vertexSteps / full.msPerFrame, full.failed);
    std::printf("BAR batch vertex_steps_per_s_per_core=%.0f alone=%.0f finest_effort=%.0f\n",
                1e3 * batched.vertexSteps / batched.msPerFrame, 1e3 * alone.vertexSteps / alone.msPerFrame,
                1e3 * full.vertexSteps / full.msPerFrame);
    return 0;
}

} // namespace crowd

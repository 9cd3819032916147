#include <cmath>
#include <cstdio>
#include <vector>

#include "Studies.h"

namespace crowd {
namespace {

struct LevelRun {
    std::vector<std::vector<float>> snapshots;  ///< render positions every 0.25 s
    double meanMs = 0.0;                        ///< [ms] per garment update
    uint32_t vertices = 0;
    bool ok = true;
};

/// A cape on a mannequin walking along +Z for `seconds`, seen from 2.5 m, at `level` (-1 = as
/// the scheduler chooses from that camera).
LevelRun runCape(int level, double seconds) {
    LevelRun run;
    cc::WorldDesc desc;
    desc.fixedCostModel = true;
    desc.maxThreads = 1;
    WorldPtr world(cc::World::create(desc).value());
    cc::ClothAssetDesc cape;
    cape.width = 0.6;
    const cc::AssetId asset = world->addClothAsset(cape).value();
    cc::CharacterDesc cd;
    cd.body = world->addMannequinBody({}).value();
    const cc::CharacterId walker = world->addCharacter(cd).value();
    cc::GarmentDesc gd;
    gd.forceLevel = level;
    const cc::GarmentId garment = world->addGarment(asset, walker, gd).value();
    const int frames = int(seconds * 60.0);
    double totalMs = 0.0;
    for (int f = 1; f <= frames; ++f) {
        const double z = 1.35 * f / 60.0, position[3] = {0.0, 0.0, z};
        (void)world->setCharacterRoot(walker, position, 0.0);
        cc::CameraDesc camera;
        lookAt(Eigen::Vector3d(-1.2, 1.5, z - 2.2), Eigen::Vector3d(0.0, 1.1, z), 16.0 / 9.0, camera.viewProjection);
        (void)world->setCameras(&camera, 1);
        if (!world->step(1.0 / 60.0).isOk()) {
            run.ok = false;
            return run;
        }
        const cc::GarmentStats s = world->garmentStats(garment).value();
        totalMs += s.measuredMs;
        run.vertices = s.vertexCount;
        run.ok = run.ok && !s.failed;
        if (f % 15 == 0) {
            const cc::RenderMeshView mesh = world->renderMesh(garment).value();
            run.snapshots.emplace_back(mesh.positions, mesh.positions + 3 * mesh.vertexCount);
        }
    }
    run.meanMs = totalMs / frames;
    return run;
}

} // namespace

int runTradeoff() {
    const double seconds = 3.0;
    std::printf("# cape (0.6 x 1.0 m) on the walking mannequin, %.0f s at 60 Hz, one thread, body mesh collision (camera 2.5 m away)\n", seconds);
    std::printf("# error: render-vertex distance to the finest level's run, same pattern point (rest-matched),\n");
    std::printf("#        sampled every 0.25 s after the first second\n");
    std::printf("%-6s %9s %12s %9s %12s %12s\n", "level", "vertices", "ms/update", "speed-up", "RMS mm", "max mm");
    std::vector<LevelRun> runs;
    for (int level = 0; level <= 4; ++level) runs.push_back(runCape(level, seconds));
    const LevelRun& finest = runs.back();
    for (int level = 0; level <= 4; ++level) {
        const LevelRun& r = runs[level];
        double sum = 0.0, worst = 0.0;
        std::size_t n = 0;
        for (std::size_t k = 4; k < r.snapshots.size() && k < finest.snapshots.size(); ++k)
            for (std::size_t v = 0; v + 2 < r.snapshots[k].size(); v += 3) {
                double d2 = 0.0;
                for (int c = 0; c < 3; ++c) d2 += std::pow(double(r.snapshots[k][v + c]) - finest.snapshots[k][v + c], 2);
                sum += d2;
                worst = std::max(worst, std::sqrt(d2));
                ++n;
            }
        std::printf("%-6d %9u %12.3f %9.1f %12.2f %12.2f%s\n", level, r.vertices, r.meanMs, finest.meanMs / r.meanMs,
                    1e3 * std::sqrt(sum / std::max<std::size_t>(n, 1)), 1e3 * worst, r.ok ? "" : "  (failed updates)");
    }
    return 0;
}

} // namespace crowd

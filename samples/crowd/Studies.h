#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "crowdcloth/World.h"
#include "crowdcloth/core/Camera.h"
#include "crowdcloth/core/Statistics.h"

namespace crowd {

using cc::percentile;

struct WorldDeleter {
    void operator()(cc::World* w) const { cc::World::destroy(w); }
};
using WorldPtr = std::unique_ptr<cc::World, WorldDeleter>;

using cc::lookAt;  // 60-degree camera, Y up

/// Every garment at its finest level, updated every frame, with no budget: what LOD saves
/// (`cc_crowd --full-resolution`, and the scaling study's mode=full).
inline void useFullResolution(cc::WorldDesc& desc) {
    desc.pixelTolerance = 1e-9;
    desc.frameBudgetMs = 1e9;
    desc.maxUpdateInterval = 1;
}

/// Crowd scaling: 10 -> 1000 characters with LOD and at full resolution, and 1 -> 2 threads.
/// With shadowCheck.garments > 0 the LOD runs also run the World's shadow check and print the
/// measured share of windows within the tolerance (BAR within_1px_measured) beside the predicted
/// one and the reference's own check. With errorTables (a cache directory) every design gets
/// its measured table (World::loadErrorTable) and the scheduler predicts from it.
int runScaling(double budgetMs, int threads, const cc::ShadowCheckDesc& shadowCheck, const std::string& errorTables);
/// Speed against accuracy: levels, substeps, iterations and strain limit against a converged
/// reference in restarted windows (Tradeoff.cpp); writes tradeoff.csv and tradeoff.png into outDir.
int runTradeoff(const std::string& outDir, double seconds);
/// 256 capes at level 3 on walking mannequins stepped one by one and in batches (BAR batch).
int runBatchBench();
/// A plaza crowd saved mid-run, restored into a fresh World, both run on (BAR snapshot).
int runSnapshotStudy(int characters, int threads);
/// Self-collision's cost against the garment's own solve, per garment kind seen close, over
/// `seconds` of a walk (BAR selfcollision).
int runSelfCollisionStudy(double seconds);

} // namespace crowd

#pragma once
// Errors that can rank (issue 14, TESTPLAN point 3): a garment's result under one configuration
// (level, substeps, iterations, strain limit) against a converged reference, measured in short
// windows each restarted from the reference's own state along a run. A long run diverges
// chaotically whatever the configuration; a window restarted from the reference measures what one
// configuration loses in a fraction of a second, where errors still rank.

#include <string>
#include <vector>

#include "crowdcloth/World.h"
#include "crowdcloth/lod/CrowdScheduler.h"
#include "crowdcloth/lod/ScreenError.h"

namespace cc::detail {

/// One character wearing one garment, driven along +Z at its clip's pace.
struct WindowScene {
    std::string name;                       ///< for the tables: "cape/walk"
    ClothAssetDesc asset;                   ///< the design worn (its levelCount is replaced by levelCount)
    std::string clip = "walk";
    double speed = 1.35;                    ///< [m/s] root speed once started (reached over the first second)
    double seconds = 3.0;                   ///< run length
    double firstWindow = 0.5;               ///< [s] where the first window starts (after the drape-in)
    double window = 0.25;                   ///< [s] window length; windows follow one another
    double cameraDistance = 2.5;            ///< [m] the camera behind and above, 60-degree field of view
    uint32_t levelCount = 6;                ///< levels of the study's asset: the top one is the reference
};

/// The reference's states at every window's start and its render mesh at every window's end.
struct ReferenceRun {
    std::vector<int> startFrames;                   ///< frame a window starts after
    std::vector<std::vector<uint8_t>> snapshots;    ///< World state there
    std::vector<std::vector<float>> endMeshes;      ///< render positions at the window's end
    std::vector<lod::SchedulerCamera> cameras;      ///< the study camera at the window's end
    double meanMs = 0.0;                            ///< [ms] per update
    bool ok = true;
};

/// What one configuration does over every window of a scene.
struct WindowResult {
    std::vector<lod::MeshDeviation> windows;  ///< at each window's end
    std::vector<double> windowMs;             ///< [ms] per garment update, mean over each window
    uint32_t vertices = 0, substeps = 0, iterationsPerSubstep = 0;
    double maxStrain = 0.0;
    bool ok = true;
    double medianMs() const;   ///< median over the windows: robust to a burst of load on a shared machine
    double medianRmsMm() const;
    double p95MaxMm() const;   ///< 95th percentile over the windows of the largest vertex distance
    double p95MaxPx() const;   ///< the same on screen
};

/// The settings a study World is made with: one thread, fixed costs, the given solver.
WorldDesc studyDesc(uint32_t substeps, uint32_t iterations, double strainLimit);

/// `base` with substeps and iterations that give `level` of an asset with `levelCount` levels the
/// effort `effort` (the inverse of WorldDesc::effortAt); fails when no valid desc gives it.
Result<WorldDesc> descGiving(const WorldDesc& base, int level, uint32_t levelCount, WorldDesc::Effort effort);

/// Runs the scene at `level` (-1 = the asset's top level) under `desc`, saving the state at every
/// window's start.
ReferenceRun recordReference(const WindowScene& scene, const WorldDesc& desc, int level = -1);

/// Restarts every window of `reference` at `level` under `desc` and measures it against the
/// reference's end of window.
WindowResult runWindows(const WindowScene& scene, const ReferenceRun& reference, const WorldDesc& desc, int level);

/// One configuration of a comparison: the World's settings and the level forced.
struct WindowConfig {
    WorldDesc desc;
    int level = 0;
};

/// runWindows for several configurations at once, interleaved window by window (so the machine's
/// drift in speed falls on all of them alike; their costs compare).
std::vector<WindowResult> runWindows(const WindowScene& scene, const ReferenceRun& reference,
                                     const std::vector<WindowConfig>& configs);

/// The level the scheduler gives the scene's garment, cut with `levelCount` levels, under `desc`
/// (its pixel tolerance, the study camera): the level of most updates after the drape-in; -1 if
/// the run fails.
int scheduledLevel(const WindowScene& scene, const WorldDesc& desc, uint32_t levelCount);

} // namespace cc::detail

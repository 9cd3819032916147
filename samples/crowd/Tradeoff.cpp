// cc_crowd --tradeoff: speed against accuracy, measured. For each scene (a garment on a walking
// or running mannequin) a converged reference is run at a level above the finest shipped (64
// substeps, 40 iterations); every configuration is then restarted from the reference's states in
// 0.25 s windows and measured at each window's end (ErrorWindows.h). Sweeps: the shipped levels at
// the World's default solver, and at the finest shipped level the substeps, the iterations and the
// strain limit; and the reference's level under the shipped solver. Writes OUT/tradeoff.csv and OUT/tradeoff.png (log cost against log error, the
// front marked) and prints the table; the reference is checked against one more refinement in
// time (32 substeps) and in space (one level coarser).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ErrorWindows.h"
#include "ExternalTools.h"
#include "Studies.h"

namespace crowd {
namespace {

constexpr uint32_t kShippedLevels = 5;            // ClothAssetDesc's default levelCount
constexpr uint32_t kDefaultSubsteps = 4, kDefaultIterations = 4;  // WorldDesc's defaults
constexpr uint32_t kReferenceSubsteps = 64, kReferenceIterations = 40;

/// One configuration of the sweep: what a shipped garment at `level` would be stepped with.
struct Config {
    std::string knob;        ///< which sweep it belongs to
    int level = 0;
    uint32_t substeps = 0;   ///< effective, at `level`
    uint32_t iterations = 0; ///< per substep, effective
    double strainLimit = 0.1;
};

/// The World desc that gives `level` of the study's asset the effort `c` names (WorldImpl's
/// solverEffort: each level below the top one iteration fewer, every second half the substeps).
cc::WorldDesc descFor(const Config& c, uint32_t levelCount) {
    const int below = int(levelCount) - 1 - c.level;
    const uint32_t substeps = std::min<uint32_t>(64, c.substeps << ((below + 1) / 2));
    const uint32_t iterations = std::min<uint32_t>(100, c.iterations + uint32_t(below));
    return studyDesc(substeps, iterations, c.strainLimit);
}

/// The effort a shipped 5-level asset gets at `level` under the default WorldDesc.
Config shipped(int level) {
    Config c;
    c.knob = "level";
    c.level = level;
    const int below = int(kShippedLevels) - 1 - level;
    c.substeps = std::max(1u, kDefaultSubsteps >> ((below + 1) / 2));
    c.iterations = uint32_t(std::max(1, int(kDefaultIterations) - below));
    return c;
}

struct Row {
    std::string scene;
    Config config;
    WindowResult result;
    bool front = false;
};

/// Marks the rows no other row of the scene beats in both cost and screen error.
void markFront(std::vector<Row>& rows) {
    for (Row& r : rows) {
        r.front = r.result.ok;
        for (const Row& o : rows)
            if (&o != &r && o.scene == r.scene && o.result.ok && o.result.meanMs <= r.result.meanMs &&
                o.result.p95MaxPx() <= r.result.p95MaxPx() &&
                (o.result.meanMs < r.result.meanMs || o.result.p95MaxPx() < r.result.p95MaxPx()))
                r.front = false;
    }
}

void printRow(const Row& r) {
    const WindowResult& x = r.result;
    std::printf("%-11s %-11s %5d %8u %8u %10u %6.2f %9.3f %9.2f %9.2f %9.2f %7.1f%% %s%s\n", r.scene.c_str(),
                r.config.knob.c_str(), r.config.level, x.vertices, x.substeps, x.iterationsPerSubstep, r.config.strainLimit,
                x.meanMs, x.medianRmsMm(), x.p95MaxMm(), x.p95MaxPx(), 100.0 * x.maxStrain, r.front ? "front" : "",
                x.ok ? "" : " (failed)");
}

} // namespace

int runTradeoff(const std::string& outDir, double seconds) {
    std::vector<WindowScene> scenes(3);
    scenes[0].name = "cape/walk";
    scenes[1].name = "cape/run";
    scenes[1].clip = "run";
    scenes[1].speed = 3.5;
    scenes[2].name = "skirt/walk";
    scenes[2].kind = cc::GarmentKind::Skirt;
    for (WindowScene& s : scenes) s.seconds = std::max(1.0, seconds);
    const int top = int(scenes[0].levelCount) - 1;

    std::printf("# speed against accuracy: each configuration restarted from a converged reference (level %d, %u substeps x %u\n"
                "# iterations) in %.2f s windows from %.1f s to %.1f s; error at each window's end, render vertices matched in\n"
                "# rest coordinates: median RMS and 95th-percentile max [mm], 95th-percentile max on screen [px] (camera %.1f m\n"
                "# away, 60-degree field of view, 1920x1080); one thread; 'front': no configuration is both cheaper and nearer\n",
                top, kReferenceSubsteps, kReferenceIterations, scenes[0].window, scenes[0].firstWindow, scenes[0].seconds,
                scenes[0].cameraDistance);
    std::vector<Config> configs;
    for (int level = 0; level < int(kShippedLevels); ++level) configs.push_back(shipped(level));
    {
        // The reference's level under the finest shipped level's solver: the solver's share of the
        // error (ref-space, the finest shipped level under the reference's solver, is the mesh's).
        Config c = shipped(int(kShippedLevels) - 1);
        c.knob = "solver-only", c.level = top;
        configs.push_back(c);
    }
    const int finest = int(kShippedLevels) - 1;
    for (uint32_t s : {1u, 2u, 8u, 16u, 32u}) {
        Config c = shipped(finest);
        c.knob = "substeps", c.substeps = s;
        configs.push_back(c);
    }
    for (uint32_t i : {1u, 2u, 8u, 16u}) {
        Config c = shipped(finest);
        c.knob = "iterations", c.iterations = i;
        configs.push_back(c);
    }
    {
        Config c = shipped(finest);
        c.knob = "no-limit", c.strainLimit = 0.0;
        configs.push_back(c);
    }

    std::vector<Row> rows;
    std::printf("%-11s %-11s %5s %8s %8s %10s %6s %9s %9s %9s %9s %8s\n", "scene", "knob", "level", "vertices", "substeps",
                "iterations", "limit", "ms/update", "RMS mm", "max mm", "max px", "strain");
    for (const WindowScene& scene : scenes) {
        const cc::WorldDesc referenceDesc = studyDesc(kReferenceSubsteps, kReferenceIterations, 0.1);
        const ReferenceRun reference = recordReference(scene, referenceDesc);
        if (!reference.ok) {
            std::fprintf(stderr, "tradeoff: the reference run of %s failed\n", scene.name.c_str());
            return 1;
        }
        // The reference against one more refinement: in time (half the substeps: the error it has
        // if it converges at first order is about that far), in space (one level coarser).
        Row time{scene.name, {"ref-time", top, kReferenceSubsteps / 2, kReferenceIterations, 0.1}, {}};
        time.result = runWindows(scene, reference, studyDesc(kReferenceSubsteps / 2, kReferenceIterations, 0.1), top);
        Row space{scene.name, {"ref-space", top - 1, kReferenceSubsteps, kReferenceIterations, 0.1}, {}};
        space.result = runWindows(scene, reference, descFor(space.config, scene.levelCount), top - 1);
        printRow(time);
        printRow(space);
        std::vector<Row> sceneRows;
        for (const Config& c : configs) {
            Row r{scene.name, c, runWindows(scene, reference, descFor(c, scene.levelCount), c.level)};
            sceneRows.push_back(r);
        }
        markFront(sceneRows);
        for (const Row& r : sceneRows) printRow(r);
        rows.insert(rows.end(), sceneRows.begin(), sceneRows.end());
        rows.push_back(time), rows.push_back(space);
        std::fflush(stdout);
    }

    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    const std::string csv = outDir + "/tradeoff.csv", png = outDir + "/tradeoff.png";
    FILE* f = std::fopen(csv.c_str(), "w");
    if (!f) {
        std::fprintf(stderr, "tradeoff: cannot write %s\n", csv.c_str());
        return 1;
    }
    std::fprintf(f, "scene,knob,level,vertices,substeps,iterations,strain_limit,ms,rms_mm,max_mm,max_px,max_strain,front,ok\n");
    for (const Row& r : rows) {
        const WindowResult& x = r.result;
        std::fprintf(f, "%s,%s,%d,%u,%u,%u,%g,%.5f,%.4f,%.4f,%.4f,%.5f,%d,%d\n", r.scene.c_str(), r.config.knob.c_str(),
                     r.config.level, x.vertices, x.substeps, x.iterationsPerSubstep, r.config.strainLimit, x.meanMs,
                     x.medianRmsMm(), x.p95MaxMm(), x.p95MaxPx(), x.maxStrain, int(r.front), int(x.ok));
    }
    std::fclose(f);
    std::printf("tradeoff: %s\n", csv.c_str());
    if (cc::Status s = plotTradeoff(csv, png); !s)
        std::fprintf(stderr, "tradeoff: no plot (%s)\n", s.message().c_str());
    else
        std::printf("tradeoff: %s\n", png.c_str());
    for (const Row& r : rows)
        if (!r.result.ok) return 3;
    return 0;
}

} // namespace crowd

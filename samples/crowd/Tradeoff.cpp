// cc_crowd --tradeoff: speed against accuracy, measured. For each scene (a garment on a walking
// or running mannequin) a converged reference is run at a level above the finest shipped (64
// substeps, 40 iterations); every configuration is then restarted from the reference's states in
// 0.25 s windows and measured at each window's end (engine/src/RestartedWindows.h). Sweeps: the shipped levels at
// the World's default solver, and at the finest shipped level the substeps, the iterations, a grid
// of the cheapest efforts and the strain limit; the reference's level under the shipped solver;
// and the three presets, each at the level its pixel tolerance gets at the study camera (BAR
// presets: is every preset on every scene's front?). Writes OUT/tradeoff.csv and OUT/tradeoff.png
// (log cost against log error, the front marked) and prints the table; the reference is checked
// against one more refinement in time (32 substeps) and in space (one level coarser).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "ExternalTools.h"
#include "RestartedWindows.h"
#include "Studies.h"

namespace crowd {
namespace {

using cc::detail::ReferenceRun;
using cc::detail::WindowConfig;
using cc::detail::WindowResult;
using cc::detail::WindowScene;
using cc::detail::recordReference;
using cc::detail::runWindows;
using cc::detail::scheduledLevel;
using cc::detail::studyDesc;

// What ships: the default asset's levels and the default World's solver effort.
const uint32_t kShippedLevels = cc::ClothAssetDesc{}.levelCount;
const cc::WorldDesc kShippedDesc{};
// The reference every error study measures against (the error tables' cook, the shadow check).
const uint32_t kReferenceSubsteps = cc::ErrorCookDesc{}.referenceSubsteps;
const uint32_t kReferenceIterations = cc::ErrorCookDesc{}.referenceIterations;

constexpr cc::QualityPreset kPresets[] = {cc::QualityPreset::Fast, cc::QualityPreset::Balanced, cc::QualityPreset::Quality};

const char* presetName(cc::QualityPreset p) {
    switch (p) {
    case cc::QualityPreset::Fast: return "fast";
    case cc::QualityPreset::Balanced: return "balanced";
    case cc::QualityPreset::Quality: return "quality";
    }
    return "?";
}

/// One configuration of the sweep: what a shipped garment at `level` would be stepped with.
struct Config {
    std::string knob;        ///< which sweep it belongs to
    int level = 0;
    uint32_t substeps = 0;   ///< effective, at `level`
    uint32_t iterations = 0; ///< per substep, effective
    double strainLimit = 0.1;
    bool operator==(const Config& o) const {
        return level == o.level && substeps == o.substeps && iterations == o.iterations && strainLimit == o.strainLimit;
    }
};

/// The World desc that gives `level` of the study's asset the effort `c` names: the inverse of
/// WorldDesc::effortAt, checked against it (a sweep that asks for more than the desc can give at a
/// coarse level stops the study rather than mislabel a row).
cc::WorldDesc descFor(const Config& c, uint32_t levelCount) {
    auto desc = cc::detail::descGiving(studyDesc(1, 1, c.strainLimit), c.level, levelCount, {c.substeps, c.iterations});
    if (!desc.isOk()) {
        std::fprintf(stderr, "tradeoff: %s\n", desc.status().message().c_str());
        std::exit(1);
    }
    return desc.value();
}

/// The effort a shipped asset gets at `level` under `desc`.
Config shipped(int level, const cc::WorldDesc& desc = kShippedDesc) {
    Config c;
    c.knob = "level";
    c.level = level;
    const cc::WorldDesc::Effort effort = desc.effortAt(uint32_t(level), kShippedLevels);
    c.substeps = effort.substeps;
    c.iterations = effort.iterations;
    c.strainLimit = desc.strainLimit;
    return c;
}

struct Row {
    std::string scene;
    Config config;
    WindowResult result;
    bool front = false;
    std::string preset;  ///< the preset this configuration is, if any
};

// The front is judged against the measurements' noise: timing on a shared 2-core machine varies by
// a few per cent, and errors by window. So one configuration beats another only measurably:
// cheaper by more than kCostNoise, or nearer in a one-sided sign test over the same windows (paired:
// both restarted from the same states) at the 5 % level.
constexpr double kCostNoise = 1.05;

bool cheaper(const WindowResult& a, const WindowResult& b) { return a.medianMs() * kCostNoise < b.medianMs(); }

/// Sign test: a is nearer than b in significantly more windows (median RMS per window).
bool nearer(const WindowResult& a, const WindowResult& b) {
    int less = 0, more = 0;
    for (std::size_t k = 0; k < std::min(a.windows.size(), b.windows.size()); ++k) {
        less += a.windows[k].rmsMetres < b.windows[k].rmsMetres;
        more += a.windows[k].rmsMetres > b.windows[k].rmsMetres;
    }
    const int n = less + more;
    // P(X >= less) for X ~ Binomial(n, 1/2), summed in logs (n is a few dozen windows).
    double tail = 0.0;
    for (int k = less; k <= n; ++k)
        tail += std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) - n * std::log(2.0));
    return n > 0 && tail < 0.05;
}

/// a dominates b: measurably better in one of cost and error, and not measurably worse in the other.
bool dominates(const WindowResult& a, const WindowResult& b) {
    return (cheaper(a, b) && !nearer(b, a)) || (!cheaper(b, a) && nearer(a, b));
}

/// Marks the rows no other row of the scene dominates.
void markFront(std::vector<Row>& rows) {
    for (Row& r : rows) {
        r.front = r.result.ok;
        for (const Row& o : rows)
            if (&o != &r && o.scene == r.scene && o.result.ok && dominates(o.result, r.result)) r.front = false;
    }
}

void printRow(const Row& r) {
    const WindowResult& x = r.result;
    std::printf("%-11s %-15s %5d %8u %8u %10u %6.2f %9.3f %9.2f %9.2f %9.2f %7.1f%% %s%s%s\n", r.scene.c_str(),
                r.config.knob.c_str(), r.config.level, x.vertices, x.substeps, x.iterationsPerSubstep, r.config.strainLimit,
                x.medianMs(), x.medianRmsMm(), x.p95MaxMm(), x.p95MaxPx(), 100.0 * x.maxStrain, r.front ? "front" : "",
                r.preset.empty() ? "" : (" preset " + r.preset).c_str(), x.ok ? "" : " (failed)");
}

/// The sweeps every scene runs (the presets are added per scene: their level follows the garment).
std::vector<Config> commonConfigs(int top) {
    std::vector<Config> configs;
    configs.reserve(kShippedLevels + 15); // the shipped levels, then the 15 sweeps below
    for (int level = 0; level < int(kShippedLevels); ++level) configs.push_back(shipped(level));
    const int finest = int(kShippedLevels) - 1;
    {
        // The reference's level under the finest shipped level's solver: the solver's share of the
        // error (ref-space, the finest shipped level under the reference's solver, is the mesh's).
        Config c = shipped(finest);
        c.knob = "solver-only", c.level = top;
        configs.push_back(c);
    }
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
    for (uint32_t sub : {1u, 2u})
        for (uint32_t it : {1u, 2u}) {
            Config c = shipped(finest);
            c.knob = "grid", c.substeps = sub, c.iterations = it;
            configs.push_back(c);
        }
    Config c = shipped(finest);
    c.knob = "no-limit", c.strainLimit = 0.0;
    configs.push_back(c);
    return configs;
}

} // namespace

int runTradeoff(const std::string& outDir, double seconds) {
    std::vector<WindowScene> scenes(3);
    scenes[0].name = "cape/walk";
    scenes[1].name = "cape/run";
    scenes[1].clip = "run";
    scenes[1].speed = 3.5;
    scenes[2].name = "skirt/walk";
    scenes[2].asset.kind = cc::GarmentKind::Skirt;
    for (WindowScene& s : scenes) s.seconds = std::max(1.0, seconds);
    const int top = int(scenes[0].levelCount) - 1;

    std::printf("# speed against accuracy: each configuration restarted from a converged reference (level %d, %u substeps x %u\n"
                "# iterations) in %.2f s windows from %.1f s to %.1f s; error at each window's end, render vertices matched in\n"
                "# rest coordinates: median RMS and 95th-percentile max [mm], 95th-percentile max on screen [px] (camera %.1f m\n"
                "# away, 60-degree field of view, 1920x1080); ms per update: median over the windows, one thread; 'front': no configuration is measurably better\n"
                "# (cheaper by > %.0f %%, or nearer in more windows by a one-sided sign test at 5 %%) and not measurably worse\n",
                top, kReferenceSubsteps, kReferenceIterations, scenes[0].window, scenes[0].firstWindow, scenes[0].seconds,
                scenes[0].cameraDistance, 100.0 * (kCostNoise - 1.0));
    const std::vector<Config> configs = commonConfigs(top);

    std::vector<Row> rows;
    bool presetsOnFront = true;
    std::printf("%-11s %-15s %5s %8s %8s %10s %6s %9s %9s %9s %9s %8s\n", "scene", "knob", "level", "vertices", "substeps",
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
        Row time{scene.name, {"ref-time", top, kReferenceSubsteps / 2, kReferenceIterations, 0.1}, {}, false, {}};
        time.result = runWindows(scene, reference, studyDesc(kReferenceSubsteps / 2, kReferenceIterations, 0.1), top);
        // (Half the reference's substeps: the most a World desc gives the level below its finest.)
        Row space{scene.name, {"ref-space", top - 1, kReferenceSubsteps / 2, kReferenceIterations, 0.1}, {}, false, {}};
        space.result = runWindows(scene, reference, descFor(space.config, scene.levelCount), top - 1);
        printRow(time);
        printRow(space);

        // Each preset where a garment under it is seen from the study camera: the level its pixel
        // tolerance asks for (no slack spent: a crowd seldom has any), with the preset's effort there.
        std::vector<Config> sceneConfigs = configs;
        std::vector<std::size_t> presetRow;
        for (const cc::QualityPreset p : kPresets) {
            cc::WorldDesc d = studyDesc(1, 1, kShippedDesc.strainLimit);
            (void)d.applyPreset(p);
            d.spendSlack = false;
            const int level = scheduledLevel(scene, d, kShippedLevels);
            if (level < 0) {
                std::fprintf(stderr, "tradeoff: %s under preset %s failed\n", scene.name.c_str(), presetName(p));
                return 1;
            }
            Config c = shipped(level, d);
            c.knob = std::string("preset-") + presetName(p);
            // A preset whose configuration another sweep measures is that row, not a second run.
            const auto same = std::find(sceneConfigs.begin(), sceneConfigs.end(), c);
            presetRow.push_back(std::size_t(same - sceneConfigs.begin()));
            if (same == sceneConfigs.end()) sceneConfigs.push_back(c);
        }
        std::vector<WindowConfig> windowConfigs;
        windowConfigs.reserve(sceneConfigs.size());
        for (const Config& c : sceneConfigs) windowConfigs.push_back({descFor(c, scene.levelCount), c.level});
        const std::vector<WindowResult> results = runWindows(scene, reference, windowConfigs);
        std::vector<Row> sceneRows;
        for (std::size_t c = 0; c < sceneConfigs.size(); ++c) sceneRows.push_back({scene.name, sceneConfigs[c], results[c], false, {}});
        for (std::size_t p = 0; p < presetRow.size(); ++p) {
            std::string& names = sceneRows[presetRow[p]].preset;
            names += (names.empty() ? "" : "+") + std::string(presetName(kPresets[p]));
        }
        markFront(sceneRows);
        for (const Row& r : sceneRows) printRow(r);
        for (std::size_t p = 0; p < presetRow.size(); ++p) {
            const Row& r = sceneRows[presetRow[p]];
            std::printf("# %s: preset %s = level %d, %u x %u: %s the front\n", scene.name.c_str(), presetName(kPresets[p]),
                        r.config.level, r.config.substeps, r.config.iterations, r.front ? "on" : "NOT on");
            presetsOnFront = presetsOnFront && r.front;
        }
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
    std::fprintf(f, "scene,knob,level,vertices,substeps,iterations,strain_limit,ms,rms_mm,max_mm,max_px,max_strain,front,ok,preset\n");
    for (const Row& r : rows) {
        const WindowResult& x = r.result;
        std::fprintf(f, "%s,%s,%d,%u,%u,%u,%g,%.5f,%.4f,%.4f,%.4f,%.5f,%d,%d,%s\n", r.scene.c_str(), r.config.knob.c_str(),
                     r.config.level, x.vertices, x.substeps, x.iterationsPerSubstep, r.config.strainLimit, x.medianMs(),
                     x.medianRmsMm(), x.p95MaxMm(), x.p95MaxPx(), x.maxStrain, int(r.front), int(x.ok), r.preset.c_str());
    }
    std::fclose(f);
    std::printf("tradeoff: %s\n", csv.c_str());
    if (cc::Status s = plotTradeoff(csv, png); !s)
        std::fprintf(stderr, "tradeoff: no plot (%s)\n", s.message().c_str());
    else
        std::printf("tradeoff: %s\n", png.c_str());
    std::printf("BAR presets front=%d scenes=%zu presets=%zu\n", int(presetsOnFront), scenes.size(), std::size(kPresets));
    for (const Row& r : rows)
        if (!r.result.ok) return 3;
    return 0;
}

} // namespace crowd

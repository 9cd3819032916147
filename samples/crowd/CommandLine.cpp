#include "CommandLine.h"

#include <cstdio>
#include <map>

#include <CLI/CLI.hpp>

namespace crowd {
namespace {

const std::map<std::string, ColorBy> kColorBy = {
    {"none", ColorBy::None}, {"lod", ColorBy::Lod}, {"solver", ColorBy::Solver}, {"error", ColorBy::Error}};

} // namespace

const char* colorByName(ColorBy c) {
    for (const auto& [name, value] : kColorBy)
        if (value == c) return name.c_str();
    return "?";
}

int parseCommandLine(int argc, char** argv, RunOptions& o) {
    using L = SceneLimits;
    CLI::App app{"crowd: the main job. A plaza of walking, running and standing characters in capes, skirts, dresses "
                 "and ponchos, seen by a moving camera; crowdcloth chooses each garment's level, solver and rate "
                 "under a frame budget. Writes PNG frames, crowd.mp4, summary.json, frames.csv and summary.png into "
                 "--out.",
                 "cc_crowd"};
    app.option_defaults()->always_capture_default();
    // Scene values given here override the scene file's; `cli` holds them until then.
    Scene cli = defaultScene();
    app.add_option("--scene", o.sceneFile, "Scene file (JSON; see samples/crowd/scenes/default.json)")
        ->check(CLI::ExistingFile);
    app.add_option("--write-scene", o.writeScene, "Write the scene (built-in, or --scene, with these options) "
                                                  "to FILE as an example, and exit");
    app.add_option("--characters", cli.plaza.characters, "Characters in the plaza")
        ->check(CLI::Range(1, L::kMaxCharacters));
    app.add_option("--seconds", cli.seconds, "Simulated seconds (60 frames each)")
        ->check(CLI::Range(1.0 / 60.0, L::kMaxSeconds));
    app.add_option("--budget", cli.budgetMs, "Cloth wall time per frame [ms]")->check(CLI::Range(0.01, L::kMaxBudgetMs));
    app.add_option("--width", cli.width, "Frame width [px]")->check(CLI::Range(L::kMinViewport, L::kMaxViewport));
    app.add_option("--height", cli.height, "Frame height [px]")->check(CLI::Range(L::kMinViewport, L::kMaxViewport));
    app.add_option("--asset", cli.assets, "Imported character to dress instead of the mannequins (any skinned "
                                          "file assimp reads; repeat to mix several)")
        ->check(CLI::ExistingFile);
    app.add_option("--clip", cli.clip, "Clip the imported characters play (default: each file's first)");
    app.add_option("--asset-height", cli.assetHeight, "Scale imported characters to this standing height [m] "
                                                      "(0 = as authored)")
        ->check(CLI::Range(0.0, 100.0));
    app.add_option("--out", o.out, "Output directory");
    app.add_option("--render-every", o.renderEvery, "Render every K-th frame (the video runs at 60/K fps)")
        ->check(CLI::Range(1, 600));
    app.add_flag("!--no-render", o.render, "Do not render frames (nor the video)");
    app.add_flag("!--no-video", o.video, "Render PNG frames but do not encode crowd.mp4");
    app.add_option("--supersample", o.supersample, "Anti-aliasing: samples per pixel along each axis")
        ->check(CLI::Range(1, 4));
    std::string colorBy = "none";
    app.add_option("--color-by", colorBy, "Garment colours: their own, or by level, solver or predicted error "
                                          "(blue 0 to red at the pixel tolerance)")
        ->check(CLI::IsMember({"none", "lod", "solver", "error"}));
    std::string exportFormat;
    app.add_option("--export", exportFormat, "Write every rendered frame's garment and body meshes to "
                                             "OUT/export (Wavefront OBJ, or binary glTF 2)")
        ->check(CLI::IsMember({"obj", "glb"}));
    app.add_flag("--frame-stats", o.frameStats, "Write every frame's stats (World::statsJson) to "
                                                "OUT/frame_stats.jsonl, one JSON line per frame");
    app.add_flag("--fixed-costs", o.fixedCosts, "Schedule by the World's fixed cost model instead of measured costs "
                                                "(WorldDesc::fixedCostModel): a run repeats exactly, frame for frame");
    app.add_flag("--garment-self-collision", o.garmentSelfCollision,
                 "Let the scheduler turn self-collision on for garments seen large (WorldDesc::selfCollision)");
    app.add_flag("--full-resolution", o.fullResolution, "Every garment at its finest level and updated every frame "
                                                        "(no budget, no LOD): the cost LOD saves");
    const std::map<std::string, int> kPresets = {{"fast", int(cc::QualityPreset::Fast)},
                                                 {"balanced", int(cc::QualityPreset::Balanced)},
                                                 {"quality", int(cc::QualityPreset::Quality)}};
    app.add_option("--preset", o.preset, "Speed against accuracy: the World's solver effort and pixel tolerance "
                                         "(WorldDesc::applyPreset; default: the default WorldDesc)")
        ->transform(CLI::CheckedTransformer(kPresets, CLI::ignore_case));
    app.add_option("--error-tables", o.errorTables, "Directory caching each garment design's measured error table "
                                                    "(cooked there on first use, about half a minute per design): the "
                                                    "scheduler predicts from measurements instead of its formula");
    app.add_option("--churn", o.churn, "Share of the characters that leave per second, each replaced by an identical "
                                       "one (new handles; a soak's joins and leaves)")
        ->check(CLI::Range(0.0, 60.0));
    app.add_option("--threads", o.threads, "Threads stepping garments (0 = all)")->check(CLI::Range(0, 1024));
    auto* scaling = app.add_flag("--scaling", o.scaling, "Study: crowd scaling 10 -> 1000 characters, with LOD "
                                                         "and at full resolution, and 1 -> 2 threads");
    app.add_option("--shadow", o.shadow, "With --scaling: garments the World's shadow check steps at once beside "
                                         "the crowd at the reference (their screen error measured, not predicted; "
                                         "0 = off)")
        ->check(CLI::Range(0, 64));
    app.add_option("--shadow-window", o.shadowWindow, "With --scaling: seconds each garment is followed by the "
                                                      "shadow check")
        ->check(CLI::Range(0.05, 2.0));
    auto* tradeoff = app.add_flag("--tradeoff", o.tradeoff, "Study: speed against accuracy (levels, substeps, "
                                                            "iterations, strain limit) in windows restarted from a converged "
                                                            "reference; OUT/tradeoff.csv and tradeoff.png (--seconds: run length)");
    auto* batch = app.add_flag("--batch", o.batch, "Study: 256 capes at level 3 stepped one by one and in batches");
    auto* snapshot = app.add_flag("--snapshot", o.snapshot, "Study: the crowd saved after 5 s, restored into a fresh "
                                                            "World, both run on 2 s (size, ms, identical frames)");
    auto* self = app.add_flag("--self-collision", o.selfCollision, "Study: self-collision's cost per frame against "
                                                                   "the garment's own solve, each garment kind at its "
                                                                   "finest level seen close on a walk (--seconds)");
    scaling->excludes(tradeoff)->excludes(batch)->excludes(snapshot)->excludes(self);
    tradeoff->excludes(batch)->excludes(snapshot)->excludes(self);
    batch->excludes(snapshot)->excludes(self);
    snapshot->excludes(self);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;  // --help is 0; every usage error is 2, like a bad scene file
    }
    o.colorBy = kColorBy.at(colorBy);
    o.exportFormat = exportFormat == "obj" ? ExportFormat::Obj : exportFormat == "glb" ? ExportFormat::Glb : ExportFormat::None;

    if (o.sceneFile.empty()) {
        o.scene = defaultScene();
    } else {
        auto scene = readScene(o.sceneFile);
        if (!scene.isOk()) {
            std::fprintf(stderr, "%s\n", scene.status().message().c_str());
            return 2;
        }
        o.scene = scene.value();
    }
    const auto given = [&](const char* name) { return app.count(name) > 0; };
    if (given("--characters")) o.scene.plaza.characters = cli.plaza.characters;
    if (given("--seconds")) o.scene.seconds = cli.seconds;
    if (given("--budget")) o.scene.budgetMs = cli.budgetMs;
    if (given("--width")) o.scene.width = cli.width;
    if (given("--height")) o.scene.height = cli.height;
    if (given("--asset")) o.scene.assets = cli.assets;
    if (given("--clip")) o.scene.clip = cli.clip;
    if (given("--asset-height")) o.scene.assetHeight = cli.assetHeight;
    return -1;
}

} // namespace crowd

// crowd: the main job. A plaza of walking, running and standing mannequins (or imported
// characters) in capes, skirts, dresses and ponchos, seen by a camera flying from a wide shot into
// a close-up and back; crowdcloth chooses each garment's level, solver and rate under a frame
// budget. `cc_crowd --help` lists every option.
//
//   cc_crowd [--scene FILE] [--characters N] [--seconds S] [--budget MS] [--threads T]
//            [--width W] [--height H] [--supersample 1-4] [--color-by none|lod|solver|error]
//            [--render-every K] [--no-render] [--no-video] [--frame-stats] [--export obj|glb]
//            [--asset FILE]... [--clip NAME] [--asset-height M] [--out DIR]
//   cc_crowd [--scene FILE] [options] --write-scene FILE   writes the scene (default: the built-in
//            one, samples/crowd/scenes/default.json) and exits; options given override the file's
//   cc_crowd --scaling   crowd scaling benchmark: 10 -> 1000 characters, with LOD and at full
//                        resolution, and the 1 -> 2 thread speed-up
//   cc_crowd --tradeoff  speed against accuracy: levels, substeps, iterations, strain limit against a
//                        converged reference in restarted windows (OUT/tradeoff.csv, tradeoff.png)
//   cc_crowd --batch     256 capes at level 3 stepped one by one and in batches (BAR batch)
//   cc_crowd --snapshot  the crowd saved, restored into a fresh World, both run on (BAR snapshot)
//   cc_crowd --self-collision --seconds 3  self-collision's cost against the solve (BAR selfcollision)
//
// Writes into --out (default crowd_out): frames/frame_NNNNN.png (every render-every frame, title
// strip with the frame's numbers), crowd.mp4 (H.264 at 60/render-every fps, unless --no-video),
// summary.json (what is printed at the end), frames.csv (one row per frame: ms, budget, garments per
// level, updated, visible, predicted error in view, resident and heap MB) and summary.png (its plot, scripts/plot-summary.py),
// frame_stats.jsonl with --frame-stats (World::statsJson() per frame), export/frame_NNNNN.obj|glb
// with --export. Exit code: 0; 2 for a bad command line or scene file; 1 for a failed run; 3 when
// garment updates failed.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "CommandLine.h"
#include "ExternalTools.h"
#include "FrameLog.h"
#include "FrameRenderer.h"
#include "GarmentVisibility.h"
#include "MeshExport.h"
#include "Plaza.h"
#include "Progress.h"
#include "RunSummary.h"
#include "SceneFile.h"
#include "Studies.h"
#include "crowdcloth/World.h"
#include "crowdcloth/import/CharacterIO.h"
#include "crowdcloth/render/OffscreenRenderer.h"

namespace {

namespace fs = std::filesystem;
using crowd::RunOptions;

int fail(const std::string& message) {
    std::fprintf(stderr, "\n%s\n", message.c_str());
    return 1;
}

/// Removes a previous run's numbered files (frame_*.EXT), which ffmpeg would otherwise pick up.
void removeOldFrames(const fs::path& dir, const std::string& extension) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("frame_", 0) == 0 && entry.path().extension() == extension) fs::remove(entry.path(), ec);
    }
}

std::string numbered(const char* extension, uint32_t n) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame_%05u.%s", n, extension);
    return name;
}

cc::Status addImportedBodies(cc::World& world, const crowd::Scene& scene, crowd::PlazaSettings& settings) {
    for (const std::string& file : scene.assets) {
        auto character = cc::importCharacter(file);
        if (!character.isOk()) return character.status();
        cc::BodyDesc bd;
        bd.height = scene.assetHeight;
        auto body = world.addCharacterBody(character.value(), bd);
        if (!body.isOk()) return cc::Status::invalidArgument(file + ": " + body.status().message());
        settings.bodies.push_back(body.value());
        std::printf("%s: %zu joints, %zu vertices, %zu clips\n", file.c_str(), character.value().skeleton.jointCount(),
                    character.value().body.vertexCount(), character.value().clips.size());
    }
    settings.clip = scene.clip;
    return cc::Status::ok();
}

int runCrowd(const RunOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    const crowd::Scene& scene = o.scene;
    cc::WorldDesc desc;
    desc.maxThreads = uint32_t(o.threads);
    desc.frameBudgetMs = scene.budgetMs;
    desc.fixedCostModel = o.fixedCosts;
    desc.selfCollision = o.garmentSelfCollision;
    if (o.preset >= 0)
        if (cc::Status s = desc.applyPreset(cc::QualityPreset(uint32_t(o.preset))); !s) return fail(s.message());
    if (o.fullResolution) crowd::useFullResolution(desc);
    auto created = cc::World::create(desc);
    if (!created.isOk()) return fail(created.status().message());
    crowd::WorldPtr world(created.value());
    crowd::PlazaSettings settings = scene.plaza;
    // Full resolution means the finest level: the tables would coarsen where it buys nothing.
    settings.errorTables = o.fullResolution ? std::string() : o.errorTables;
    if (cc::Status s = addImportedBodies(*world, scene, settings); !s) return fail(s.message());
    auto plaza = crowd::Plaza::create(*world, settings);
    if (!plaza.isOk()) return fail("plaza: " + plaza.status().message());

    const fs::path out(o.out);
    const fs::path frameDir = out / "frames", exportDir = out / "export";
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) return fail(out.string() + ": " + ec.message());
    std::unique_ptr<cc::render::OffscreenRenderer> renderer;
    if (o.render) {
        cc::render::RendererOptions ro;
        ro.supersample = o.supersample;
        auto r = cc::render::OffscreenRenderer::create(scene.width, scene.height, ro);
        if (!r.isOk()) return fail("renderer: " + r.status().message() + " (rerun with --no-render)");
        renderer = std::move(r).value();
        fs::create_directories(frameDir);
        removeOldFrames(frameDir, ".png");
    }
    const char* exportExtension = o.exportFormat == crowd::ExportFormat::Glb ? "glb" : "obj";
    if (o.exportFormat != crowd::ExportFormat::None) {
        fs::create_directories(exportDir);
        removeOldFrames(exportDir, std::string(".") + exportExtension);
    }

    const int frames = std::max(1, int(std::lround(scene.seconds * 60.0)));
    crowd::RunSummary summary(frames);
    crowd::RunSummary::Outputs outputs;
    {
        auto log = crowd::FrameLog::open(out, o.frameStats);
        if (!log.isOk()) return fail(log.status().message());
        outputs.framesCsv = log.value().csvPath().string();
        outputs.frameStats = log.value().jsonlPath().string();
        crowd::Progress progress(frames);
        std::vector<cc::GarmentStats> garments(plaza.value().garments().size());
        uint32_t exported = 0;
        const std::size_t crowdSize = plaza.value().characters().size();
        uint64_t churned = 0;
        for (int f = 1; f <= frames; ++f) {
            const double t = f / 60.0;
            // Churn: characters leave and identical ones join, round the crowd (the close-up's
            // character, number 0, stays).
            for (; crowdSize > 1 && double(churned) < o.churn * double(crowdSize) * t; ++churned)
                if (cc::Status s = plaza.value().respawn(*world, 1 + churned % (crowdSize - 1)); !s)
                    return fail("churn: " + s.message());
            if (cc::Status s = plaza.value().update(*world, t, scene.width, scene.height); !s) return fail(s.message());
            if (cc::Status s = world->step(1.0 / 60.0); !s) return fail("step: " + s.message());
            for (std::size_t i = 0; i < garments.size(); ++i) {
                auto gs = world->garmentStats(plaza.value().garments()[i]);
                if (!gs.isOk()) return fail(gs.status().message());
                garments[i] = gs.value();
            }
            const cc::FrameStats& stats = world->frameStats();
            summary.addFrame(f, stats);
            auto inView = crowd::garmentsInView(*world, plaza.value());
            if (!inView.isOk()) return fail(inView.status().message());
            if (cc::Status s = log.value().record(*world, f, t, scene.budgetMs, garments, inView.value()); !s)
                return fail(s.message());
            if (f % o.renderEvery == 0) {
                if (renderer) {
                    summary.addRenderedFrame();
                    const std::string png = (frameDir / numbered("png", summary.renderedFrames())).string();
                    if (cc::Status s = crowd::renderFrame(*world, plaza.value(), garments, o.colorBy, desc.pixelTolerance,
                                                          crowd::titleText(f, t, stats), *renderer, png);
                        !s)
                        return fail(s.message());
                }
                if (o.exportFormat != crowd::ExportFormat::None) {
                    const std::string file = (exportDir / numbered(exportExtension, ++exported)).string();
                    const cc::Status s = o.exportFormat == crowd::ExportFormat::Glb
                                             ? crowd::exportGlb(*world, plaza.value(), file)
                                             : crowd::exportObj(*world, plaza.value(), file);
                    if (!s) return fail(s.message());
                }
            }
            progress.update(f, stats.totalMs);
        }
    }

    if (renderer) outputs.frames = frameDir.string();
    if (o.exportFormat != crowd::ExportFormat::None) outputs.exportDir = exportDir.string();
    if (renderer && o.video && summary.renderedFrames() > 0) {
        const std::string mp4 = (out / "crowd.mp4").string();
        if (cc::Status s = crowd::encodeVideo(frameDir.string(), o.renderEvery, mp4); s) outputs.video = mp4;
        else std::fprintf(stderr, "video skipped: %s\n", s.message().c_str());
    }
    const std::string plot = (out / "summary.png").string();
    if (cc::Status s = crowd::plotSummary(outputs.framesCsv, plot); s) outputs.plot = plot;
    else std::fprintf(stderr, "summary.png skipped: %s\n", s.message().c_str());

    const uint32_t threads = world->frameStats().threads;
    summary.print(o, threads, outputs);
    const std::string summaryPath = (out / "summary.json").string();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (cc::Status s = summary.write(summaryPath, o, threads, wall, outputs); !s) return fail(s.message());
    std::printf("summary: %s (%.1f s wall)\n", summaryPath.c_str(), wall);
    return summary.failedUpdates() == 0 ? 0 : 3;
}

} // namespace

int main(int argc, char** argv) {
    RunOptions o;
    if (int code = crowd::parseCommandLine(argc, argv, o); code >= 0) return code;
    if (!o.writeScene.empty()) {
        if (cc::Status s = crowd::writeScene(o.scene, o.writeScene); !s) {
            std::fprintf(stderr, "%s\n", s.message().c_str());
            return 1;
        }
        std::printf("scene: %s\n", o.writeScene.c_str());
        return 0;
    }
    if (o.scaling) {
        cc::ShadowCheckDesc shadow;
        shadow.garments = uint32_t(o.shadow);
        shadow.windowSeconds = o.shadowWindow;
        return crowd::runScaling(o.scene.budgetMs, o.threads, shadow, o.errorTables);
    }
    if (o.tradeoff) return crowd::runTradeoff(o.out, o.scene.seconds);
    if (o.batch) return crowd::runBatchBench();
    if (o.snapshot) return crowd::runSnapshotStudy(o.scene.plaza.characters, o.threads);
    if (o.selfCollision) return crowd::runSelfCollisionStudy(o.scene.seconds);
    return runCrowd(o);
}

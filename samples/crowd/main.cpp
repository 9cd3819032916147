// crowd: the main job. A plaza of walking, running and standing mannequins wearing capes and
// skirts, seen by a moving camera; crowdcloth chooses each garment's level, solver and rate under
// a frame budget. Renders frames headless (OSMesa) to PNG, and to MP4 when ffmpeg is present;
// writes per-frame stats as JSON; prints a summary.
//
//   cc_crowd [--characters N] [--seconds S] [--out DIR] [--render-every K] [--no-render]
//            [--budget MS] [--threads T] [--width W] [--height H]
//            [--asset FILE]... [--clip NAME] [--asset-height M]
//            --asset dresses imported characters (any skinned file assimp reads; give several to
//            mix them) instead of the mannequins, in capes and skirts fitted to each; --clip picks
//            the clip they play (default: each file's first), --asset-height scales them all to
//            a standing height [m] (default: as authored)
//   cc_crowd --scaling   crowd scaling benchmark: 10 -> 1000 characters, with LOD and at full
//                        resolution, and the 1 -> 2 thread speed-up
//   cc_crowd --tradeoff  a cape on a walking mannequin at each uniform level against the finest:
//                        vertices, ms per step, RMS and max distance
//   cc_crowd --batch     256 capes at level 3 stepped one by one and in batches (BAR batch)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "Plaza.h"
#include "Studies.h"
#include "crowdcloth/World.h"
#include "crowdcloth/import/CharacterIO.h"
#include "crowdcloth/render/OffscreenRenderer.h"

namespace {

using crowd::percentile;
using crowd::WorldPtr;

struct Options {
    int characters = 200;
    double seconds = 10.0;
    std::string out = "crowd_out";
    int renderEvery = 4;
    bool render = true;
    double budgetMs = 12.0;
    int threads = 0;
    int width = 960, height = 540;
    bool scaling = false;
    bool tradeoff = false;
    bool batch = false;
    std::vector<std::string> assets;
    std::string clip;
    double assetHeight = 0.0;
};

bool parse(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&](const char* what) -> const char* {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "%s needs a value\n", what);
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--characters") o.characters = std::atoi(next("--characters"));
        else if (a == "--seconds") o.seconds = std::atof(next("--seconds"));
        else if (a == "--out") o.out = next("--out");
        else if (a == "--render-every") o.renderEvery = std::max(1, std::atoi(next("--render-every")));
        else if (a == "--no-render") o.render = false;
        else if (a == "--budget") o.budgetMs = std::atof(next("--budget"));
        else if (a == "--threads") o.threads = std::atoi(next("--threads"));
        else if (a == "--width") o.width = std::atoi(next("--width"));
        else if (a == "--height") o.height = std::atoi(next("--height"));
        else if (a == "--scaling") o.scaling = true;
        else if (a == "--tradeoff") o.tradeoff = true;
        else if (a == "--batch") o.batch = true;
        else if (a == "--asset") o.assets.push_back(next("--asset"));
        else if (a == "--clip") o.clip = next("--clip");
        else if (a == "--asset-height") o.assetHeight = std::atof(next("--asset-height"));
        else {
            std::fprintf(stderr, "unknown option '%s' (see the comment at the top of samples/crowd/main.cpp)\n", a.c_str());
            return false;
        }
    }
    if (o.characters < 1 || o.characters > 100000 || !(o.seconds > 0.0) || o.width < 16 || o.height < 16) {
        std::fprintf(stderr, "bad option value\n");
        return false;
    }
    return true;
}

void progress(int frame, int frames, double ms) {
    if (frame % 30 != 0 && frame != frames) return;
    const int width = 30, filled = frame * width / frames;
    std::fprintf(stderr, "\r[%.*s%*s] %3d%% frame %d/%d %6.2f ms", filled, "##############################",
                 width - filled, "", 100 * frame / frames, frame, frames, ms);
    if (frame == frames) std::fprintf(stderr, "\n");
}

const float kBodyColour[3] = {0.80f, 0.72f, 0.62f};

cc::Status renderFrame(cc::World& world, const crowd::Plaza& plaza, cc::render::OffscreenRenderer& renderer,
                       const std::string& path) {
    const float sky[3] = {0.78f, 0.84f, 0.90f};
    renderer.beginFrame(plaza.viewProjection(), sky);
    renderer.drawGround(float(plaza.extent() + 15.0), 2.0f);
    for (std::size_t i = 0; i < plaza.characters().size(); ++i) {
        auto body = world.characterMesh(plaza.characters()[i]);
        if (!body.isOk()) return body.status();
        const cc::RenderMeshView& b = body.value();
        renderer.drawMesh(b.positions, b.normals, b.vertexCount, b.indices, b.triangleCount,
                          cc::render::MeshStyle::body({kBodyColour[0], kBodyColour[1], kBodyColour[2]}));
        auto garment = world.renderMesh(plaza.garments()[i]);
        if (!garment.isOk()) return garment.status();
        const cc::RenderMeshView& g = garment.value();
        const auto& outside = plaza.garmentColours()[i];
        const cc::render::Rgb inside{0.6f * outside[0], 0.6f * outside[1], 0.6f * outside[2]};
        renderer.drawMesh(g.positions, g.normals, g.vertexCount, g.indices, g.triangleCount,
                          cc::render::MeshStyle::garment({outside[0], outside[1], outside[2]}, inside));
    }
    renderer.endFrame();
    return renderer.writePng(path);
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse(argc, argv, o)) return 2;
    if (o.scaling) return crowd::runScaling(o.budgetMs, o.threads);
    if (o.tradeoff) return crowd::runTradeoff();
    if (o.batch) return crowd::runBatchBench();

    cc::WorldDesc desc;
    desc.maxThreads = uint32_t(std::max(o.threads, 0));
    desc.frameBudgetMs = o.budgetMs;
    auto created = cc::World::create(desc);
    if (!created.isOk()) {
        std::fprintf(stderr, "%s\n", created.status().message().c_str());
        return 1;
    }
    WorldPtr world(created.value());
    crowd::PlazaSettings ps;
    ps.characters = o.characters;
    for (const std::string& file : o.assets) {
        auto character = cc::importCharacter(file);
        if (!character.isOk()) {
            std::fprintf(stderr, "%s\n", character.status().message().c_str());
            return 1;
        }
        cc::BodyDesc bd;
        bd.height = o.assetHeight;
        auto body = world->addCharacterBody(character.value(), bd);
        if (!body.isOk()) {
            std::fprintf(stderr, "%s: %s\n", file.c_str(), body.status().message().c_str());
            return 1;
        }
        ps.bodies.push_back(body.value());
        std::printf("%s: %zu joints, %zu vertices, %zu clips\n", file.c_str(), character.value().skeleton.jointCount(),
                    character.value().body.vertexCount(), character.value().clips.size());
    }
    ps.clip = o.clip;
    auto plaza = crowd::Plaza::create(*world, ps);
    if (!plaza.isOk()) {
        std::fprintf(stderr, "plaza: %s\n", plaza.status().message().c_str());
        return 1;
    }
    std::unique_ptr<cc::render::OffscreenRenderer> renderer;
    const std::filesystem::path out(o.out);
    std::filesystem::create_directories(out / "frames");
    if (o.render) {
        auto r = cc::render::OffscreenRenderer::create(o.width, o.height);
        if (!r.isOk()) {
            std::fprintf(stderr, "renderer: %s (rerun with --no-render)\n", r.status().message().c_str());
            return 1;
        }
        renderer = std::move(r).value();
    }

    const int frames = int(std::lround(o.seconds * 60.0));
    std::ofstream statsFile(out / "crowd_stats.json");
    statsFile << "[\n";
    std::vector<double> frameMs;
    uint32_t failed = 0, rendered = 0;
    std::vector<double> perLevel(16, 0.0);
    for (int f = 1; f <= frames; ++f) {
        if (cc::Status s = plaza.value().update(*world, f / 60.0, o.width, o.height); !s) {
            std::fprintf(stderr, "\n%s\n", s.message().c_str());
            return 1;
        }
        if (cc::Status s = world->step(1.0 / 60.0); !s) {
            std::fprintf(stderr, "\nstep: %s\n", s.message().c_str());
            return 1;
        }
        const cc::FrameStats& fs = world->frameStats();
        if (f > 60) frameMs.push_back(fs.totalMs);
        failed += fs.failed;
        for (int l = 0; l < 16; ++l) perLevel[l] += fs.garmentsPerLevel[l];
        statsFile << (f > 1 ? ",\n" : "") << world->statsJson();
        if (renderer && f % o.renderEvery == 0) {
            char name[64];
            std::snprintf(name, sizeof(name), "frame_%05d.png", ++rendered);
            if (cc::Status s = renderFrame(*world, plaza.value(), *renderer, (out / "frames" / name).string()); !s) {
                std::fprintf(stderr, "\n%s\n", s.message().c_str());
                return 1;
            }
        }
        progress(f, frames, fs.totalMs);
    }
    statsFile << "\n]\n";

    std::printf("crowd: %d characters, %d frames at 60 Hz, cloth budget %.1f ms, %u threads\n", o.characters, frames,
                o.budgetMs, world->frameStats().threads);
    std::printf("cloth ms per frame (after 1 s warm-up): median %.2f, p99 %.2f, max %.2f\n", percentile(frameMs, 0.5),
                percentile(frameMs, 0.99), percentile(frameMs, 1.0));
    std::printf("garments per level (mean over frames):");
    for (int l = 0; l < 8; ++l) std::printf(" L%d %.1f", l, perLevel[l] / frames);
    std::printf("\nfailed garment updates: %u\nstats: %s\n", failed, (out / "crowd_stats.json").string().c_str());
    if (renderer) {
        std::printf("frames: %u PNG in %s\n", rendered, (out / "frames").string().c_str());
        if (std::system("command -v ffmpeg > /dev/null 2>&1") == 0) {
            const std::string cmd = "ffmpeg -loglevel error -y -framerate " + std::to_string(60 / o.renderEvery) +
                                    " -i '" + (out / "frames" / "frame_%05d.png").string() +
                                    "' -vf pad=ceil(iw/2)*2:ceil(ih/2)*2 -pix_fmt yuv420p '" +
                                    (out / "crowd.mp4").string() + "'";
            if (std::system(cmd.c_str()) == 0) std::printf("video: %s\n", (out / "crowd.mp4").string().c_str());
        }
    }
    return failed == 0 ? 0 : 3;
}

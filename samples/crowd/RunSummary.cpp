#include "RunSummary.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "JsonText.h"
#include "Studies.h"

namespace crowd {

void RunSummary::addFrame(int frame, const cc::FrameStats& fs) {
    if (frame > warmUpFrames()) mFrameMs.push_back(fs.totalMs);
    for (std::size_t l = 0; l < mPerLevel.size(); ++l) mPerLevel[l] += fs.garmentsPerLevel[l];
    mUpdated += fs.updated;
    mVisible += fs.visible;
    mAsleep += fs.asleep;
    mFailed += fs.failed;
}

void RunSummary::print(const RunOptions& o, uint32_t threads, const Outputs& outputs) const {
    const Scene& s = o.scene;
    std::printf("crowd: %d characters, %d frames at 60 Hz, cloth budget %.1f ms, %u threads\n", s.plaza.characters,
                mFrames, s.budgetMs, threads);
    std::printf("cloth ms per frame (%s): median %.2f, p99 %.2f, max %.2f\n",
                warmUpFrames() > 0 ? "after 1 s warm-up" : "every frame", percentile(mFrameMs, 0.5),
                percentile(mFrameMs, 0.99), percentile(mFrameMs, 1.0));
    std::printf("garments per level (mean over frames):");
    for (int l = 0; l < int(mPerLevel.size()); ++l) std::printf(" L%d %.1f", l, meanLevel(l));
    std::printf("\ngarments per frame (mean): updated %.1f, visible %.1f, asleep %.1f\n", mUpdated / mFrames,
                mVisible / mFrames, mAsleep / mFrames);
    std::printf("failed garment updates: %u\n", mFailed);
    const auto line = [](const char* what, const std::string& path) {
        if (!path.empty()) std::printf("%s: %s\n", what, path.c_str());
    };
    if (!outputs.frames.empty()) std::printf("frames: %u PNG in %s\n", mRendered, outputs.frames.c_str());
    line("video", outputs.video);
    line("per-frame table", outputs.framesCsv);
    line("per-frame stats", outputs.frameStats);
    line("summary plot", outputs.plot);
    line("meshes", outputs.exportDir);
}

cc::Status RunSummary::write(const std::string& path, const RunOptions& o, uint32_t threads, double wallSeconds,
                             const Outputs& outputs) const {
    const Scene& s = o.scene;
    nlohmann::ordered_json levels = nlohmann::ordered_json::array();
    for (int l = 0; l < int(mPerLevel.size()); ++l) levels.push_back(meanLevel(l));
    const auto pathOrNull = [](const std::string& p) { return p.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(p); };
    const nlohmann::ordered_json summary = {
        {"scene", o.sceneFile.empty() ? "built-in" : o.sceneFile},
        {"characters", s.plaza.characters},
        {"seconds", s.seconds},
        {"frames", mFrames},
        {"threads", threads},
        {"budgetMs", s.budgetMs},
        {"warmUpFrames", warmUpFrames()},
        {"frameMs", {{"median", percentile(mFrameMs, 0.5)}, {"p99", percentile(mFrameMs, 0.99)}, {"max", percentile(mFrameMs, 1.0)}}},
        {"meanGarmentsPerLevel", levels},
        {"meanGarmentsUpdated", mUpdated / mFrames},
        {"meanGarmentsVisible", mVisible / mFrames},
        {"meanGarmentsAsleep", mAsleep / mFrames},
        {"failedUpdates", mFailed},
        {"renderedFrames", mRendered},
        {"viewport", {{"width", s.width}, {"height", s.height}, {"supersample", o.supersample}}},
        {"colorBy", colorByName(o.colorBy)},
        {"wallSeconds", wallSeconds},
        {"frameDir", pathOrNull(outputs.frames)},
        {"video", pathOrNull(outputs.video)},
        {"framesCsv", pathOrNull(outputs.framesCsv)},
        {"frameStats", pathOrNull(outputs.frameStats)},
        {"plot", pathOrNull(outputs.plot)},
        {"exportDir", pathOrNull(outputs.exportDir)}};
    std::ofstream out(path);
    out << prettyJson(summary);
    if (!out) return cc::Status::invalidArgument(path + ": cannot be written");
    return cc::Status::ok();
}

} // namespace crowd

#pragma once
// The run's totals: printed at the end and written to OUT/summary.json (small, for a person at a
// glance and for scripts).

#include <string>
#include <vector>

#include "CommandLine.h"
#include "crowdcloth/World.h"

namespace crowd {

class RunSummary {
public:
    explicit RunSummary(int frames) : mFrames(frames) {}
    void addFrame(int frame, const cc::FrameStats& stats);
    void addRenderedFrame() { ++mRendered; }
    uint32_t renderedFrames() const { return mRendered; }
    uint32_t failedUpdates() const { return mFailed; }

    /// What was written besides the summary (empty = not written).
    struct Outputs {
        std::string frames, video, frameStats, framesCsv, plot, exportDir;
    };
    void print(const RunOptions& options, uint32_t threads, const Outputs& outputs) const;
    cc::Status write(const std::string& path, const RunOptions& options, uint32_t threads, double wallSeconds,
                     const Outputs& outputs) const;

private:
    /// Frames before this are warm-up (levels and learned costs settling) and left out of the timings.
    int warmUpFrames() const { return mFrames >= 120 ? 60 : 0; }
    double meanLevel(int level) const { return mPerLevel[std::size_t(level)] / mFrames; }

    int mFrames;
    std::vector<double> mFrameMs;
    std::vector<double> mPerLevel = std::vector<double>(8, 0.0);
    double mUpdated = 0.0, mVisible = 0.0, mAsleep = 0.0;  // summed over frames
    uint32_t mFailed = 0, mRendered = 0;
};

} // namespace crowd

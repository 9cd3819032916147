#pragma once
// The programs the run hands its outputs to: ffmpeg for the video, Python's matplotlib for the
// summary plot. Each is run from an argument vector, never through a shell (paths may hold any
// character).

#include <string>
#include <vector>

#include "crowdcloth/core/Status.h"

namespace crowd {

/// Runs `argv[0]` (searched on PATH) and waits; returns its exit code, 127 when it cannot be started.
int runProgram(const std::vector<std::string>& argv);

/// Encodes frame_00001.png, frame_00002.png, ... in `frameDir` into an H.264 MP4 (yuv420p, padded
/// to an even size) at 60/renderEvery frames per second.
cc::Status encodeVideo(const std::string& frameDir, int renderEvery, const std::string& mp4Path);

/// Plots frames.csv into a PNG with scripts/plot-summary.py and /usr/bin/python3 (Debian's, which
/// has python3-matplotlib); the error says how to get them.
cc::Status plotSummary(const std::string& csvPath, const std::string& pngPath);
/// Plots tradeoff.csv (cost against error per scene, the front marked) with scripts/plot-tradeoff.py.
cc::Status plotTradeoff(const std::string& csvPath, const std::string& pngPath);

} // namespace crowd

#include "Progress.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <unistd.h>

namespace crowd {
namespace {

std::string minutesSeconds(double seconds) {
    const int s = int(std::lround(seconds)); // elapsed and ETA are never negative
    char text[32];
    std::snprintf(text, sizeof(text), "%d:%02d", s / 60, s % 60);
    return text;
}

} // namespace

Progress::Progress(int frames)
    : mFrames(frames), mTerminal(isatty(STDERR_FILENO) != 0), mStart(std::chrono::steady_clock::now()),
      mLastDraw(mStart) {}

void Progress::update(int frame, double clothMs) {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - mStart).count();
    const double eta = elapsed / frame * (mFrames - frame);
    const bool last = frame == mFrames;
    if (mTerminal) {
        // Redraw at most 10 times a second: the bar must not cost what it measures.
        if (!last && now - mLastDraw < std::chrono::milliseconds(100)) return;
        mLastDraw = now;
        const int width = 30, filled = int(long(frame) * width / mFrames);
        std::fprintf(stderr, "\r[%s%s] %3d%% frame %d/%d  cloth %6.2f ms  elapsed %s  ETA %s ",
                     std::string(std::size_t(filled), '#').c_str(), std::string(std::size_t(width - filled), ' ').c_str(),
                     int(100L * frame / mFrames), frame, mFrames, clothMs, minutesSeconds(elapsed).c_str(),
                     minutesSeconds(eta).c_str());
        if (last) std::fprintf(stderr, "\n");
        return;
    }
    if (long(frame) * 10 < long(mNextTenth) * mFrames && !last) return;
    while (long(mNextTenth) * mFrames <= long(frame) * 10) ++mNextTenth;
    std::fprintf(stderr, "progress: %3d%% frame %d/%d, cloth %.2f ms, elapsed %s, ETA %s\n", int(100L * frame / mFrames),
                 frame, mFrames, clothMs, minutesSeconds(elapsed).c_str(), minutesSeconds(eta).c_str());
}

} // namespace crowd

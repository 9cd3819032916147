#pragma once
// Progress of the run on stderr: a bar with an ETA on a terminal, a plain line every 10 % otherwise
// (CI logs keep every line, so redrawing a bar there would only add noise).

#include <chrono>

namespace crowd {

class Progress {
public:
    explicit Progress(int frames);
    /// After frame `frame` (1-based) whose cloth took `clothMs`.
    void update(int frame, double clothMs);

private:
    int mFrames;
    bool mTerminal;
    int mNextTenth = 1;
    std::chrono::steady_clock::time_point mStart, mLastDraw;
};

} // namespace crowd

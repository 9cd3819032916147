// The update step: whole frames at a fixed rate, a shared grid otherwise (issue 9: garments share
// factors whatever the frame times).
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "UpdateStep.h"

namespace cc::detail {
namespace {

TEST(UpdateStep, WholeFramesAtAFixedRateAreExactlyFramesTimesDt) {
    // Elapsed times as a World forms them: differences of a clock summed from frame times, late in
    // a long session, where their last bits differ from n * dt.
    const double dt = 1.0 / 60.0;
    double clock = 0.0;
    for (int f = 0; f < 60 * 3600; ++f) clock += dt;  // an hour
    for (int n = 1; n <= 16; ++n) {
        double later = clock;
        for (int k = 0; k < n; ++k) later += dt;
        const double elapsed = later - clock;
        EXPECT_NE(elapsed, n * dt) << "the test needs drifted bits (n = " << n << ")";
        EXPECT_EQ(updateStep(elapsed, dt), n * dt) << n << " frames";
    }
}

TEST(UpdateStep, JitteredFramesShareAFewGridSteps) {
    // A host whose frame times jitter by +-3 %: every elapsed time within 0.55 % of its step, and
    // all of them on a handful of steps (a factor each), not one per frame.
    const double nominal = 1.0 / 60.0;
    std::set<double> steps;
    for (int f = 0; f < 1000; ++f) {
        const double elapsed = nominal * (1.0 + 0.03 * std::sin(0.7 * f));
        const double step = updateStep(elapsed, nominal);
        EXPECT_NEAR(step / elapsed, 1.0, 0.0055) << "frame " << f;
        steps.insert(step);
    }
    EXPECT_LE(steps.size(), 8u);  // +-3 % spans 6 %, 5.5 grid spacings: 7 grid steps and the frame itself
}

} // namespace
} // namespace cc::detail

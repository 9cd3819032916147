// The overlay palette: the heat ramp's ends and clamping, distinct level and solver colours.
#include <gtest/gtest.h>

#include <cmath>

#include "crowdcloth/render/Palette.h"

namespace cc::render {
namespace {

float distance(const Rgb& a, const Rgb& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

float luminance(const Rgb& c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

TEST(Palette, HeatRampRunsFromDarkBlueThroughGreenToDarkRed) {
    const Rgb cold = heatColour(0.0), middle = heatColour(0.5), hot = heatColour(1.0);
    EXPECT_GT(cold[2], cold[0]) << "cold end is blue";
    EXPECT_GT(hot[0], hot[2]) << "hot end is red";
    EXPECT_GT(middle[1], 0.9f) << "middle is bright green-yellow";
    EXPECT_GT(luminance(middle), luminance(cold));
    EXPECT_GT(luminance(middle), luminance(hot));
}

TEST(Palette, HeatRampClampsAndIsContinuous) {
    EXPECT_EQ(heatColour(-3.0), heatColour(0.0));
    EXPECT_EQ(heatColour(7.0), heatColour(1.0));
    for (int i = 0; i < 1000; ++i)
        EXPECT_LT(distance(heatColour(i / 1000.0), heatColour((i + 1) / 1000.0)), 0.01f) << "jump at t = " << i / 1000.0;
}

TEST(Palette, LevelsAndSolversHaveDistinctColours) {
    for (int a = 0; a < 5; ++a)
        for (int b = a + 1; b < 5; ++b) EXPECT_GT(distance(levelColour(a), levelColour(b)), 0.2f) << a << " vs " << b;
    for (int a = 0; a < 8; ++a)
        for (int b = a + 1; b < 8; ++b) EXPECT_GT(distance(solverColour(a), solverColour(b)), 0.2f) << a << " vs " << b;
    EXPECT_EQ(levelColour(9), levelColour(4)) << "levels past the palette repeat its coarsest colour";
    EXPECT_EQ(solverColour(8), solverColour(0));
}

} // namespace
} // namespace cc::render

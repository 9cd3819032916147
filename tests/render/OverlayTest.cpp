// The title strip and text overlay: drawn where asked, over the scene, nowhere else.
#include "RenderScene.h"

namespace cc::render::test {
namespace {

constexpr int kWidth = 320, kHeight = 120;
const float kGreyBackground[3] = {0.5f, 0.5f, 0.5f};

struct Counts {
    int darker = 0, brighter = 0, unchanged = 0;
};

// Pixels in rows [top, bottom) compared with the background's grey 128.
Counts countRows(const OffscreenRenderer& r, int top, int bottom) {
    Counts c;
    for (int y = top; y < bottom; ++y)
        for (int x = 0; x < r.width(); ++x) {
            const int red = pixel(r, {x, y})[0];
            if (red < 118) ++c.darker;
            else if (red > 138) ++c.brighter;
            else ++c.unchanged;
        }
    return c;
}

std::unique_ptr<OffscreenRenderer> frameWithBackgroundOnly() {
    auto r = makeRenderer(kWidth, kHeight, {});
    if (!r) return r;
    const Camera camera({0.0, 1.0, 5.0}, {0.0, 0.0, 0.0}, kWidth, kHeight);
    r->beginFrame(camera.viewProjection, kGreyBackground);
    return r;
}

TEST(Overlay, TitleStripIsADarkBandWithLightTextAcrossTheTop) {
    auto r = frameWithBackgroundOnly();
    ASSERT_TRUE(r);
    r->drawTitleStrip("frame 120  3.4 ms  200 garments  L0 120 L1 50", 2.0f);
    r->endFrame();
    const int stripHeight = 32;  // (12 font pixels + 4 margin) x scale 2
    const Counts strip = countRows(*r, 0, stripHeight);
    EXPECT_GT(strip.darker, kWidth * stripHeight / 2) << "the strip darkens the frame's top";
    EXPECT_GT(strip.brighter, 200) << "the text is lighter than the background";
    EXPECT_EQ(strip.unchanged, 0) << "every strip pixel is either strip or text";
    const Counts below = countRows(*r, stripHeight + 1, kHeight);
    EXPECT_EQ(below.darker + below.brighter, 0) << "nothing is drawn below the strip";
}

TEST(Overlay, TextIsDrawnAtItsPositionInItsColour) {
    auto r = frameWithBackgroundOnly();
    ASSERT_TRUE(r);
    r->drawText(100.0f, 60.0f, "L3", {1.0f, 1.0f, 1.0f}, 3.0f);
    r->endFrame();
    EXPECT_EQ(countRows(*r, 0, 60).brighter, 0) << "nothing above the text's top";
    EXPECT_GT(countRows(*r, 60, 60 + 36).brighter, 50) << "the text's glyphs";
    EXPECT_EQ(countRows(*r, 60 + 36, kHeight).brighter, 0) << "nothing below the text's line";
}

} // namespace
} // namespace cc::render::test

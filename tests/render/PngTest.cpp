// writePng writes the frame losslessly (stb_image reads the same pixels back) and reports failure.
#include "RenderScene.h"

#include <algorithm>
#include <cstdio>

#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

namespace cc::render::test {
namespace {

TEST(Png, WrittenFrameReadsBackPixelForPixel) {
    RendererOptions o;
    o.supersample = 2;
    auto r = makeRenderer(48, 32, o);
    ASSERT_TRUE(r);
    const Camera camera({0.0, 3.0, 4.0}, {0.0, 0.0, 0.0}, 48, 32);
    const float sky[3] = {0.7f, 0.8f, 0.9f};
    r->beginFrame(camera.viewProjection, sky);
    r->drawGround(5.0f, 1.0f);
    facingPlusZ({0.0f, 0.8f, 0.0f}, 0.5f).draw(*r, MeshStyle::garment({0.8f, 0.2f, 0.2f}, {0.2f, 0.2f, 0.8f}));
    r->drawTitleStrip("png", 1.0f);
    r->endFrame();
    const std::string path = ::testing::TempDir() + "cc_render_roundtrip.png";
    ASSERT_TRUE(r->writePng(path).isOk());
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
    ASSERT_NE(data, nullptr) << "stb_image could not read " << path << ": " << stbi_failure_reason();
    EXPECT_EQ(w, 48);
    EXPECT_EQ(h, 32);
    EXPECT_TRUE(std::equal(r->image().begin(), r->image().end(), data)) << "pixels differ after the round trip";
    for (std::size_t i = 3; i < r->image().size(); i += 4)
        ASSERT_EQ(r->image()[i], 255) << "the frame is opaque, also under shadows and the strip (byte " << i << ")";
    stbi_image_free(data);
    std::remove(path.c_str());
}

TEST(Png, UnwritablePathIsAnError) {
    auto r = makeRenderer(8, 8, {});
    ASSERT_TRUE(r);
    const Status s = r->writePng("/nonexistent-directory/frame.png");
    EXPECT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("/nonexistent-directory/frame.png"), std::string::npos) << s.message();
}

} // namespace
} // namespace cc::render::test

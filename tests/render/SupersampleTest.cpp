// Anti-aliasing by supersampling: a slanted edge gets intermediate colours only when supersampled.
#include "RenderScene.h"

namespace cc::render::test {
namespace {

constexpr int kSize = 96;
const float kBlack[3] = {0.0f, 0.0f, 0.0f};

// Pixels strictly between the black background and the white quad.
int intermediatePixels(int supersample) {
    RendererOptions o;
    o.supersample = supersample;
    o.ambient = 1.0f;  // unshaded white, so only coverage makes a pixel grey
    o.diffuse = 0.0f;
    auto r = makeRenderer(kSize, kSize, o);
    if (!r) return -1;
    // Rolled camera: the quad's edges cross pixel rows and columns at a slant.
    double vp[16];
    lookAt({0.0, 0.0, 4.0}, {0.0, 0.0, 0.0}, 1.0, vp, 40.0, 0.1, 100.0);
    const Eigen::Matrix4d roll = Eigen::Affine3d(Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitZ())).matrix();
    Eigen::Map<Eigen::Matrix4d> viewProjection(vp);
    viewProjection = Eigen::Matrix4d(viewProjection * roll);
    r->beginFrame(vp, kBlack);
    facingPlusZ({0.0f, 0.0f, 0.0f}, 0.7f).draw(*r, MeshStyle::body({1.0f, 1.0f, 1.0f}));
    r->endFrame();
    int count = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const int red = pixel(*r, {x, y})[0];
            if (red > 20 && red < 235) ++count;
        }
    return count;
}

TEST(Supersample, WithoutSupersamplingEveryPixelIsBackgroundOrQuad) {
    EXPECT_EQ(intermediatePixels(1), 0);
}

TEST(Supersample, TwoByTwoGivesTheEdgesIntermediateColours) {
    // The quad's outline is about 4 x 45 pixels long; most edge pixels are partly covered.
    EXPECT_GT(intermediatePixels(2), 90);
}

TEST(Supersample, FactorOutsideOneToFourIsRejected) {
    RendererOptions o;
    o.supersample = 5;
    auto r = OffscreenRenderer::create(16, 16, o);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("supersample"), std::string::npos) << r.status().message();
}

} // namespace
} // namespace cc::render::test

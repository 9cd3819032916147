// Ground shadows from the directional light: where they must fall, where they must not, and that
// overlapping shadows darken once.
#include "RenderScene.h"

namespace cc::render::test {
namespace {

constexpr int kWidth = 160, kHeight = 120;
const float kSky[3] = {0.7f, 0.8f, 0.9f};
const Rgb kGrey{0.6f, 0.6f, 0.6f};

// Light at 45 degrees along +x: a point at height h casts its shadow h metres towards -x.
RendererOptions sunAlongX() {
    RendererOptions o;
    o.lightDirection = {1.0f, 1.0f, 0.0f};
    return o;
}

Rgb inShadow(const RendererOptions& o) {
    const float keep = 1.0f - o.shadowDarkening;
    return {o.groundColour[0] * keep, o.groundColour[1] * keep, o.groundColour[2] * keep};
}

const Camera kCamera({0.0, 6.0, 5.0}, {0.0, 0.0, 0.0}, kWidth, kHeight);

TEST(Shadow, QuadAboveTheGroundShadowsTheGroundAlongTheLight) {
    const RendererOptions o = sunAlongX();
    auto r = makeRenderer(kWidth, kHeight, o);
    ASSERT_TRUE(r);
    r->beginFrame(kCamera.viewProjection, kSky);
    r->drawGround(20.0f, 40.0f);
    facingUp({0.0f, 1.0f, 0.0f}, 0.5f).draw(*r, MeshStyle::body(kGrey));  // shadow: x in [-1.5, -0.5]
    r->endFrame();
    // Neither point is hidden behind the quad from this camera.
    expectNear(pixel(*r, kCamera.pixelOf({-1.0, 0.0, 0.0})), toBytes(inShadow(o)), 3, "where the shadow falls");
    expectNear(pixel(*r, kCamera.pixelOf({1.5, 0.0, 0.0})), toBytes(o.groundColour), 1, "on the lit side");
    expectNear(pixel(*r, kCamera.pixelOf({-1.0, 0.0, 1.2})), toBytes(o.groundColour), 1, "beside the shadow");
}

TEST(Shadow, OverlappingShadowsDarkenOnce) {
    const RendererOptions o = sunAlongX();
    auto r = makeRenderer(kWidth, kHeight, o);
    ASSERT_TRUE(r);
    r->beginFrame(kCamera.viewProjection, kSky);
    r->drawGround(20.0f, 40.0f);
    facingUp({0.0f, 1.0f, 0.0f}, 0.5f).draw(*r, MeshStyle::body(kGrey));
    facingUp({0.5f, 1.5f, 0.0f}, 0.5f).draw(*r, MeshStyle::body(kGrey));  // its shadow is centred at x = -1 too
    r->endFrame();
    expectNear(pixel(*r, kCamera.pixelOf({-1.0, 0.0, 0.0})), toBytes(inShadow(o)), 3, "under both shadows");
}

TEST(Shadow, MeshThatCastsNoShadowLeavesTheGroundLit) {
    const RendererOptions o = sunAlongX();
    auto r = makeRenderer(kWidth, kHeight, o);
    ASSERT_TRUE(r);
    MeshStyle style = MeshStyle::body(kGrey);
    style.castsShadow = false;
    r->beginFrame(kCamera.viewProjection, kSky);
    r->drawGround(20.0f, 40.0f);
    facingUp({0.0f, 1.0f, 0.0f}, 0.5f).draw(*r, style);
    r->endFrame();
    expectNear(pixel(*r, kCamera.pixelOf({-1.0, 0.0, 0.0})), toBytes(o.groundColour), 1, "no shadow");
}

TEST(Shadow, LightFromBelowTheHorizonIsRejected) {
    RendererOptions o;
    o.lightDirection = {1.0f, 0.0f, 0.0f};
    auto r = OffscreenRenderer::create(16, 16, o);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("lightDirection"), std::string::npos) << r.status().message();
}

} // namespace
} // namespace cc::render::test

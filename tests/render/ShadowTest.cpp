// Ground shadows from the directional light: where they must fall, where they must not, and that
// overlapping shadows darken once.
#include "RenderScene.h"

#include <initializer_list>

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

// The ground (grid lines only at its border) with `quads` drawn on it in order, seen by kCamera.
std::unique_ptr<OffscreenRenderer> render(const RendererOptions& o, std::initializer_list<Quad> quads,
                                          const MeshStyle& style = MeshStyle::body(kGrey)) {
    auto r = makeRenderer(kWidth, kHeight, o);
    if (!r) return r;
    r->beginFrame(kCamera.viewProjection, kSky);
    r->drawGround(20.0f, 40.0f);
    for (const Quad& q : quads) q.draw(*r, style);
    r->endFrame();
    return r;
}

const Quad kCaster = facingUp({0.0f, 1.0f, 0.0f}, 0.5f);  // its shadow: x in [-1.5, -0.5], z in [-0.5, 0.5]

TEST(Shadow, QuadAboveTheGroundShadowsTheGroundAlongTheLight) {
    const RendererOptions o = sunAlongX();
    auto r = render(o, {kCaster});
    ASSERT_TRUE(r);
    // None of these points is hidden behind the quad from this camera.
    expectNear(pixel(*r, kCamera.pixelOf({-1.0, 0.0, 0.0})), toBytes(inShadow(o)), 3, "where the shadow falls");
    expectNear(pixel(*r, kCamera.pixelOf({1.5, 0.0, 0.0})), toBytes(o.groundColour), 1, "on the lit side");
    expectNear(pixel(*r, kCamera.pixelOf({-1.0, 0.0, 1.2})), toBytes(o.groundColour), 1, "beside the shadow");
}

TEST(Shadow, OverlappingShadowsDarkenOnce) {
    const RendererOptions o = sunAlongX();
    auto r = render(o, {kCaster, facingUp({0.5f, 1.5f, 0.0f}, 0.5f)});  // both shadows centred at x = -1
    ASSERT_TRUE(r);
    expectNear(pixel(*r, kCamera.pixelOf({-1.0, 0.0, 0.0})), toBytes(inShadow(o)), 3, "under both shadows");
}

TEST(Shadow, ShadowDoesNotShowThroughAMeshDrawnBeforeIt) {
    const RendererOptions o = sunAlongX();
    const Quad wall = facingPlusZ({-0.7f, 1.8f, 1.5f}, 0.4f);  // hangs between the camera and the shadow
    auto wallOnly = render(o, {wall});
    auto wallThenCaster = render(o, {wall, kCaster});
    ASSERT_TRUE(wallOnly && wallThenCaster);
    const auto at = kCamera.pixelOf({-1.0, 0.0, 0.0});
    ASSERT_NE(pixel(*wallOnly, at), toBytes(o.groundColour)) << "the wall must hide the shadow's centre";
    expectNear(pixel(*wallThenCaster, at), pixel(*wallOnly, at), 0, "the wall in front of the shadow");
}

TEST(Shadow, MeshThatCastsNoShadowLeavesTheGroundLit) {
    const RendererOptions o = sunAlongX();
    MeshStyle style = MeshStyle::body(kGrey);
    style.castsShadow = false;
    auto r = render(o, {kCaster}, style);
    ASSERT_TRUE(r);
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

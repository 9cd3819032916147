// Lambert shading of lit quads: a garment's front and back colours, a body's single lit side, and
// the ground away from objects.
#include "RenderScene.h"

namespace cc::render::test {
namespace {

constexpr int kSize = 64;
const float kBlack[3] = {0.0f, 0.0f, 0.0f};
const Rgb kFront{0.8f, 0.3f, 0.2f};
const Rgb kBack{0.2f, 0.7f, 0.3f};

RendererOptions lightFrom(const Rgb& direction) {
    RendererOptions o;
    o.lightDirection = direction;
    o.ambient = 0.3f;
    o.diffuse = 0.6f;
    return o;
}

Rgb lambert(const Rgb& colour, const RendererOptions& o, float nDotL) {
    const float shade = o.ambient + o.diffuse * std::max(nDotL, 0.0f);
    return {colour[0] * shade, colour[1] * shade, colour[2] * shade};
}

// The quad z = 0 facing +z seen from (0, 0, eyeZ); returns its centre pixel.
std::array<int, 3> centreOfQuadSeenFrom(double eyeZ, const RendererOptions& o, const MeshStyle& style) {
    auto r = makeRenderer(kSize, kSize, o);
    if (!r) return {-1, -1, -1};
    const Camera camera({0.0, 0.0, eyeZ}, {0.0, 0.0, 0.0}, kSize, kSize);
    r->beginFrame(camera.viewProjection, kBlack);
    facingPlusZ({0.0f, 0.0f, 0.0f}, 1.0f).draw(*r, style);
    r->endFrame();
    return pixel(*r, camera.pixelOf({0.0, 0.0, 0.0}));
}

TEST(Shading, GarmentFrontIsLambertShadedInItsFrontColour) {
    const RendererOptions o = lightFrom({0.0f, 0.6f, 0.8f});  // n . l = 0.8 on the front
    expectNear(centreOfQuadSeenFrom(3.0, o, MeshStyle::garment(kFront, kBack)), toBytes(lambert(kFront, o, 0.8f)), 3,
               "front of the garment");
}

TEST(Shading, GarmentBackIsLitWithTheFlippedNormalInItsBackColour) {
    const RendererOptions o = lightFrom({0.0f, 0.6f, -0.8f});  // lights the back: -n . l = 0.8
    expectNear(centreOfQuadSeenFrom(-3.0, o, MeshStyle::garment(kFront, kBack)), toBytes(lambert(kBack, o, 0.8f)), 3,
               "back of the garment");
}

TEST(Shading, BodyBackFaceIsNotLitFromBehind) {
    // One-sided: the back face keeps the front normal, which faces away from this light.
    const RendererOptions o = lightFrom({0.0f, 0.6f, -0.8f});
    expectNear(centreOfQuadSeenFrom(-3.0, o, MeshStyle::body(kFront)), toBytes(lambert(kFront, o, 0.0f)), 3,
               "back of a body");
}

TEST(Shading, GroundFarFromObjectsHasTheGroundColour) {
    const RendererOptions o = lightFrom({0.3f, 1.0f, 0.5f});
    auto r = makeRenderer(kSize, kSize, o);
    ASSERT_TRUE(r);
    const Camera camera({0.0, 4.0, 6.0}, {0.0, 0.0, 0.0}, kSize, kSize);
    r->beginFrame(camera.viewProjection, kBlack);
    r->drawGround(20.0f, 40.0f);  // grid lines only at the border
    facingPlusZ({0.0f, 1.0f, 0.0f}, 0.5f).draw(*r, MeshStyle::body(kFront));
    r->endFrame();
    expectNear(pixel(*r, camera.pixelOf({2.5, 0.0, 2.0})), toBytes(o.groundColour), 1, "open ground");
}

} // namespace
} // namespace cc::render::test

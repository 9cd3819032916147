#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "crowdcloth/core/Status.h"
#include "crowdcloth/render/Rgb.h"

namespace cc::render {

/// How a renderer lights and samples its frames; fixed for the renderer's lifetime.
struct RendererOptions {
    /// Samples per pixel along each axis: the frame is drawn at supersample x the size and
    /// box-filtered down (OSMesa has no MSAA). 1 (no anti-aliasing) to 4.
    int supersample = 1;
    /// Direction towards the directional light (normalised by create); y > 0 so it casts ground shadows.
    Rgb lightDirection{0.3f, 1.0f, 0.5f};
    /// Lambert shading: colour * (ambient + diffuse * max(0, n . l)), clamped to 1.
    float ambient = 0.55f;
    float diffuse = 0.75f;
    Rgb groundColour{0.55f, 0.55f, 0.50f};
    Rgb gridColour{0.45f, 0.45f, 0.42f};
    /// Fraction of the ground colour a shadow takes away, in [0, 1].
    float shadowDarkening = 0.45f;
};

/// How one mesh is shaded.
struct MeshStyle {
    Rgb front{};
    /// Colour of the back faces; used only when twoSided.
    Rgb back{};
    /// Cloth: back faces are lit with the flipped normal and shaded in `back`. Otherwise (bodies)
    /// only the front side is lit, as for a closed surface.
    bool twoSided = false;
    bool castsShadow = true;

    static MeshStyle body(const Rgb& colour) { return {colour, colour, false, true}; }
    static MeshStyle garment(const Rgb& outside, const Rgb& inside) { return {outside, inside, true, true}; }
};

/// A headless renderer for samples and tests: Mesa's OSMesa software rasteriser, fixed-function
/// OpenGL with one directional light, into an RGBA image that can be written as PNG.
/// One renderer per thread (OSMesa contexts are current per thread).
///
///   RendererOptions options;
///   options.supersample = 2;
///   auto r = OffscreenRenderer::create(1280, 720, options).value();
///   r->beginFrame(viewProjection, {0.8f, 0.85f, 0.9f});
///   r->drawGround(50.0f, 2.0f);                         // first: shadows fall on it
///   r->drawMesh(positions, normals, vertexCount, indices, triangleCount, MeshStyle::body(skin));
///   r->drawMesh(..., MeshStyle::garment(red, darkRed));
///   r->drawTitleStrip("frame 120  3.4 ms  200 garments");  // last: drawn over the scene
///   r->endFrame();
///   r->writePng("frame.png");
class OffscreenRenderer {
public:
    static Result<std::unique_ptr<OffscreenRenderer>> create(int width, int height,
                                                             const RendererOptions& options = {});
    ~OffscreenRenderer();
    OffscreenRenderer(const OffscreenRenderer&) = delete;
    OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

    /// Clears to `background` (RGB in [0, 1]) and sets the camera (column-major, OpenGL clip).
    void beginFrame(const double viewProjection[16], const float background[3]);
    /// A ground grid at y = 0 over [-extent, extent]^2 [m]. Draw it before the meshes: a mesh's
    /// shadow is laid onto the ground as the mesh is drawn.
    void drawGround(float extent, float spacing);
    /// Triangles (xyz floats, unit normals, 3 indices each); the arrays need only outlive the call.
    /// Its shadow (style.castsShadow) is laid on the ground drawn so far, right away.
    void drawMesh(const float* positions, const float* normals, uint32_t vertexCount, const uint32_t* indices,
                  uint32_t triangleCount, const MeshStyle& style);
    /// The same in one colour on both sides, lit from both sides, casting a shadow.
    void drawMesh(const float* positions, const float* normals, uint32_t vertexCount, const uint32_t* indices,
                  uint32_t triangleCount, const float color[3]);
    /// ASCII text with its top-left corner at (x, y) image pixels (y down), `scale` pixels per font
    /// pixel (the font is 12 font pixels per line). Drawn over everything drawn so far.
    void drawText(float x, float y, const std::string& text, const Rgb& colour, float scale = 2.0f);
    /// A semi-transparent dark strip across the top of the frame with `text` in white on it.
    void drawTitleStrip(const std::string& text, float scale = 2.0f);
    /// Finishes the frame; the image is then readable.
    void endFrame();

    int width() const { return mWidth; }
    int height() const { return mHeight; }
    /// RGBA, top row first.
    const std::vector<uint8_t>& image() const { return mImage; }
    Status writePng(const std::string& path) const;

private:
    OffscreenRenderer() = default;
    void drawShadow(uint32_t triangleCount);
    struct Context;
    std::unique_ptr<Context> mContext;
    RendererOptions mOptions;
    int mWidth = 0, mHeight = 0;
    std::vector<uint8_t> mSamples;  // OSMesa's framebuffer at supersample x the size (bottom row first)
    std::vector<uint8_t> mImage;
};

} // namespace cc::render

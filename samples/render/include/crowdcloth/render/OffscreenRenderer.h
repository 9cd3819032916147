#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "crowdcloth/core/Status.h"

namespace cc::render {

/// A headless renderer for samples and tests: Mesa's OSMesa software rasteriser, fixed-function
/// OpenGL with one directional light, into an RGBA image that can be written as PNG.
/// One renderer per thread (OSMesa contexts are current per thread).
///
///   auto r = OffscreenRenderer::create(1280, 720).value();
///   r->beginFrame(viewProjection, {0.8f, 0.85f, 0.9f});
///   r->drawMesh(positions, normals, vertexCount, indices, triangleCount, {0.7f, 0.2f, 0.2f});
///   r->endFrame();
///   r->writePng("frame.png");
class OffscreenRenderer {
public:
    static Result<std::unique_ptr<OffscreenRenderer>> create(int width, int height);
    ~OffscreenRenderer();
    OffscreenRenderer(const OffscreenRenderer&) = delete;
    OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

    /// Clears to `background` (RGB in [0, 1]) and sets the camera (column-major, OpenGL clip).
    void beginFrame(const double viewProjection[16], const float background[3]);
    /// A ground grid at y = 0 over [-extent, extent]^2 [m].
    void drawGround(float extent, float spacing);
    /// Triangles (xyz floats, unit normals, 3 indices each) in `color` (RGB), lit from above.
    void drawMesh(const float* positions, const float* normals, uint32_t vertexCount, const uint32_t* indices,
                  uint32_t triangleCount, const float color[3]);
    /// Finishes the frame; the image is then readable.
    void endFrame();

    int width() const { return mWidth; }
    int height() const { return mHeight; }
    /// RGBA, top row first.
    const std::vector<uint8_t>& image() const { return mFlipped; }
    Status writePng(const std::string& path) const;

private:
    OffscreenRenderer() = default;
    struct Context;
    std::unique_ptr<Context> mContext;
    int mWidth = 0, mHeight = 0;
    std::vector<uint8_t> mBuffer;   // OSMesa's framebuffer (bottom row first)
    std::vector<uint8_t> mFlipped;
};

} // namespace cc::render

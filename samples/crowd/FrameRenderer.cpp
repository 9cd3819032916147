#include "FrameRenderer.h"

#include <algorithm>
#include <cstdio>

#include "crowdcloth/render/Palette.h"

namespace crowd {
namespace {

const cc::render::Rgb kBodyColour{0.80f, 0.72f, 0.62f};
const float kSky[3] = {0.78f, 0.84f, 0.90f};
constexpr float kInsideShade = 0.6f;  // a garment's inside is this much of its outside colour

cc::render::Rgb outsideColour(const Plaza& plaza, std::size_t i, const cc::GarmentStats& stats, ColorBy colorBy,
                              double pixelTolerance) {
    switch (colorBy) {
    case ColorBy::Lod: return cc::render::levelColour(stats.level);
    case ColorBy::Solver: return cc::render::solverColour(int(stats.solver));
    case ColorBy::Error: return cc::render::heatColour(stats.predictedErrorPx / pixelTolerance);
    case ColorBy::None: break;
    }
    const auto& c = plaza.garmentColours()[i];
    return {c[0], c[1], c[2]};
}

} // namespace

std::string titleText(int frame, double time, const cc::FrameStats& fs) {
    char head[160];
    std::snprintf(head, sizeof(head), "frame %d  t %.2f s  cloth %.1f ms  %u garments: %u updated %u visible %u asleep ",
                  frame, time, fs.totalMs, fs.garments, fs.updated, fs.visible, fs.asleep);
    std::string text = head;
    for (int l = 0; l < 16; ++l)
        if (fs.garmentsPerLevel[l] > 0) text += " L" + std::to_string(l) + ":" + std::to_string(fs.garmentsPerLevel[l]);
    return text;
}

cc::Status renderFrame(cc::World& world, const Plaza& plaza, const std::vector<cc::GarmentStats>& garments,
                       ColorBy colorBy, double pixelTolerance, const std::string& title,
                       cc::render::OffscreenRenderer& renderer, const std::string& pngPath) {
    renderer.beginFrame(plaza.viewProjection(), kSky);
    renderer.drawGround(float(plaza.extent() + 15.0), 2.0f);  // first: the meshes' shadows fall on it
    for (std::size_t i = 0; i < plaza.characters().size(); ++i) {
        auto body = world.characterMesh(plaza.characters()[i]);
        if (!body.isOk()) return body.status();
        const cc::RenderMeshView& b = body.value();
        renderer.drawMesh(b.positions, b.normals, b.vertexCount, b.indices, b.triangleCount,
                          cc::render::MeshStyle::body(kBodyColour));
        auto garment = world.renderMesh(plaza.garments()[i]);
        if (!garment.isOk()) return garment.status();
        const cc::RenderMeshView& g = garment.value();
        const cc::render::Rgb outside = outsideColour(plaza, i, garments[i], colorBy, pixelTolerance);
        const cc::render::Rgb inside{kInsideShade * outside[0], kInsideShade * outside[1], kInsideShade * outside[2]};
        renderer.drawMesh(g.positions, g.normals, g.vertexCount, g.indices, g.triangleCount,
                          cc::render::MeshStyle::garment(outside, inside));
    }
    // The font is about 6 font pixels per character: shrink the strip's text to fit the width.
    const float scale = std::clamp(float(renderer.width()) / (6.5f * float(title.size() + 2)), 1.0f, 2.0f);
    renderer.drawTitleStrip(title, scale);
    renderer.endFrame();
    return renderer.writePng(pngPath);
}

} // namespace crowd

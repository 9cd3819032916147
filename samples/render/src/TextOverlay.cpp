// OffscreenRenderer's 2D overlay: text from stb_easy_font's quads and the title strip, drawn in an
// orthographic projection over the finished 3D scene.
#include "crowdcloth/render/OffscreenRenderer.h"

#include <GL/gl.h>

#include <vector>

#include <stb_easy_font.h>

namespace cc::render {
namespace {

constexpr float kLineHeight = 12.0f;  // stb_easy_font's line advance in font pixels
constexpr int kBytesPerQuad = 64;     // 4 vertices of x, y, z floats and 4 colour bytes

// stb_easy_font indexes its glyph table by (c - 32) and has glyphs for ' '..'~' only.
std::vector<char> printable(const std::string& text) {
    std::vector<char> out;
    out.reserve(text.size() + 1);
    for (char c : text) out.push_back((c == '\n' || (c >= ' ' && c <= '~')) ? c : '?');
    out.push_back('\0');
    return out;
}

// Pixel coordinates of the output image, y down; the supersampled viewport scales them.
void beginOverlay(int width, int height) {
    glPushAttrib(GL_ENABLE_BIT | GL_CURRENT_BIT | GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_LIGHTING);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);  // the frame stays opaque
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glOrtho(0.0, width, height, 0.0, -1.0, 1.0);
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
}

void endOverlay() {
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glMatrixMode(GL_MODELVIEW);
    glPopMatrix();
    glPopAttrib();
}

void drawTextQuads(float x, float y, const std::string& text, const Rgb& colour, float scale) {
    std::vector<char> chars = printable(text);
    std::vector<char> quads(chars.size() * 300);  // stb_easy_font averages ~270 bytes per character
    const int quadCount = stb_easy_font_print(0.0f, 0.0f, chars.data(), nullptr, quads.data(), int(quads.size()));
    glTranslatef(x, y, 0.0f);
    glScalef(scale, scale, 1.0f);
    glColor4f(colour[0], colour[1], colour[2], 1.0f);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, kBytesPerQuad / 4, quads.data());
    glDrawArrays(GL_QUADS, 0, quadCount * 4);
    glDisableClientState(GL_VERTEX_ARRAY);
}

} // namespace

void OffscreenRenderer::drawText(float x, float y, const std::string& text, const Rgb& colour, float scale) {
    beginOverlay(mWidth, mHeight);
    drawTextQuads(x, y, text, colour, scale);
    endOverlay();
}

void OffscreenRenderer::drawTitleStrip(const std::string& text, float scale) {
    const float margin = 4.0f * scale;
    const float stripHeight = kLineHeight * scale + margin;
    beginOverlay(mWidth, mHeight);
    glColor4f(0.0f, 0.0f, 0.0f, 0.6f);
    glRectf(0.0f, 0.0f, float(mWidth), stripHeight);
    drawTextQuads(margin, 0.5f * margin + scale, text, {1.0f, 1.0f, 1.0f}, scale);
    endOverlay();
}

} // namespace cc::render

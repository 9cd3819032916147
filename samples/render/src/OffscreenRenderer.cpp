#include "crowdcloth/render/OffscreenRenderer.h"

#include <GL/osmesa.h>
#include <GL/gl.h>

#include <cstring>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace cc::render {

struct OffscreenRenderer::Context {
    OSMesaContext context = nullptr;
};

Result<std::unique_ptr<OffscreenRenderer>> OffscreenRenderer::create(int width, int height) {
    if (width <= 0 || height <= 0 || width > 8192 || height > 8192)
        return Status::invalidArgument("OffscreenRenderer: size must be in [1, 8192] pixels");
    std::unique_ptr<OffscreenRenderer> r(new OffscreenRenderer());
    r->mContext = std::make_unique<Context>();
    r->mContext->context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
    if (!r->mContext->context) return Status::error(StatusCode::InvalidOperation, "OSMesaCreateContextExt failed");
    r->mWidth = width;
    r->mHeight = height;
    r->mBuffer.assign(std::size_t(width) * height * 4, 0);
    r->mFlipped.assign(r->mBuffer.size(), 0);
    if (!OSMesaMakeCurrent(r->mContext->context, r->mBuffer.data(), GL_UNSIGNED_BYTE, width, height))
        return Status::error(StatusCode::InvalidOperation, "OSMesaMakeCurrent failed");
    return r;
}

OffscreenRenderer::~OffscreenRenderer() {
    if (mContext && mContext->context) OSMesaDestroyContext(mContext->context);
}

void OffscreenRenderer::beginFrame(const double viewProjection[16], const float background[3]) {
    OSMesaMakeCurrent(mContext->context, mBuffer.data(), GL_UNSIGNED_BYTE, mWidth, mHeight);
    glViewport(0, 0, mWidth, mHeight);
    glClearColor(background[0], background[1], background[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixd(viewProjection);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    // Light from above and slightly in front; both sides of the cloth are lit.
    const GLfloat direction[4] = {0.3f, 1.0f, 0.5f, 0.0f};
    const GLfloat ambient[4] = {0.35f, 0.35f, 0.35f, 1.0f};
    const GLfloat diffuse[4] = {0.75f, 0.75f, 0.75f, 1.0f};
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glLightfv(GL_LIGHT0, GL_POSITION, direction);
    glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glEnable(GL_NORMALIZE);
}

void OffscreenRenderer::drawGround(float extent, float spacing) {
    glDisable(GL_LIGHTING);
    glColor3f(0.55f, 0.55f, 0.5f);
    glBegin(GL_QUADS);
    glVertex3f(-extent, -0.002f, -extent);
    glVertex3f(-extent, -0.002f, extent);
    glVertex3f(extent, -0.002f, extent);
    glVertex3f(extent, -0.002f, -extent);
    glEnd();
    glColor3f(0.45f, 0.45f, 0.42f);
    glBegin(GL_LINES);
    for (float x = -extent; x <= extent; x += spacing) {
        glVertex3f(x, 0.0f, -extent);
        glVertex3f(x, 0.0f, extent);
        glVertex3f(-extent, 0.0f, x);
        glVertex3f(extent, 0.0f, x);
    }
    glEnd();
    glEnable(GL_LIGHTING);
}

void OffscreenRenderer::drawMesh(const float* positions, const float* normals, uint32_t vertexCount,
                                 const uint32_t* indices, uint32_t triangleCount, const float color[3]) {
    if (vertexCount == 0 || triangleCount == 0) return;
    glColor3fv(color);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, positions);
    if (normals) {
        glEnableClientState(GL_NORMAL_ARRAY);
        glNormalPointer(GL_FLOAT, 0, normals);
    }
    glDrawElements(GL_TRIANGLES, GLsizei(3 * triangleCount), GL_UNSIGNED_INT, indices);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
}

void OffscreenRenderer::endFrame() {
    glFinish();
    const std::size_t row = std::size_t(mWidth) * 4;
    for (int y = 0; y < mHeight; ++y)
        std::memcpy(&mFlipped[std::size_t(y) * row], &mBuffer[std::size_t(mHeight - 1 - y) * row], row);
}

Status OffscreenRenderer::writePng(const std::string& path) const {
    if (!stbi_write_png(path.c_str(), mWidth, mHeight, 4, mFlipped.data(), mWidth * 4))
        return Status::invalidArgument("could not write PNG '" + path + "'");
    return Status::ok();
}

} // namespace cc::render

#include "crowdcloth/render/OffscreenRenderer.h"

#include <GL/osmesa.h>
#include <GL/gl.h>

#include <cmath>
#include <malloc.h>

#include "BoxFilter.h"
#include "GroundShadow.h"
#include "MeshBuffers.h"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace cc::render {

struct OffscreenRenderer::Context {
    OSMesaContext context = nullptr;
    std::unique_ptr<MeshBuffers> meshBuffers;  // created once the context is current
};

namespace {

// Stencil values: the ground marks its pixels; a shadow darkens a marked pixel once and clears it,
// so overlapping shadows do not darken twice.
constexpr GLint kGroundStencil = 1;
constexpr int kMaxSamplesPerAxis = 16384;  // Mesa's largest framebuffer side

Status checkOptions(int width, int height, const RendererOptions& o) {
    if (width <= 0 || height <= 0 || width > 8192 || height > 8192)
        return Status::invalidArgument("OffscreenRenderer: size must be in [1, 8192] pixels");
    if (o.supersample < 1 || o.supersample > 4)
        return Status::invalidArgument("OffscreenRenderer: supersample must be in [1, 4], got " +
                                       std::to_string(o.supersample));
    if (width * o.supersample > kMaxSamplesPerAxis || height * o.supersample > kMaxSamplesPerAxis)
        return Status::invalidArgument("OffscreenRenderer: size x supersample exceeds " +
                                       std::to_string(kMaxSamplesPerAxis) + " samples");
    if (!(o.lightDirection[1] > 0.0f))
        return Status::invalidArgument("OffscreenRenderer: lightDirection must point up (y > 0) to cast ground shadows");
    if (!(o.shadowDarkening >= 0.0f && o.shadowDarkening <= 1.0f))
        return Status::invalidArgument("OffscreenRenderer: shadowDarkening must be in [0, 1]");
    return Status::ok();
}

void setMaterial(GLenum face, const Rgb& colour) {
    const GLfloat rgba[4] = {colour[0], colour[1], colour[2], 1.0f};
    glMaterialfv(face, GL_AMBIENT_AND_DIFFUSE, rgba);
}

} // namespace

Result<std::unique_ptr<OffscreenRenderer>> OffscreenRenderer::create(int width, int height,
                                                                     const RendererOptions& options) {
    if (Status s = checkOptions(width, height, options); !s) return s;
    // Mesa's draw module mallocs and frees its vertex buffers on every draw; at glibc's default trim
    // threshold each free hands the heap top back to the kernel and the next draw faults it in again
    // (measured: about half the frame time with one rasteriser thread). Keep up to 256 MB instead.
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    std::unique_ptr<OffscreenRenderer> r(new OffscreenRenderer());
    r->mOptions = options;
    Rgb& l = r->mOptions.lightDirection;
    const float length = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    for (float& c : l) c /= length;
    r->mWidth = width;
    r->mHeight = height;
    r->mContext = std::make_unique<Context>();
    r->mContext->context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
    if (!r->mContext->context)
        return Status::error(StatusCode::InvalidOperation,
                             "OSMesaCreateContextExt failed (RGBA, 24-bit depth, 8-bit stencil); is libosmesa6 installed?");
    const int s = options.supersample;
    r->mSamples.assign(std::size_t(width) * s * height * s * 4, 0);
    r->mImage.assign(std::size_t(width) * height * 4, 0);
    if (!OSMesaMakeCurrent(r->mContext->context, r->mSamples.data(), GL_UNSIGNED_BYTE, width * s, height * s))
        return Status::error(StatusCode::InvalidOperation, "OSMesaMakeCurrent failed");
    GLint stencilBits = 0;
    glGetIntegerv(GL_STENCIL_BITS, &stencilBits);
    if (stencilBits == 0)
        return Status::error(StatusCode::InvalidOperation, "OSMesa context has no stencil buffer (needed for shadows)");
    r->mContext->meshBuffers = std::make_unique<MeshBuffers>();
    return r;
}

OffscreenRenderer::~OffscreenRenderer() {
    if (mContext && mContext->context) OSMesaDestroyContext(mContext->context);  // frees the mesh buffers too
}

void OffscreenRenderer::beginFrame(const double viewProjection[16], const float background[3]) {
    const int s = mOptions.supersample;
    OSMesaMakeCurrent(mContext->context, mSamples.data(), GL_UNSIGNED_BYTE, mWidth * s, mHeight * s);
    glViewport(0, 0, mWidth * s, mHeight * s);
    glClearColor(background[0], background[1], background[2], 1.0f);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixd(viewProjection);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    // Lighting happens in world space (identity model-view), so the light is fixed in the world.
    const Rgb& l = mOptions.lightDirection;
    const GLfloat direction[4] = {l[0], l[1], l[2], 0.0f};
    const GLfloat ambient[4] = {mOptions.ambient, mOptions.ambient, mOptions.ambient, 1.0f};
    const GLfloat diffuse[4] = {mOptions.diffuse, mOptions.diffuse, mOptions.diffuse, 1.0f};
    const GLfloat black[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glLightfv(GL_LIGHT0, GL_POSITION, direction);
    glLightfv(GL_LIGHT0, GL_AMBIENT, ambient);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
    glLightfv(GL_LIGHT0, GL_SPECULAR, black);
    // No global ambient term: the shading is exactly ambient + diffuse * n.l, as documented.
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, black);
    glDisable(GL_COLOR_MATERIAL);
    glEnable(GL_NORMALIZE);
}

void OffscreenRenderer::drawGround(float extent, float spacing) {
    glDisable(GL_LIGHTING);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, kGroundStencil, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    glColor3fv(mOptions.groundColour.data());
    glBegin(GL_QUADS);
    glVertex3f(-extent, -0.002f, -extent);
    glVertex3f(-extent, -0.002f, extent);
    glVertex3f(extent, -0.002f, extent);
    glVertex3f(extent, -0.002f, -extent);
    glEnd();
    glLineWidth(float(mOptions.supersample));  // the same width in image pixels at any supersampling
    glColor3fv(mOptions.gridColour.data());
    glBegin(GL_LINES);
    for (float x = -extent; x <= extent; x += spacing) {
        glVertex3f(x, 0.0f, -extent);
        glVertex3f(x, 0.0f, extent);
        glVertex3f(-extent, 0.0f, x);
        glVertex3f(extent, 0.0f, x);
    }
    glEnd();
    glDisable(GL_STENCIL_TEST);
    glEnable(GL_LIGHTING);
}

void OffscreenRenderer::drawMesh(const float* positions, const float* normals, uint32_t vertexCount,
                                 const uint32_t* indices, uint32_t triangleCount, const MeshStyle& style) {
    if (vertexCount == 0 || triangleCount == 0) return;
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, style.twoSided ? GL_TRUE : GL_FALSE);
    setMaterial(GL_FRONT, style.front);
    setMaterial(GL_BACK, style.twoSided ? style.back : style.front);
    mContext->meshBuffers->bind(positions, normals, vertexCount, indices, triangleCount);
    glDrawElements(GL_TRIANGLES, GLsizei(3 * triangleCount), GL_UNSIGNED_INT, nullptr);
    if (style.castsShadow) drawShadow(triangleCount);
    mContext->meshBuffers->unbind();
}

void OffscreenRenderer::drawMesh(const float* positions, const float* normals, uint32_t vertexCount,
                                 const uint32_t* indices, uint32_t triangleCount, const float color[3]) {
    const Rgb colour{color[0], color[1], color[2]};
    drawMesh(positions, normals, vertexCount, indices, triangleCount, MeshStyle{colour, colour, true, true});
}

// The mesh flattened onto y = 0 and blended darker where the ground is still unshadowed. It is
// depth tested against what is already drawn, so it never shows through a body in front of it.
// Draws the mesh drawMesh has bound.
void OffscreenRenderer::drawShadow(uint32_t triangleCount) {
    float flatten[16];
    groundShadowMatrix(mOptions.lightDirection, flatten);
    glPushMatrix();
    glMultMatrixf(flatten);
    glDisable(GL_LIGHTING);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);  // the frame stays opaque
    glColor4f(0.0f, 0.0f, 0.0f, mOptions.shadowDarkening);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_EQUAL, kGroundStencil, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_ZERO);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-2.0f, -2.0f);  // pulled towards the camera, off the ground it lies on
    glDepthMask(GL_FALSE);
    glDrawElements(GL_TRIANGLES, GLsizei(3 * triangleCount), GL_UNSIGNED_INT, nullptr);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_BLEND);
    glEnable(GL_LIGHTING);
    glPopMatrix();
}

void OffscreenRenderer::endFrame() {
    glFinish();
    boxFilterAndFlip(mSamples.data(), mOptions.supersample, mWidth, mHeight, mImage.data());
}

Status OffscreenRenderer::writePng(const std::string& path) const {
    if (!stbi_write_png(path.c_str(), mWidth, mHeight, 4, mImage.data(), mWidth * 4))
        return Status::invalidArgument("could not write PNG '" + path + "'");
    return Status::ok();
}

} // namespace cc::render

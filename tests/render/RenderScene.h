#pragma once
// What the renderer tests share: a renderer that fails the test clearly when OSMesa is missing,
// a unit quad mesh, and where a world point lands in the image.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>

#include <Eigen/Core>

#include "crowdcloth/core/Camera.h"
#include "crowdcloth/render/OffscreenRenderer.h"

namespace cc::render::test {

inline std::unique_ptr<OffscreenRenderer> makeRenderer(int width, int height, const RendererOptions& options) {
    auto r = OffscreenRenderer::create(width, height, options);
    EXPECT_TRUE(r.isOk()) << "could not create the OSMesa renderer (libosmesa6 must be installed): "
                          << r.status().message();
    return r.isOk() ? std::move(r).value() : nullptr;
}

/// Two triangles, counter-clockwise seen from the side `normal` points to.
struct Quad {
    std::array<float, 12> positions{};
    std::array<float, 12> normals{};
    std::array<uint32_t, 6> indices{0, 1, 2, 0, 2, 3};

    void draw(OffscreenRenderer& r, const MeshStyle& style) const {
        r.drawMesh(positions.data(), normals.data(), 4, indices.data(), 2, style);
    }
};

/// The square [-h, h]^2 in the plane z = 0 facing +z, moved to `centre`.
inline Quad facingPlusZ(const Eigen::Vector3f& centre, float h) {
    const float corners[4][2] = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
    Quad q;
    for (int v = 0; v < 4; ++v) {
        const float p[3] = {centre.x() + corners[v][0], centre.y() + corners[v][1], centre.z()};
        for (int k = 0; k < 3; ++k) {
            q.positions[3 * v + k] = p[k];
            q.normals[3 * v + k] = (k == 2) ? 1.0f : 0.0f;
        }
    }
    return q;
}

/// The square [-h, h]^2 in the plane y = centre.y facing +y.
inline Quad facingUp(const Eigen::Vector3f& centre, float h) {
    const float corners[4][2] = {{-h, h}, {h, h}, {h, -h}, {-h, -h}};  // (x, z), counter-clockwise from above
    Quad q;
    for (int v = 0; v < 4; ++v) {
        const float p[3] = {centre.x() + corners[v][0], centre.y(), centre.z() + corners[v][1]};
        for (int k = 0; k < 3; ++k) {
            q.positions[3 * v + k] = p[k];
            q.normals[3 * v + k] = (k == 1) ? 1.0f : 0.0f;
        }
    }
    return q;
}

struct Camera {
    double viewProjection[16];
    int width, height;

    Camera(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, int w, int h) : width(w), height(h) {
        lookAt(eye, target, double(w) / h, viewProjection, 40.0, 0.1, 100.0);
    }

    /// The image pixel (column, row from the top) that `p` projects into.
    std::array<int, 2> pixelOf(const Eigen::Vector3d& p) const {
        const Eigen::Map<const Eigen::Matrix4d> vp(viewProjection);
        const Eigen::Vector4d clip = vp * p.homogeneous();
        const double x = clip.x() / clip.w(), y = clip.y() / clip.w();
        return {int(std::floor((0.5 * x + 0.5) * width)), int(std::floor((0.5 - 0.5 * y) * height))};
    }
};

/// RGB of pixel (column, row from the top) in [0, 255].
inline std::array<int, 3> pixel(const OffscreenRenderer& r, std::array<int, 2> at) {
    const std::size_t i = (std::size_t(at[1]) * r.width() + at[0]) * 4;
    return {r.image()[i], r.image()[i + 1], r.image()[i + 2]};
}

inline std::array<int, 3> toBytes(const Rgb& c) {
    return {int(std::lround(c[0] * 255.0f)), int(std::lround(c[1] * 255.0f)), int(std::lround(c[2] * 255.0f))};
}

inline void expectNear(const std::array<int, 3>& actual, const std::array<int, 3>& expected, int tolerance,
                       const char* what) {
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(actual[k], expected[k], tolerance)
            << what << ", channel " << k << ": (" << actual[0] << ", " << actual[1] << ", " << actual[2]
            << ") vs expected (" << expected[0] << ", " << expected[1] << ", " << expected[2] << ")";
}

} // namespace cc::render::test

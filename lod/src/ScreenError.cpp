#include "crowdcloth/lod/ScreenError.h"

#include <algorithm>
#include <cmath>

namespace cc::lod {
namespace {

/// Viewport pixel coordinates of a world point, or false when it is not in front of the near plane.
bool toPixels(const SchedulerCamera& camera, const float* p, double& x, double& y) {
    const Eigen::Vector4d clip = camera.viewProjection * Eigen::Vector4d(p[0], p[1], p[2], 1.0);
    if (!(clip.w() > 0.0) || clip.z() < -clip.w()) return false;
    x = 0.5 * (clip.x() / clip.w() + 1.0) * camera.viewportWidth;
    y = 0.5 * (clip.y() / clip.w() + 1.0) * camera.viewportHeight;
    return true;
}

} // namespace

MeshDeviation meshDeviation(const float* positions, const float* reference, std::size_t vertexCount,
                            const SchedulerCamera* camera) {
    MeshDeviation d;
    d.vertices = vertexCount;
    double sum = 0.0, pixelSum = 0.0;
    std::size_t projected = 0;
    for (std::size_t v = 0; v < vertexCount; ++v) {
        const float* a = positions + 3 * v;
        const float* b = reference + 3 * v;
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c) d2 += (double(a[c]) - double(b[c])) * (double(a[c]) - double(b[c]));
        sum += d2;
        d.maxMetres = std::max(d.maxMetres, std::sqrt(d2));
        double ax, ay, bx, by;
        if (camera && toPixels(*camera, a, ax, ay) && toPixels(*camera, b, bx, by)) {
            const double apart = std::hypot(ax - bx, ay - by);
            d.maxPixels = std::max(d.maxPixels, apart);
            pixelSum += apart * apart;
            ++projected;
        }
    }
    if (vertexCount > 0) d.rmsMetres = std::sqrt(sum / double(vertexCount));
    if (projected > 0) d.rmsPixels = std::sqrt(pixelSum / double(projected));
    return d;
}

double pixelsAtDistance(double metres, double distance, double fovY, double viewportHeight) {
    return metres / (2.0 * distance * std::tan(0.5 * fovY)) * viewportHeight;
}

} // namespace cc::lod

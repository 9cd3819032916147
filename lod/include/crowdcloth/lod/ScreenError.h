#pragma once

#include <cstddef>

#include "crowdcloth/lod/CrowdScheduler.h"

namespace cc::lod {

/// How far one render mesh lies from another of the same topology: vertices are matched by
/// index, which for a garment's fixed render mesh means by rest (pattern) coordinates, so a
/// coarse level's result is compared with the reference at the same points of the cloth.
struct MeshDeviation {
    double rmsMetres = 0.0;  ///< [m] root mean square of the vertex distances
    double maxMetres = 0.0;  ///< [m] largest vertex distance
    double maxPixels = 0.0;  ///< [px] largest on-screen distance (0 without a camera)
    double rmsPixels = 0.0;  ///< [px] root mean square of the on-screen distances (0 without a camera)
    std::size_t vertices = 0;
};

/// Deviation of `positions` from `reference` (xyz floats per vertex, `vertexCount` of each),
/// and, when `camera` is given, how far their projections are apart on its viewport (largest and
/// root mean square); pairs with a vertex behind the camera's near plane are left out of the pixels.
MeshDeviation meshDeviation(const float* positions, const float* reference, std::size_t vertexCount,
                            const SchedulerCamera* camera = nullptr);

/// Pixels that `metres` seen face-on from `distance` [m] cover on a viewport `viewportHeight` [px]
/// tall with vertical field of view `fovY` [rad] (pinhole camera).
double pixelsAtDistance(double metres, double distance, double fovY, double viewportHeight);

} // namespace cc::lod

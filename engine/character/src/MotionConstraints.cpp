#include "crowdcloth/character/MotionConstraints.h"

#include <cmath>
#include <string>

namespace cc {

Status applyMotionConstraints(Span<const Vec3> targets, Span<const double> maxDistances,
                              Span<const Vec3> surfacePoints, Span<const Vec3> surfaceNormals,
                              const MotionConstraintSettings& settings, Span<Vec3> inOutPositions,
                              Span<Vec3> inOutVelocities, MotionConstraintStats* outStats) {
    const std::size_t n = inOutPositions.size();
    const auto sized = [n](std::size_t s) { return s == 0 || s == n; };
    if (!sized(maxDistances.size()) || !sized(surfacePoints.size()) || !sized(surfaceNormals.size()) ||
        !sized(inOutVelocities.size()) || surfacePoints.size() != surfaceNormals.size() ||
        (!maxDistances.empty() && targets.size() != n)) {
        return Status::invalidArgument("applyMotionConstraints: every non-empty span must have " + std::to_string(n) +
                                       " entries (targets are required with maxDistances, normals with surface points)");
    }
    if (!std::isfinite(settings.backstopOffset)) {
        return Status::invalidArgument("MotionConstraintSettings.backstopOffset must be finite");
    }
    MotionConstraintStats stats;
    const bool velocities = !inOutVelocities.empty();
    for (std::size_t i = 0; i < n; ++i) {
        Vec3& x = inOutPositions[i];
        if (!maxDistances.empty()) {
            const double r = maxDistances[i];
            if (r >= 0.0 && std::isfinite(r)) {
                const Vec3 d = x - targets[i];
                const double len = d.norm();
                if (len > r) {
                    const Vec3 dir = d / len;
                    x = targets[i] + r * dir;
                    if (velocities) {
                        const double vr = inOutVelocities[i].dot(dir);
                        if (vr > 0.0) inOutVelocities[i] -= vr * dir;
                    }
                    ++stats.maxDistanceClamped;
                }
            }
        }
        if (!surfacePoints.empty()) {
            const Vec3& nrm = surfaceNormals[i];
            const double d = (x - surfacePoints[i]).dot(nrm);
            if (d < settings.backstopOffset) {
                x += (settings.backstopOffset - d) * nrm;
                if (velocities) {
                    const double vn = inOutVelocities[i].dot(nrm);
                    if (vn < 0.0) inOutVelocities[i] -= vn * nrm;
                }
                ++stats.backstopClamped;
            }
        }
    }
    if (outStats) *outStats = stats;
    return Status::ok();
}

} // namespace cc

#pragma once

#include <cstddef>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc {

/// Motion constraints of skinned cloth, as in NvCloth/PhysX ("motion constraints" = max distance,
/// "separation constraints"/backstop): each constrained vertex may move at most maxDistance from
/// its skinned target, and never behind the body surface along the skinned normal.
struct MotionConstraintSettings {
    double backstopOffset = 0.0; ///< [m] the vertex stays at least this far in front of the body
                                 ///< surface along the normal; may be negative (allows that much
                                 ///< behind); 0 = on the surface
};

/// What applyMotionConstraints changed.
struct MotionConstraintStats {
    std::size_t maxDistanceClamped = 0; ///< vertices pulled back inside their sphere
    std::size_t backstopClamped = 0;    ///< vertices pushed out in front of the backstop
};

/// Clamps positions in place, per vertex i:
/// 1. max distance: if |x - target| > maxDistances[i], x moves onto that sphere (towards the
///    target), and the velocity component along the outward radial direction, if positive, is
///    removed. A negative or infinite maxDistance leaves the vertex free.
/// 2. backstop: with d = (x - surfacePoint) . normal, if d < backstopOffset, x moves along the
///    normal to d = backstopOffset and a velocity component into the body (v . n < 0) is removed.
/// Empty maxDistances skips (1); empty surfacePoints/surfaceNormals skip (2); empty velocities
/// leaves velocities alone. All non-empty spans must have positions.size() entries (checked).
/// The backstop runs last, so a vertex never ends behind the body even when the two disagree.
Status applyMotionConstraints(Span<const Vec3> targets, Span<const double> maxDistances,
                              Span<const Vec3> surfacePoints, Span<const Vec3> surfaceNormals,
                              const MotionConstraintSettings& settings, Span<Vec3> inOutPositions,
                              Span<Vec3> inOutVelocities, MotionConstraintStats* outStats = nullptr);

} // namespace cc

#pragma once

#include <algorithm>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"

namespace cc {

/// A sphere about a point set's centroid holding every point: a garment's size on screen and the
/// scale its measured errors are divided by.
struct BoundingSphere {
    Vec3 centre = Vec3::Zero();  ///< [m] the centroid
    double radius = 0.0;         ///< [m] the farthest point's distance from it
};

/// The centroid of `points` and the largest distance from it; zero for none.
inline BoundingSphere centroidSphere(Span<const Vec3> points) {
    BoundingSphere sphere;
    if (points.empty()) return sphere;
    for (const Vec3& p : points) sphere.centre += p;
    sphere.centre /= double(points.size());
    for (const Vec3& p : points) sphere.radius = std::max(sphere.radius, (p - sphere.centre).norm());
    return sphere;
}

} // namespace cc

#pragma once
// The convex hull of points in a plane (body slices, garment cross sections).

#include <vector>

#include "crowdcloth/core/Math.h"

namespace cc {

/// Counter-clockwise convex hull, without repeated or collinear points (Andrew's monotone chain).
/// Fewer than three distinct points come back sorted as they are.
std::vector<Vec2> convexHull(std::vector<Vec2> points);

} // namespace cc

#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/core/ConvexHull.h"
#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"

namespace cc::detail {

/// One closed cross-section of a body: the points where a horizontal plane cuts the triangles of
/// one connected ring of the mesh (2D: x and z in bind space).
struct SliceLoop {
    std::vector<Vec2> points;
    Vec2 centroid = Vec2::Zero();
};

/// Points where the plane y = height cuts the triangles whose `keep` flag is set (all when `keep`
/// is empty), as (x, z). No allocation once outPoints has grown.
void slicePoints(Span<const Vec3> positions, const std::vector<std::array<uint32_t, 3>>& triangles,
                 const std::vector<uint8_t>& keep, double height, std::vector<Vec2>& outPoints);

/// For each vertex, the first vertex at the same position: meshes split vertices along hard
/// edges and UV seams, and a cut through such a seam must still close its loop.
std::vector<uint32_t> samePositionIds(Span<const Vec3> positions);

/// The same cut split into its closed loops: two cut triangles belong to one loop when they share
/// a cut edge (edges compared through `sameIds`, see samePositionIds). Loops come in a
/// deterministic order (by their smallest triangle index).
void sliceLoops(Span<const Vec3> positions, const std::vector<std::array<uint32_t, 3>>& triangles,
                const std::vector<uint8_t>& keep, const std::vector<uint32_t>& sameIds, double height,
                std::vector<SliceLoop>& outLoops);

/// Length of a closed polygon [m].
double perimeter(const std::vector<Vec2>& polygon);

/// True when p lies inside the convex CCW polygon or within `margin` of it.
bool insideConvex(const std::vector<Vec2>& hull, const Vec2& p, double margin);

} // namespace cc::detail

#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// What a body collider needs of its mesh that does not change as the body animates: the
/// triangles, the triangles on welded vertices, each vertex's triangles, edge groups and connected
/// parts. Built once per body asset and shared (immutable) by every character's collider, so a
/// collider made when a character comes near the camera costs its trees, not a topology pass
/// (2-5 ms on a 5,776-triangle body).
///
/// Topology is built on positions, not indices: an exported skin splits a vertex at every UV or
/// normal seam, and a body torn into open patches there has no inside (its pseudonormals and
/// parts would be those of the patches).
struct BodyTopology {
    /// `triangles` index `weldPositions` (the bind pose: vertices at exactly one position are one).
    /// Names the first triangle corner out of range.
    static Result<std::shared_ptr<const BodyTopology>> build(Span<const std::array<uint32_t, 3>> triangles,
                                                             Span<const Vec3> weldPositions);

    uint32_t vertexCount = 0;
    std::vector<std::array<uint32_t, 3>> triangles;  ///< as given
    std::vector<std::array<uint32_t, 3>> welded;     ///< the same on welded vertex indices
    /// The triangles around welded vertex v: vertexTriangles[vertexStart[v] .. vertexStart[v + 1]).
    std::vector<uint32_t> vertexStart, vertexTriangles;
    /// Triangle-edge slots (3 t + k) grouped by undirected welded edge: slots of group g are
    /// edgeSlots[edgeStart[g] .. edgeStart[g + 1]).
    std::vector<uint32_t> edgeSlots, edgeStart;
    /// Connected part of each triangle (triangles sharing welded vertices): a body is often several
    /// closed surfaces that overlap (a thigh into the pelvis), and a point outside the nearest one
    /// may be inside another.
    std::vector<uint32_t> part;
    uint32_t partCount = 0;
    /// Per part: 1 when it is a closed surface, consistently wound (each edge shared by two of its
    /// triangles, running opposite ways): only a closed part has an inside a ray can count.
    std::vector<uint8_t> partClosed;
};

} // namespace cc::collision

#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Status.h"

namespace cc {

/// A garment's triangle mesh as the solver sees it: rest (pattern) coordinates in metres, the
/// initial world positions, and counter-clockwise triangles (in rest space).
///
/// The rest shape is flat: garments are cut from cloth, so each vertex has 2D pattern coordinates
/// (u, v) in metres. Stretch is measured against them and bending rests flat.
struct ClothMesh {
    std::vector<Vec2> restPositions;                  ///< [m] pattern (u, v) per vertex
    std::vector<Vec3> positions;                      ///< [m] initial world position per vertex
    std::vector<std::array<uint32_t, 3>> triangles;   ///< vertex indices, CCW in pattern space

    std::size_t vertexCount() const { return positions.size(); }

    /// Checks sizes, index ranges, finiteness, zero-area triangles and zero-length edges.
    /// The message names the first offending triangle, vertex or edge.
    Status validate() const;
};

/// Relative tolerance below which a rest triangle's area or edge length counts as degenerate,
/// measured against the mesh's mean rest edge length (squared for areas).
constexpr double kDegenerateRelativeTolerance = 1e-6;

} // namespace cc

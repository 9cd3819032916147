#pragma once

#include <cstdint>

#include "crowdcloth/core/ClothMesh.h"

namespace cc {

/// A rectangular pattern panel triangulated the 4-8 way: grid squares split by alternating
/// diagonals, so every interior vertex alternates between valence 4 and 8 and the mesh is level 0
/// of a 4-8 hierarchy that lod/ can refine.
///
///   v ^   (0,2)---(1,2)---(2,2)
///     |     | \     |     / |
///     |     |   \   |   /   |
///     |   (0,1)---(1,1)---(2,1)
///     |     |   /   |   \   |
///     |     | /     |     \ |
///     |   (0,0)---(1,0)---(2,0)  -> u
///
/// The panel is placed in world space with its u axis along +X and its v axis along `vAxis`
/// (default +Y, so it hangs in the XY plane), origin at `origin`.
struct RectanglePanel {
    double width = 1.0;        ///< [m] extent along u; > 0
    double height = 1.0;       ///< [m] extent along v; > 0
    uint32_t columns = 16;     ///< grid squares along u; >= 1
    uint32_t rows = 16;        ///< grid squares along v; >= 1
    Vec3 origin = Vec3::Zero();       ///< [m] world position of pattern point (0, 0)
    Vec3 vAxis = Vec3::UnitY();       ///< world direction of the v axis (unit, orthogonal to X)

    Status validate() const;
    /// Vertex index of grid point (i, j), i along u, j along v.
    uint32_t vertexIndex(uint32_t i, uint32_t j) const { return j * (columns + 1) + i; }
    /// Builds the mesh; fails with a message if the panel is invalid.
    Result<ClothMesh> build() const;
};

} // namespace cc

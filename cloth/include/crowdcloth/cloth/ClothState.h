#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"

namespace cc::cloth {

/// Per-vertex dynamic state of one garment, structure of arrays. Masses are lumped [kg] and
/// positive; pinned and driven vertices are expressed by the ConstraintSet, not by the mass.
struct ClothState {
    std::vector<Vec3> positions;   ///< [m]
    std::vector<Vec3> velocities;  ///< [m/s]
    std::vector<double> masses;    ///< [kg] > 0

    uint32_t vertexCount() const { return static_cast<uint32_t>(positions.size()); }
    double kineticEnergy() const;
    /// [J] potential energy of the masses in a uniform field `gravity` [m/s^2] (zero at the origin).
    double gravityEnergy(const Vec3& gravity) const;
    /// Index of the first vertex with a non-finite position or velocity, or vertexCount().
    uint32_t firstNonFinite() const;
    /// Bitwise digest of positions and velocities.
    uint64_t hash() const;
};

} // namespace cc::cloth

#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/core/ClothMesh.h"

namespace cc::lod {

/// The active (simulated) mesh of a GarmentHierarchy in the solver's terms, with the maps between
/// simulation indices and the hierarchy's stable vertex ids.
///
/// ClothMesh keeps one pattern position per vertex, so a hierarchy vertex on a seam or on a tube's
/// wrap-around side (which has a different pattern position in each panel or across the wrap)
/// becomes one simulation vertex per pattern position. `welds` lists those copies: the solver must
/// keep them together (see the report: ClothMesh needs per-corner pattern coordinates to avoid it).
struct ActiveMesh {
    static constexpr uint32_t kNone = 0xffffffffu;

    ClothMesh mesh;                       ///< positions = the hierarchy's current positions
    std::vector<Vec3> velocities;         ///< [m/s] per simulation vertex
    std::vector<double> masses;           ///< [kg] lumped from rest area (as cloth::lumpedMasses)
    std::vector<uint32_t> simToVertex;    ///< simulation index -> hierarchy vertex id
    std::vector<uint32_t> vertexToSim;    ///< hierarchy vertex id -> first simulation index, or kNone
    std::vector<uint32_t> triangleIds;    ///< simulation triangle -> hierarchy triangle id
    std::vector<std::array<uint32_t, 2>> welds;  ///< (first copy, other copy) simulation indices
};

} // namespace cc::lod

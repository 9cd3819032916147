#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/core/ClothMesh.h"

namespace cc::cloth {

/// A hinge: two triangles sharing the edge (edge0, edge1), with the opposite vertices
/// `wingA` (triangle edge0, edge1, wingA counter-clockwise) and `wingB`.
///
///            wingA
///           /     \   .
///      edge0 ------- edge1
///           \     /
///            wingB
struct Hinge {
    uint32_t edge0, edge1, wingA, wingB;
    uint32_t triangleA, triangleB;
};

/// Mesh connectivity the force models need: unique edges (with the triangles beside them) and
/// interior hinges, in a deterministic order (sorted by vertex indices).
struct ClothTopology {
    std::vector<std::array<uint32_t, 2>> edges;          ///< (low, high) vertex index
    std::vector<std::array<uint32_t, 2>> edgeTriangles;  ///< adjacent triangles; second = kNone on the border
    std::vector<Hinge> hinges;

    static constexpr uint32_t kNone = 0xffffffffu;

    /// Fails if an edge is shared by more than two triangles (non-manifold), naming the edge.
    static Result<ClothTopology> build(const ClothMesh& mesh);
};

/// Rest area [m^2] of triangle t in pattern space.
double restArea(const ClothMesh& mesh, uint32_t t);

/// Lumped vertex masses [kg]: each triangle gives a third of its rest mass to each corner. The
/// total is exactly density times rest area, at every resolution.
std::vector<double> lumpedMasses(const ClothMesh& mesh, double arealDensity);

} // namespace cc::cloth

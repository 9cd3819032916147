#include "crowdcloth/cloth/ClothTopology.h"

#include <algorithm>
#include <string>

namespace cc::cloth {

double restArea(const ClothMesh& mesh, uint32_t t) {
    const auto& tri = mesh.triangles[t];
    const Vec2 e1 = mesh.restPositions[tri[1]] - mesh.restPositions[tri[0]];
    const Vec2 e2 = mesh.restPositions[tri[2]] - mesh.restPositions[tri[0]];
    return 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
}

std::vector<double> lumpedMasses(const ClothMesh& mesh, double arealDensity) {
    std::vector<double> mass(mesh.vertexCount(), 0.0);
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const double third = arealDensity * restArea(mesh, t) / 3.0;
        for (uint32_t v : mesh.triangles[t]) mass[v] += third;
    }
    return mass;
}

Result<ClothTopology> ClothTopology::build(const ClothMesh& mesh) {
    // (low, high, triangle, opposite vertex) for each triangle side, sorted to pair up neighbours.
    struct Side {
        uint32_t low, high, triangle, opposite;
    };
    std::vector<Side> sides;
    sides.reserve(mesh.triangles.size() * 3);
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = tri[e], b = tri[(e + 1) % 3];
            sides.push_back({std::min(a, b), std::max(a, b), t, tri[(e + 2) % 3]});
        }
    }
    std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
        return std::tie(x.low, x.high, x.triangle) < std::tie(y.low, y.high, y.triangle);
    });

    ClothTopology topo;
    for (std::size_t i = 0; i < sides.size();) {
        std::size_t j = i + 1;
        while (j < sides.size() && sides[j].low == sides[i].low && sides[j].high == sides[i].high) ++j;
        if (j - i > 2) {
            return Status::invalidArgument("cloth mesh edge " + std::to_string(sides[i].low) + "-" +
                                           std::to_string(sides[i].high) + " is shared by " +
                                           std::to_string(j - i) + " triangles (non-manifold)");
        }
        topo.edges.push_back({sides[i].low, sides[i].high});
        topo.edgeTriangles.push_back({sides[i].triangle, j - i == 2 ? sides[i + 1].triangle : kNone});
        if (j - i == 2) {
            // Orient the hinge so (edge0, edge1, wingA) is counter-clockwise in triangle A.
            const auto& triA = mesh.triangles[sides[i].triangle];
            uint32_t e0 = sides[i].low, e1 = sides[i].high;
            for (int k = 0; k < 3; ++k) {
                if (triA[k] == e1 && triA[(k + 1) % 3] == e0) std::swap(e0, e1);
            }
            topo.hinges.push_back({e0, e1, sides[i].opposite, sides[i + 1].opposite,
                                   sides[i].triangle, sides[i + 1].triangle});
        }
        i = j;
    }
    return topo;
}

} // namespace cc::cloth

#include "crowdcloth/core/ClothMesh.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace cc {
namespace {

std::string triangleName(std::size_t t, const std::array<uint32_t, 3>& tri) {
    return "triangle " + std::to_string(t) + " (vertices " + std::to_string(tri[0]) + ", " +
           std::to_string(tri[1]) + ", " + std::to_string(tri[2]) + ")";
}

} // namespace

Status ClothMesh::validate() const {
    if (positions.empty()) return Status::invalidArgument("cloth mesh has no vertices");
    if (restPositions.size() != positions.size()) {
        return Status::invalidArgument("cloth mesh has " + std::to_string(positions.size()) +
                                       " positions but " + std::to_string(restPositions.size()) +
                                       " rest positions");
    }
    if (triangles.empty()) return Status::invalidArgument("cloth mesh has no triangles");
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (!isFinite(positions[i]) || !std::isfinite(restPositions[i].x()) ||
            !std::isfinite(restPositions[i].y())) {
            return Status::invalidArgument("cloth mesh vertex " + std::to_string(i) +
                                           " has a non-finite position or rest position");
        }
    }
    double edgeSum = 0.0;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        for (uint32_t v : tri) {
            if (v >= positions.size()) {
                return Status::invalidArgument(triangleName(t, tri) + " indexes vertex " +
                                               std::to_string(v) + " but the mesh has " +
                                               std::to_string(positions.size()) + " vertices");
            }
        }
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
            return Status::invalidArgument(triangleName(t, tri) + " repeats a vertex");
        }
        for (int e = 0; e < 3; ++e) {
            edgeSum += (restPositions[tri[(e + 1) % 3]] - restPositions[tri[e]]).norm();
        }
    }
    const double meanEdge = edgeSum / (3.0 * static_cast<double>(triangles.size()));
    const double minEdge = kDegenerateRelativeTolerance * meanEdge;
    const double minArea = kDegenerateRelativeTolerance * meanEdge * meanEdge;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = tri[e], b = tri[(e + 1) % 3];
            if ((restPositions[b] - restPositions[a]).norm() <= minEdge) {
                return Status::invalidArgument(triangleName(t, tri) + " has a zero-length rest edge " +
                                               std::to_string(a) + "-" + std::to_string(b));
            }
        }
        const Vec2 e1 = restPositions[tri[1]] - restPositions[tri[0]];
        const Vec2 e2 = restPositions[tri[2]] - restPositions[tri[0]];
        const double signedArea = 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
        if (std::abs(signedArea) <= minArea) {
            return Status::invalidArgument(triangleName(t, tri) + " has zero rest area");
        }
        if (signedArea < 0.0) {
            return Status::invalidArgument(triangleName(t, tri) +
                                           " is clockwise in pattern space (inverted)");
        }
    }
    return Status::ok();
}

} // namespace cc

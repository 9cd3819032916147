#include "crowdcloth/character/SkinnedMesh.h"

#include <cmath>
#include <string>

namespace cc {

Status SkinnedMesh::validate(std::size_t jointCount) const {
    const std::size_t n = bindPositions.size();
    if (n == 0) return Status::invalidArgument("body has no vertices");
    if (n > kMaxBodyVertices) {
        return Status::invalidArgument("body has " + std::to_string(n) + " vertices, more than the cap " +
                                       std::to_string(kMaxBodyVertices));
    }
    if (triangles.size() > kMaxBodyTriangles) {
        return Status::invalidArgument("body has " + std::to_string(triangles.size()) +
                                       " triangles, more than the cap " + std::to_string(kMaxBodyTriangles));
    }
    if (bindNormals.size() != n || jointIndices.size() != n || jointWeights.size() != n) {
        return Status::invalidArgument("body arrays disagree: " + std::to_string(n) + " positions, " +
                                       std::to_string(bindNormals.size()) + " normals, " +
                                       std::to_string(jointIndices.size()) + " joint index sets, " +
                                       std::to_string(jointWeights.size()) + " weight sets");
    }
    if (inverseBindMatrices.size() != jointCount) {
        return Status::invalidArgument("body has " + std::to_string(inverseBindMatrices.size()) +
                                       " inverse bind matrices for " + std::to_string(jointCount) + " joints");
    }
    for (std::size_t j = 0; j < jointCount; ++j) {
        const Mat4& m = inverseBindMatrices[j];
        if (!m.allFinite() || m.row(3) != Eigen::RowVector4d(0, 0, 0, 1) ||
            !(std::abs(m.topLeftCorner<3, 3>().determinant()) > 1e-12)) {
            return Status::invalidArgument("inverse bind matrix of joint " + std::to_string(j) +
                                           " is not a finite invertible affine matrix");
        }
    }
    for (std::size_t v = 0; v < n; ++v) {
        const std::string where = "body vertex " + std::to_string(v);
        if (!isFinite(bindPositions[v])) return Status::invalidArgument(where + ": non-finite position");
        const double len = bindNormals[v].norm();
        if (!std::isfinite(len) || std::abs(len - 1.0) > 1e-6) {
            return Status::invalidArgument(where + ": normal is not unit length (" + std::to_string(len) + ")");
        }
        double sum = 0.0;
        for (int k = 0; k < kMaxInfluences; ++k) {
            const double w = jointWeights[v][static_cast<std::size_t>(k)];
            if (!std::isfinite(w) || w < 0.0) {
                return Status::invalidArgument(where + ": weight " + std::to_string(k) + " is negative or not finite");
            }
            if (jointIndices[v][static_cast<std::size_t>(k)] >= jointCount) {
                return Status::invalidArgument(where + ": joint index " +
                                               std::to_string(jointIndices[v][static_cast<std::size_t>(k)]) +
                                               " outside [0, " + std::to_string(jointCount) + ")");
            }
            sum += w;
        }
        if (std::abs(sum - 1.0) > kWeightSumTolerance) {
            return Status::invalidArgument(where + ": weights sum to " + std::to_string(sum) + ", not 1");
        }
    }
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        for (uint32_t i : tri) {
            if (i >= n) {
                return Status::invalidArgument("body triangle " + std::to_string(t) + ": vertex index " +
                                               std::to_string(i) + " outside [0, " + std::to_string(n) + ")");
            }
        }
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
            return Status::invalidArgument("body triangle " + std::to_string(t) + ": repeated vertex");
        }
    }
    return Status::ok();
}

void SkinnedMesh::computeBindNormals() {
    bindNormals.assign(bindPositions.size(), Vec3::Zero());
    for (const auto& tri : triangles) {
        const Vec3& a = bindPositions[tri[0]];
        const Vec3 n = (bindPositions[tri[1]] - a).cross(bindPositions[tri[2]] - a); // 2 * area * normal
        for (uint32_t i : tri) bindNormals[i] += n;
    }
    for (Vec3& n : bindNormals) {
        const double len = n.norm();
        n = len > 0.0 ? Vec3(n / len) : Vec3::UnitY();
    }
}

void computeSkinMatrices(Span<const Mat4> globalTransforms, Span<const Mat4> inverseBindMatrices,
                         Span<Mat4> outSkinMatrices) {
    for (std::size_t j = 0; j < outSkinMatrices.size(); ++j) {
        outSkinMatrices[j] = globalTransforms[j] * inverseBindMatrices[j];
    }
}

namespace {

// Blends the top 3x4 rows of the skin matrices of one vertex's influences.
inline Eigen::Matrix<double, 3, 4> blend(const std::array<uint16_t, kMaxInfluences>& joints,
                                         const std::array<double, kMaxInfluences>& weights,
                                         Span<const Mat4> skin) {
    Eigen::Matrix<double, 3, 4> m = weights[0] * skin[joints[0]].topRows<3>();
    for (std::size_t k = 1; k < kMaxInfluences; ++k) {
        if (weights[k] != 0.0) m += weights[k] * skin[joints[k]].topRows<3>();
    }
    return m;
}

} // namespace

Vec3 skinPoint(const Vec3& bindPosition, const std::array<uint16_t, kMaxInfluences>& joints,
               const std::array<double, kMaxInfluences>& weights, Span<const Mat4> skinMatrices) {
    const Eigen::Matrix<double, 3, 4> m = blend(joints, weights, skinMatrices);
    return m.leftCols<3>() * bindPosition + m.col(3);
}

Status skinVertices(const SkinnedMesh& mesh, Span<const Mat4> skinMatrices, Span<Vec3> outPositions,
                    Span<Vec3> outNormals) {
    const std::size_t n = mesh.vertexCount();
    if (skinMatrices.size() != mesh.inverseBindMatrices.size()) {
        return Status::invalidArgument("skinVertices: " + std::to_string(skinMatrices.size()) +
                                       " skin matrices for " + std::to_string(mesh.inverseBindMatrices.size()) + " joints");
    }
    if (outPositions.size() != n || (!outNormals.empty() && outNormals.size() != n)) {
        return Status::invalidArgument("skinVertices: output arrays must have " + std::to_string(n) + " entries");
    }
    for (std::size_t v = 0; v < n; ++v) {
        const Eigen::Matrix<double, 3, 4> m = blend(mesh.jointIndices[v], mesh.jointWeights[v], skinMatrices);
        outPositions[v] = m.leftCols<3>() * mesh.bindPositions[v] + m.col(3);
        if (!outNormals.empty()) {
            const Vec3 nrm = m.leftCols<3>() * mesh.bindNormals[v];
            const double len = nrm.norm();
            outNormals[v] = len > 0.0 ? Vec3(nrm / len) : mesh.bindNormals[v];
        }
    }
    return Status::ok();
}

} // namespace cc

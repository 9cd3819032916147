#include "crowdcloth/character/CapsuleFit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace cc {

std::vector<BodyCapsule> fitBodyCapsules(const Character& character, Span<const Vec3> restPositions,
                                         Span<const Mat4> restSkinMatrices, std::size_t minVertices) {
    const SkinnedMesh& body = character.body;
    std::vector<std::vector<uint32_t>> carried(character.skeleton.jointCount());
    for (std::size_t v = 0; v < body.vertexCount(); ++v) {
        int best = 0;
        for (int k = 1; k < kMaxInfluences; ++k)
            if (body.jointWeights[v][k] > body.jointWeights[v][best]) best = k;
        carried[body.jointIndices[v][best]].push_back(uint32_t(v));
    }
    std::vector<BodyCapsule> capsules;
    for (std::size_t j = 0; j < carried.size(); ++j) {
        const std::vector<uint32_t>& verts = carried[j];
        if (verts.size() < std::max<std::size_t>(minVertices, 2)) continue;
        Vec3 mean = Vec3::Zero();
        for (uint32_t v : verts) mean += restPositions[v];
        mean /= double(verts.size());
        Mat3 cov = Mat3::Zero();
        for (uint32_t v : verts) cov += (restPositions[v] - mean) * (restPositions[v] - mean).transpose();
        Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
        const Vec3 axis = eig.eigenvectors().col(2).normalized();
        double lo = 0.0, hi = 0.0;
        std::vector<double> distance;
        for (uint32_t v : verts) {
            const Vec3 d = restPositions[v] - mean;
            const double t = d.dot(axis);
            lo = std::min(lo, t), hi = std::max(hi, t);
            distance.push_back((d - t * axis).norm());
        }
        std::nth_element(distance.begin(), distance.begin() + std::ptrdiff_t(distance.size() / 2), distance.end());
        const double radius = distance[distance.size() / 2];
        if (!(radius > 0.0)) continue;
        // Shortened so the caps reach the extreme vertices, never inverted.
        const double a = std::min(lo + radius, 0.5 * (lo + hi)), b = std::max(hi - radius, 0.5 * (lo + hi));
        const Mat4 toBind = affineInverse(restSkinMatrices[j]);
        const auto bindPoint = [&](const Vec3& x) { return Vec3(toBind.topLeftCorner<3, 3>() * x + toBind.topRightCorner<3, 1>()); };
        // The rest skin may scale (a rig authored in centimetres): the radius stays in rest units,
        // which is what the posed capsule is measured in.
        capsules.push_back({int32_t(j), bindPoint(mean + a * axis), bindPoint(mean + b * axis), radius});
    }
    return capsules;
}

} // namespace cc

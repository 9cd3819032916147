#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/character/Transform.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc {

constexpr int kMaxInfluences = 4;                 ///< joints per vertex
constexpr std::size_t kMaxBodyVertices = 2000000; ///< sanity caps checked before allocation
constexpr std::size_t kMaxBodyTriangles = 4000000;
constexpr double kWeightSumTolerance = 1e-3;      ///< |sum of weights - 1| allowed by validate()

/// A body mesh bound to a skeleton for linear blend skinning: bind-pose positions and normals,
/// triangles (counter-clockwise seen from outside), and per vertex up to four joints with
/// normalised weights (unused slots have weight 0 and joint 0).
///
/// Skin matrix of joint j = global(j) * inverseBindMatrices[j]; at the bind pose every skin matrix
/// is the identity and skinning reproduces bindPositions.
struct SkinnedMesh {
    std::vector<Vec3> bindPositions;                     ///< [m] bind space
    std::vector<Vec3> bindNormals;                       ///< unit, one per vertex
    std::vector<std::array<uint32_t, 3>> triangles;      ///< vertex indices, CCW from outside
    std::vector<std::array<uint16_t, kMaxInfluences>> jointIndices; ///< per vertex
    std::vector<std::array<double, kMaxInfluences>> jointWeights;   ///< per vertex; sum 1, >= 0
    std::vector<Mat4> inverseBindMatrices;               ///< per skeleton joint (bind -> joint space)

    std::size_t vertexCount() const { return bindPositions.size(); }
    /// Checks caps, array sizes, finiteness, unit normals, triangle indices and non-repeated
    /// corners, joint indices < jointCount, weights >= 0 summing to 1 within kWeightSumTolerance.
    /// The message names the first offending vertex, triangle or joint.
    Status validate(std::size_t jointCount) const;
    /// Recomputes bindNormals as area-weighted averages of the adjacent triangle normals.
    void computeBindNormals();
};

/// skin[j] = global[j] * inverseBind[j]. All spans have the skeleton's joint count.
void computeSkinMatrices(Span<const Mat4> globalTransforms, Span<const Mat4> inverseBindMatrices,
                         Span<Mat4> outSkinMatrices);

/// Linear blend skinning of every body vertex into caller-owned arrays (no allocation):
/// p = sum_i w_i M_i p_bind, n = normalise(sum_i w_i A_i n_bind) with A_i the linear part of M_i
/// (exact for rotations and uniform scale). outNormals may be empty to skip normals.
/// Sizes: skinMatrices = joint count, outputs = vertex count (checked; returns an error if not).
Status skinVertices(const SkinnedMesh& mesh, Span<const Mat4> skinMatrices, Span<Vec3> outPositions,
                    Span<Vec3> outNormals);

/// Skins one point with explicit joints and weights (used by attachments and tests).
Vec3 skinPoint(const Vec3& bindPosition, const std::array<uint16_t, kMaxInfluences>& joints,
               const std::array<double, kMaxInfluences>& weights, Span<const Mat4> skinMatrices);

} // namespace cc

#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/character/SkinnedMesh.h"

namespace cc {

/// Binding settings. Distances in metres.
struct SkinBindingSettings {
    double maxBindDistance = 0.25; ///< [m] a vertex farther than this from the body is an error; > 0
    double gridCell = 0.0;         ///< [m] cell of the bind-time search grid; 0 = 2x mean body edge

    Status validate() const;
};

/// One garment vertex bound to the body: the closest body surface point (triangle + barycentric
/// coordinates), the vertex's offset from that point in bind space, and that point's skin
/// influences (barycentric blend of the corner weights, top four, renormalised).
struct BoundVertex {
    uint32_t triangle = 0;
    std::array<double, 3> barycentric{};
    Vec3 offset = Vec3::Zero();                       ///< [m] bind-space vertex - surface point
    std::array<uint16_t, kMaxInfluences> joints{};
    std::array<double, kMaxInfluences> weights{};
};

/// Garment vertices bound to a skinned body, so they follow it exactly (attachments, and the
/// anchors of max-distance/backstop constraints). Immutable after bind(); share it between all
/// instances of a garment on characters with the same body.
///
/// Target of a bound vertex each frame:
///     target = sum_k b_k LBS(v_k) + (sum_i w_i A_i) * offset
/// i.e. the barycentric blend of the three skinned triangle corners (so a vertex on the surface
/// stays exactly on the skinned surface), plus the bind offset carried by the linear part of the
/// point's blended skin matrix. Skinning the vertex itself with the interpolated weights would not
/// stay on the skinned surface: linear blend skinning is not linear in the weights and positions
/// together: over the mannequin's walk that gap reached 3.6 mm (SkinBindingTest).
///
/// The closest point search at bind time uses a uniform grid of triangle bounding boxes, searched
/// in growing shells until no unsearched cell can hold a closer triangle (exact; deterministic).
///
///     Result<SkinBinding> b = SkinBinding::bind(body, garmentBindPositions);
///     b.value().evaluate(body, pose.skinMatrices(), targets, points, normals);
class SkinBinding {
public:
    SkinBinding() = default;

    /// Binds each position (given in the body's bind space) to its closest body surface point.
    /// Errors name the vertex (non-finite, or farther than maxBindDistance) or the body problem.
    static Result<SkinBinding> bind(const SkinnedMesh& body, Span<const Vec3> garmentBindPositions,
                                    const SkinBindingSettings& settings = {});

    /// Binds positions given with the body in a pose (`posedPositions`: the body skinned by
    /// `skinMatrices`), for bodies whose bind-space mesh is not one coherent shape (a file whose
    /// rigid parts sit at their rest place and skinned parts at their bind place): evaluate() with
    /// the same skin matrices gives the positions back. Otherwise as bind().
    static Result<SkinBinding> bindPosed(const SkinnedMesh& body, Span<const Vec3> posedPositions,
                                         Span<const Mat4> skinMatrices, Span<const Vec3> garmentPositions,
                                         const SkinBindingSettings& settings = {});

    std::size_t size() const { return mVertices.size(); }
    const std::vector<BoundVertex>& vertices() const { return mVertices; }

    /// Per bound vertex: its target, the skinned body surface point it is bound to, and the
    /// body's unit normal there (barycentric blend of skinned vertex normals). Any output span may
    /// be empty to skip it; non-empty spans must have size(). No allocation.
    /// The body must be the one bound to (its vertex count is checked).
    Status evaluate(const SkinnedMesh& body, Span<const Mat4> skinMatrices, Span<Vec3> outTargets,
                    Span<Vec3> outSurfacePoints, Span<Vec3> outSurfaceNormals) const;

    /// The same outputs from a body already skinned this frame (positions and unit normals per
    /// body vertex, e.g. from skinVertices() or handed in by a host): cheaper than evaluate() when
    /// the body is skinned anyway. With skin matrices the result equals evaluate(); with an empty
    /// skinMatrices span (host-skinned bodies) the bind offset is carried by the rotation that
    /// takes the bound triangle's bind-pose frame to its current frame (exact for rigid motion).
    Status evaluateSkinned(const SkinnedMesh& body, Span<const Vec3> skinnedPositions,
                           Span<const Vec3> skinnedNormals, Span<const Mat4> skinMatrices,
                           Span<Vec3> outTargets, Span<Vec3> outSurfacePoints,
                           Span<Vec3> outSurfaceNormals) const;

private:
    static Result<SkinBinding> bindAt(const SkinnedMesh& body, Span<const Vec3> positions, Span<const Mat4> skinMatrices,
                                      Span<const Vec3> garmentPositions, const SkinBindingSettings& settings);
    Status checkSizes(const SkinnedMesh& body, Span<Vec3> outTargets, Span<Vec3> outSurfacePoints,
                      Span<Vec3> outSurfaceNormals) const;

    std::vector<BoundVertex> mVertices;
    std::size_t mBodyVertexCount = 0;
    std::size_t mBodyTriangleCount = 0;
};

/// Closest point to p on triangle (a, b, c) and its barycentric coordinates (Ericson, Real-Time
/// Collision Detection, 5.1.5).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            std::array<double, 3>& outBarycentric);

} // namespace cc

#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "crowdcloth/collision/BodyTopology.h"
#include "crowdcloth/collision/CollisionDevice.h"
#include "crowdcloth/collision/Collider.h"
#include "crowdcloth/collision/ContactQuery.h"
#include "crowdcloth/core/Contact.h"
#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// Settings of one body collider.
struct BodyColliderSettings {
    double rebuildFraction = 0.1;  ///< [-] the trees are updated in place every update (the
                                   ///< surface's rebuilt, the swept boxes' refit) and made anew when
                                   ///< the mean vertex displacement since the last build exceeds
                                   ///< this fraction of the body's bounding-box diagonal (a refit
                                   ///< keeps the tree's topology, so its quality drops with large
                                   ///< motion); (0, 100]
    double degenerateArea = 1e-12; ///< [-] a triangle whose area is below this fraction of its
                                   ///< longest edge squared is degenerate and skipped by queries
                                   ///< (its edges belong to its neighbours); [0, 0.1]

    /// Names the first invalid field.
    Status validate() const;
};

/// Counters of one collider, for stats and tests.
struct BodyColliderStats {
    uint64_t refits = 0;              ///< [-] updates served by a refit
    uint64_t rebuilds = 0;            ///< [-] full BVH builds (including the first)
    uint32_t degenerateTriangles = 0; ///< [-] zero-area triangles skipped in the current pose
};

/// An animated body (one character's skinned triangle mesh, possibly several closed surfaces) in
/// an Embree scene, refit each frame and shared by every garment of the character.
///
/// Normals point out of the body: triangles are counter-clockwise seen from outside. Inside and
/// outside are decided with angle-weighted pseudonormals (Baerentzen & Aanaes 2005), so a point
/// nearest to an edge or vertex gets the right side too. A degenerate triangle (see settings) is
/// skipped in the pose where it is degenerate and counted in stats().
///
/// Thread-safety: update()/reset() must not run concurrently with anything else on the collider;
/// the const queries may run concurrently with each other (every garment of the character).
///
///   auto body = BodyCollider::create(device, triangles, bindPose).value();
///   body->update(skinned, dt);                       // once per frame
///   body->queryProximity(cloth.positions, query, contacts);
class BodyCollider final : public Collider {
public:
    /// `triangles` index `positions` (the initial pose, which is also the previous pose; also the
    /// pose its vertices are welded in, see BodyTopology).
    static Result<std::unique_ptr<BodyCollider>> create(CollisionDevice& device,
                                                        Span<const std::array<uint32_t, 3>> triangles,
                                                        Span<const Vec3> positions,
                                                        const BodyColliderSettings& settings = {});
    /// The same on a body's shared topology (built once per body asset).
    static Result<std::unique_ptr<BodyCollider>> create(CollisionDevice& device,
                                                        std::shared_ptr<const BodyTopology> shape,
                                                        Span<const Vec3> positions,
                                                        const BodyColliderSettings& settings = {});
    ~BodyCollider();
    BodyCollider(const BodyCollider&) = delete;
    BodyCollider& operator=(const BodyCollider&) = delete;

    /// The pose at the end of a step of dt [s] (> 0): the current pose becomes the previous one,
    /// surface velocities are (current - previous) / dt, and the BVH is refit (or rebuilt).
    /// On error (wrong count, non-finite vertex, bad dt) nothing changes.
    Status update(Span<const Vec3> positions, double dt);
    /// Teleports the body: previous = current = positions, zero velocity; the trees are refit, or
    /// rebuilt when the pose is far from the one they were built on (as in update()).
    Status reset(Span<const Vec3> positions);

    /// For every point within query.reach(i) of the current surface: the closest surface point,
    /// outward normal, depth and surface velocity, appended to outContacts sorted by vertex (the
    /// point's index in `points`, which must be finite). outContacts is cleared first.
    Status queryProximity(Span<const Vec3> points, const ContactQuery& query,
                          std::vector<Contact>& outContacts) const override;

    /// For every point moving linearly from start[i] to end[i] over the step that comes within
    /// thickness / 4 of a triangle moving linearly from its previous to its current pose (Ccd.h's
    /// vertexTriangleCcd, candidates gathered from an Embree tree of the triangles' swept boxes):
    /// a contact at the first time of impact, with that triangle's point (same barycentric
    /// weights) and outward normal at the end of the step. Only a point that starts on the outer
    /// side of the triangle counts: one already behind it is a penetration for the proximity
    /// contact; and only one that ends less than query.thickness above the triangle's plane (else
    /// the contact's depth would be <= 0: it asks for nothing). The search resolves the gap to half
    /// of thickness / 4 and the time to 1e-3 of the step. Sorted by vertex, one contact per vertex.
    /// outContacts is cleared first.
    Status queryContinuous(Span<const Vec3> start, Span<const Vec3> end, const ContactQuery& query,
                           std::vector<Contact>& outContacts) const override;

    /// Collider::traceRays on the current pose (Embree rays collecting every crossing).
    Status traceRays(Span<const Vec3> origins, Span<const Vec3> directions, RayParts parts,
                     Span<RayTrace> outTraces) const override;

    uint32_t vertexCount() const;
    uint32_t triangleCount() const;
    Span<const Vec3> currentPositions() const;
    Span<const Vec3> previousPositions() const;
    const BodyColliderStats& stats() const;

    struct Impl;

private:
    explicit BodyCollider(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> mImpl;
};

} // namespace cc::collision

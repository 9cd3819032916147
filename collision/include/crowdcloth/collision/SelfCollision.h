#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/collision/Ccd.h"
#include "crowdcloth/collision/TriangleBvh.h"
#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/ParallelFor.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::collision {

/// Tuning of one garment's self-collision.
struct SelfCollisionSettings {
    double thickness = 3.0e-3;        ///< [m] repulsion keeps non-adjacent primitives this far apart; > 0
    double repulsionFraction = 0.25;  ///< [-] share of the overlap below `thickness` undone per step;
                                      ///< [0, 1]; 0 = only stop approaching pairs
    double ccdGap = 1.0e-4;           ///< [m] gap the continuous tests keep; a pair that starts closer
                                      ///< keeps a quarter of its start gap; (0, thickness]
    int impulseIterations = 8;        ///< [-] continuous test + inelastic impulse passes before the
                                      ///< impact zones take over; >= 1
    int zoneIterations = 32;          ///< [-] impact-zone passes before the last resort (stopping the
                                      ///< vertices still colliding); >= 1
    ParallelSettings parallel;        ///< threads for the continuous tests (results do not depend on it)

    /// Names the first invalid field.
    Status validate() const;
};

/// What one resolve() call did.
struct SelfCollisionStats {
    uint32_t proximityPairs = 0;       ///< vertex-triangle + edge-edge pairs closer than thickness at x0
    uint32_t repulsions = 0;           ///< of those, pairs that got a repulsion or inelastic impulse
    uint32_t ccdTests = 0;             ///< continuous tests run, all passes
    uint32_t firstPassCollisions = 0;  ///< collisions found by the first continuous pass
    uint32_t impulseIterations = 0;    ///< continuous passes with impulses
    uint32_t zoneIterations = 0;       ///< impact-zone passes
    uint32_t failSafeActivations = 0;  ///< 1 when impulses did not suffice and impact zones ran, else 0
    uint32_t impactZones = 0;          ///< rigid zones at the end
    uint32_t zoneVertices = 0;         ///< vertices in those zones
    uint32_t stoppedVertices = 0;      ///< vertices held at x0 by the last resort
    uint32_t unresolved = 0;           ///< collisions left: only pinned vertices move in them
    uint32_t cappedTests = 0;          ///< continuous tests that hit their box budget (conservative)
    uint64_t ccdBoxes = 0;             ///< search boxes over all continuous tests (their cost)
};

/// Self-collision of one garment over one step (Bridson, Fedkiw & Anderson 2002, "Robust treatment
/// of collisions, contact and friction for cloth animation"): repulsion of vertex-triangle and
/// edge-edge pairs closer than the thickness at the start of the step, then continuous tests over
/// the step with inelastic impulses, iterated, and rigid impact zones (Provot 1997, "Collision and
/// self-collision handling in cloth model dedicated to design garments") as the fail-safe. Adjacent
/// primitives (a vertex of the triangle, edges sharing a vertex) are skipped.
///
/// Works on positions: x0 at the start of the step (assumed free of intersections) and the solver's
/// candidate end positions x1, which resolve() adjusts; the caller then sets the velocities to
/// (x1 - x0) / dt. Every list is sorted and impulses are applied in that order, so the result does
/// not depend on the thread count. Owns its scratch memory; not thread-safe (one per garment).
///
///   auto self = SelfCollision::create(mesh.triangles, mesh.vertexCount(), {}).value();
///   x0 = state.positions; sim.step(dt); x1 = state.positions;
///   self.resolve(x0, x1, masses, stats);   // masses: 0 or +inf for pinned vertices
///   state.positions = x1; velocities = (x1 - x0) / dt;
class SelfCollision {
public:
    SelfCollision() = default;
    /// Fails on an out-of-range index, a repeated vertex in a triangle, or invalid settings.
    static Result<SelfCollision> create(Span<const std::array<uint32_t, 3>> triangles, uint32_t vertexCount,
                                        const SelfCollisionSettings& settings);

    /// Adjusts x1 [m] so that no non-adjacent primitives cross during the linear motion x0 -> x1.
    /// masses [kg] per vertex; 0 or +inf = pinned (never moved). Fails, leaving x1 unchanged, on
    /// sizes that do not match or a non-finite position (the message names the vertex).
    Status resolve(Span<const Vec3> x0, Span<Vec3> x1, Span<const double> masses, SelfCollisionStats& outStats);

    const SelfCollisionSettings& settings() const { return mSettings; }
    uint32_t vertexCount() const { return mVertexCount; }
    Span<const std::array<uint32_t, 3>> triangles() const { return mTriangles; }
    Span<const std::array<uint32_t, 2>> edges() const { return mEdges; }

    /// Vertex-triangle and edge-edge pairs (non-adjacent) whose boxes, swept from x0 to x1 and
    /// grown by `margin` [m], overlap; sorted. Exposed for the broad-phase tests.
    void candidates(Span<const Vec3> x0, Span<const Vec3> x1, double margin,
                    std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                    std::vector<std::array<uint32_t, 2>>& outEdgeEdge);

private:
    struct Collision {
        std::array<uint32_t, 4> vertices;  ///< VF: p, a, b, c; EE: a, b, c, d
        std::array<double, 4> weights;     ///< signed: separation = sum weights[i] * x[vertices[i]]
        Vec3 normal;
    };
    void applyProximity(Span<const Vec3> x0, Span<Vec3> x1, SelfCollisionStats& stats);
    void findCollisions(Span<const Vec3> x0, Span<const Vec3> x1, std::vector<Collision>& outCollisions,
                        SelfCollisionStats& stats);
    void applyImpulse(const Collision& c, Span<const Vec3> x0, Span<Vec3> x1) const;
    void rigidifyZones(Span<const Vec3> x0, Span<Vec3> x1, const std::vector<Collision>& collisions,
                       SelfCollisionStats& stats);

    SelfCollisionSettings mSettings;
    uint32_t mVertexCount = 0;
    std::vector<std::array<uint32_t, 3>> mTriangles;
    std::vector<std::array<uint32_t, 2>> mEdges;          ///< sorted, a < b
    std::vector<std::array<uint32_t, 3>> mTriangleEdges;  ///< edge indices of each triangle
    TriangleBvh mBvh;
    bool mBvhBuilt = false;
    // Per-step scratch.
    std::vector<double> mInvMass;
    std::vector<Aabb> mBoxes;
    std::vector<uint32_t> mZoneParent;  ///< union-find over vertices, root = smallest index
    std::vector<uint8_t> mInZone;
};

} // namespace cc::collision

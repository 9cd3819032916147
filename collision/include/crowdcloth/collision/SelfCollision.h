#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/collision/Ccd.h"
#include "crowdcloth/collision/TriangleBvh.h"
#include "crowdcloth/core/Contact.h"
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
    bool proximityPass = true;        ///< repulsion of pairs closer than `thickness` at x0 before the
                                      ///< continuous tests; off when the solve kept pairs apart by
                                      ///< separatingPlanes(), which repel the same pairs inside it
    int impulseIterations = 8;        ///< [-] continuous test + inelastic impulse passes before the
                                      ///< impact zones take over; >= 1
    int zoneIterations = 32;          ///< [-] impact-zone passes before the last resort (stopping the
                                      ///< vertices still colliding); >= 1
    uint32_t maxPairsPerTriangle = 64;  ///< [-] a search that meets more overlapping triangle pairs
                                        ///< than this per triangle stops: the garment is crumpled
                                        ///< (cloth meets 7-32 a triangle, a coarse fold prolonged to a
                                        ///< fine level 480) and is left to itself; >= 1
    ParallelSettings parallel;        ///< threads for the continuous tests (results do not depend on it)

    /// Names the first invalid field.
    Status validate() const;
};

/// What one resolve() call did.
struct SelfCollisionStats {
    uint32_t proximityPairs = 0;       ///< vertex-triangle + edge-edge pairs closer than thickness at x0
    uint32_t repulsions = 0;           ///< of those, pairs that got a repulsion or inelastic impulse
    uint32_t ccdTests = 0;             ///< candidate pairs of the continuous tests, all passes (a pass
                                       ///< after the first re-tests only those its predecessor moved)
    uint32_t broadPhases = 0;          ///< broad-phase searches for them; the other passes filtered
                                       ///< the pairs separatingPlanes() kept for the step
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
    uint32_t crowded = 0;              ///< 1 when a search stopped at maxPairsPerTriangle: the call
                                       ///< ended there, leaving the rest of x1 as it was
};

/// Where separatingPlanes() puts the planes a solve keeps pairs apart by.
struct SeparatingPlaneSettings {
    double thickness = 3.0e-3;        ///< [m] pairs may approach to this distance; > 0
    double repulsionFraction = 0.25;  ///< [-] share of the overlap below `thickness` a pair closer than
                                      ///< it at the start is moved apart by over the step; [0, 1]
    double lookahead = 2.0;           ///< [-] a pair gets planes when it can come within `thickness`
                                      ///< moving `lookahead` times its velocity over the step; >= 0
    double maxReach = 0.1;            ///< [m] most a vertex's motion counts towards that; > 0
    double acceleration = 9.81;       ///< [m/s^2] how hard a pair may close from rest over the look-ahead
                                      ///< (gravity, for a layer falling onto one the body holds); >= 0
    double solverOffset = 0.0;        ///< [m] the solver puts a contact's plane this far outside its
                                      ///< point (SubstepSettings::contactThickness); the points are
                                      ///< placed so that the plane lands where it must; >= 0

    /// Names the first invalid field.
    Status validate() const;
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

    /// Self-contacts as constraints of the solve: for every vertex-triangle and edge-edge pair that
    /// can come within the thickness over the step (from x0, moving at `velocities` [m/s] for
    /// `lookahead` x dt [s]), the plane through the midpoint of its closest points at x0, normal to
    /// the line between them, offset by half the kept distance to each side; every vertex of each
    /// side gets its side's plane as a Contact (point on the plane less `solverOffset`, the plane
    /// moving at the pair's mean velocity, which is its surfaceVelocity, so a pair falling together
    /// is not held). The closest points of two disjoint convex primitives span a separating plane
    /// of them, so a vertex is never pushed by a plane it does not reach, and while every vertex
    /// keeps to its planes the pair cannot cross (its distance along the normal stays linear in time
    /// between the solver's substeps). In a crease this keeps the solve itself from folding the cloth
    /// through itself, and neighbours answer a contact inside the solve instead of resolve()'s
    /// impulses after it, which a stiff crumpled region stores as strain (the blow-up a sheet folding
    /// onto itself showed). Appends to outPlanes, sorted by vertex; allocates only while its scratch
    /// grows. Appends nothing for a crumpled garment (crowded()). Fails, appending nothing, on
    /// mismatched sizes or a non-finite input (naming the vertex).
    Status separatingPlanes(Span<const Vec3> x0, Span<const Vec3> velocities, double dt,
                            const SeparatingPlaneSettings& settings, std::vector<Contact>& outPlanes);

    const SelfCollisionSettings& settings() const { return mSettings; }
    /// The last search stopped at maxPairsPerTriangle (see SelfCollisionStats::crowded).
    bool crowded() const { return mCrowded; }
    uint32_t vertexCount() const { return mVertexCount; }
    Span<const std::array<uint32_t, 3>> triangles() const { return mTriangles; }
    Span<const std::array<uint32_t, 2>> edges() const { return mEdges; }

    /// Vertex-triangle and edge-edge pairs (non-adjacent) whose boxes, swept from x0 to x1 and
    /// grown by `margin` [m], overlap; sorted. False, with the lists empty, when the search stopped
    /// at maxPairsPerTriangle. Exposed for the broad-phase tests.
    bool candidates(Span<const Vec3> x0, Span<const Vec3> x1, double margin,
                    std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                    std::vector<std::array<uint32_t, 2>>& outEdgeEdge);

private:
    struct Collision {
        std::array<uint32_t, 4> vertices;  ///< VF: p, a, b, c; EE: a, b, c, d
        std::array<double, 4> weights;     ///< signed: separation = sum weights[i] * x[vertices[i]]
        Vec3 normal;
    };
    /// Broad-phase pairs kept for later calls: every non-adjacent pair whose per-vertex `boxes`
    /// grown by `margin` overlap, sorted.
    struct PairCache {
        std::vector<Aabb> boxes;
        std::vector<std::array<uint32_t, 2>> vf, ee;
        double margin = 0.0;
        bool valid = false;
    };
    /// maxPairsPerTriangle for the whole mesh.
    std::size_t maxTrianglePairs() const;
    /// candidates() of any per-vertex boxes: pairs whose primitives' hulls of them, grown by
    /// `margin`, overlap. False (crowded) when the search stopped at maxTrianglePairs().
    bool candidatesOfBoxes(Span<const Aabb> vertexBoxes, double margin,
                           std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                           std::vector<std::array<uint32_t, 2>>& outEdgeEdge);
    /// The same lists as candidatesOfBoxes(vertexBoxes, margin) from a cache whose boxes hold most of
    /// these: its pairs filtered, and a search for the pairs of the few vertices that left their
    /// cached box (marked). False, writing nothing, when the cache cannot serve.
    bool pairsFromCache(const PairCache& cache, Span<const Aabb> vertexBoxes, double margin,
                        std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                        std::vector<std::array<uint32_t, 2>>& outEdgeEdge);
    /// mVertexBoxes: each vertex's box over its motion from x0 to x1.
    void sweptBoxes(Span<const Vec3> x0, Span<const Vec3> x1);
    /// The tree over mTreeBoxes: built the first time, refit after.
    void fitTree();
    /// mBoxes (each triangle's hull of its vertices' boxes, grown by margin), mTreeBoxes (the
    /// same grown by mTreeMargin, about half the margin) and mEdgeBoxes.
    void hullBoxes(Span<const Aabb> vertexBoxes, double margin);
    /// A box to ask the tree for the triangles whose mBoxes may meet `box` (a superset).
    Aabb treeQuery(const Aabb& box) const;
    /// The broad phase's box test of two edges (their boxes of the last hullBoxes(), one grown by its
    /// margin), the same whichever is named first.
    bool edgesOverlap(uint32_t e, uint32_t f) const;
    /// The vertex-triangle and edge-edge pairs of mTrianglePairs (each through its owners) whose
    /// boxes overlap; with `markedOnly`, only those with a vertex in mMarked.
    void pairsOfTrianglePairs(Span<const Aabb> vertexBoxes, bool markedOnly,
                              std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                              std::vector<std::array<uint32_t, 2>>& outEdgeEdge);
    /// Sorts pairs (first index below firstCount, second below secondCount), without allocating
    /// once warm.
    void sortPairs(std::vector<std::array<uint32_t, 2>>& pairs, uint32_t firstCount, uint32_t secondCount);
    /// Both candidate lists sorted (sortPairs), so results do not depend on the search's order.
    void sortCandidates(std::vector<std::array<uint32_t, 2>>& vertexTriangle,
                        std::vector<std::array<uint32_t, 2>>& edgeEdge);
    /// An end of edge e is in mMarked.
    bool markedEdge(uint32_t e) const;
    /// mMarkedTriangle from mMarked: 1 = holds a marked vertex.
    void markTriangles();
    /// Appends the pairs with a marked vertex whose boxes (of the last hullBoxes()) overlap: one
    /// descent of the tree through the marked triangles. Unsorted. False (crowded) when the search
    /// stopped at maxTrianglePairs().
    bool appendMarkedPairs(Span<const Aabb> vertexBoxes, std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                           std::vector<std::array<uint32_t, 2>>& outEdgeEdge);
    /// The candidates of findCollisions()'s later passes: the pairs with a vertex in mChanged whose
    /// swept boxes, grown by margin, overlap; sorted. False when crowded.
    bool changedCandidates(Span<const Vec3> x0, Span<const Vec3> x1, double margin,
                           std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                           std::vector<std::array<uint32_t, 2>>& outEdgeEdge);
    /// candidates(x0, x1, margin): from the pairs separatingPlanes() found for the same x0 where
    /// they serve, else a new search (counted in stats.broadPhases). False when crowded.
    bool sweptCandidates(Span<const Vec3> x0, Span<const Vec3> x1, double margin,
                         std::vector<std::array<uint32_t, 2>>& outVertexTriangle,
                         std::vector<std::array<uint32_t, 2>>& outEdgeEdge, SelfCollisionStats& stats);
    void applyProximity(Span<const Vec3> x0, Span<Vec3> x1, SelfCollisionStats& stats);
    /// The collisions of x0 -> x1 (a pass after the first: of the pairs with a changed vertex).
    /// False, with none, when its search was crowded.
    bool findCollisions(Span<const Vec3> x0, Span<const Vec3> x1, std::vector<Collision>& outCollisions,
                        SelfCollisionStats& stats);
    /// resolve()'s end when a search was crowded.
    Status crowdedResolve(SelfCollisionStats& stats);
    void applyImpulse(const Collision& c, Span<const Vec3> x0, Span<Vec3> x1) const;
    void rigidifyZones(Span<const Vec3> x0, Span<Vec3> x1, const std::vector<Collision>& collisions,
                       SelfCollisionStats& stats);

    SelfCollisionSettings mSettings;
    uint32_t mVertexCount = 0;
    std::vector<std::array<uint32_t, 3>> mTriangles;
    std::vector<std::array<uint32_t, 2>> mEdges;          ///< sorted, a < b
    std::vector<uint32_t> mEdgeTriangle;                 ///< the first triangle (by index) of each edge
    /// The vertices and edges a triangle owns (it is the first triangle holding them): the broad
    /// phase meets each vertex and edge through its owner only.
    struct Owned {
        uint32_t vertexCount = 0, edgeCount = 0;
        std::array<uint32_t, 3> vertices{}, edges{};
    };
    std::vector<Owned> mOwned;
    std::vector<uint32_t> mLoneVertices;          ///< vertices of no triangle
    std::vector<std::array<uint32_t, 2>> mTrianglePairs, mSortedPairs;  ///< broad-phase scratch
    std::vector<uint32_t> mBucketStart;                                 ///< sortPairs' scratch
    TriangleBvh mBvh;
    bool mBvhBuilt = false;
    // Per-step scratch.
    std::vector<double> mInvMass;
    std::vector<Aabb> mBoxes, mTreeBoxes, mEdgeBoxes, mGrownEdgeBoxes;
    double mTreeMargin = 0.0;  ///< [m] mTreeBoxes' growth
    std::vector<uint32_t> mHits;
    std::vector<Vec3> mReachEnd;                              ///< separatingPlanes: x0 + lookahead motion
    std::vector<Vec3> mNormals;                               ///< separatingPlanes: per triangle at x0
    std::vector<std::array<uint32_t, 2>> mPairsVf, mPairsEe;  ///< applyProximity's, findCollisions' candidates
    std::vector<Aabb> mVertexBoxes;
    // separatingPlanes(): the update's pairs, which resolve() filters for the same x0.
    PairCache mUpdate;
    std::vector<Vec3> mUpdateStart;  ///< the x0 mUpdate is for
    /// Per vertex, 1 = its pairs are searched in the tree: it left its cached box (pairsFromCache)
    /// or moved since findCollisions()' last pass (changedCandidates).
    std::vector<uint8_t> mMarked;
    std::vector<uint8_t> mMarkedTriangle;  ///< per triangle, 1 = holds a marked vertex
    std::vector<Contact> mPlanes;       ///< separatingPlanes: kPlanesPerVertex slots per vertex
    std::vector<uint8_t> mPlaneCount;   ///< slots in use per vertex
    std::vector<uint32_t> mZoneParent;  ///< union-find over vertices, root = smallest index
    std::vector<uint8_t> mInZone;
    std::vector<std::array<uint32_t, 2>> mZoneMembers;  ///< rigidifyZones: (root, vertex)
    std::vector<Collision> mCollisions, mFound;         ///< resolve's and findCollisions' scratch
    std::vector<uint8_t> mStatus, mStopped;
    std::vector<uint32_t> mBoxCounts;
    // findCollisions' passes within one resolve(): what the last one saw.
    bool mRetestMovedOnly = false;            ///< not the resolve's first pass
    std::vector<Vec3> mLastEnd;               ///< x1 of the last pass
    std::vector<uint8_t> mInLastCollision;    ///< per vertex: in one of the last pass's collisions
    std::vector<uint8_t> mChanged;            ///< per vertex: to re-test this pass
    // The last resolve(): its x0, and whether it ended with no collision left.
    std::vector<Vec3> mResolveStart;
    bool mLastResolveClean = false;
    bool mCrowded = false;  ///< the last search stopped at maxTrianglePairs()
};

} // namespace cc::collision

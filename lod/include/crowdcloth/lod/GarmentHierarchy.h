#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "crowdcloth/core/SparseInterpolation.h"
#include "crowdcloth/lod/ActiveMesh.h"
#include "crowdcloth/lod/GarmentPattern.h"
#include "crowdcloth/lod/RefinementSettings.h"

namespace cc::lod {

/// Cook-time choices for one garment's hierarchy.
struct HierarchySettings {
    double arealDensity = 0.15;  ///< [kg/m^2] mass per rest area (match cloth::ClothMaterial); (0, 100]
    uint32_t maxLevel = 10;      ///< [-] finest level a triangle may reach (each level halves its area);
                                 ///< [0, 20]
    uint32_t renderLevel = 6;    ///< [-] level of the fixed render mesh; [0, maxLevel]
    uint32_t vertexBudget = 0;   ///< [vertices] most active vertices adapt() keeps; 0 = unlimited
    uint32_t maxRenderVertices = 4u << 20;  ///< [vertices] guard against absurd render levels; >= 1
    uint32_t morphFrames = 8;    ///< [frames] a merged vertex's detail fades out of the render mesh over
                                 ///< this many advanceMorph() calls; 0 = drops at the next call

    Status validate() const;
};

/// One garment at many resolutions: a 4-8 (bintree) hierarchy over the pattern's base grids
/// (Velho & Zorin 2001, "4-8 subdivision"; the split/merge discipline of ROAM, Duchaineau et al. 1997).
///
/// A triangle is split at the midpoint of its longest (base) edge together with its neighbour
/// across that edge (a diamond); if the neighbour is coarser it is split first, recursively, so the
/// active mesh is always conforming and neighbours differ by at most one level, across seams and a
/// tube's wrap-around side too. A diamond merges back only when its children are all leaves.
/// Vertex and triangle ids are stable: splitting and merging the same diamond reuses them.
///
/// State lives here between solver rebuilds: masses are lumped from rest area (exact total at all
/// times); a split gives the new vertex the world midpoint and the mean velocity of the edge's ends
/// (momentum unchanged); a merge returns the removed vertex's mass and momentum to the edge's ends.
///
///   auto pattern = GarmentPattern::cape(1.0, 1.2, 0.25).value();
///   auto h = GarmentHierarchy::create(pattern, HierarchySettings{}).value();
///   h.setUniformLevel(3);
///   ActiveMesh active = h.activeMesh();            // -> cloth::ClothSimulation::create(active.mesh, ...)
///   ... step ...; h.readState(active, positions, velocities);
///   if (h.adapt(criteria, input).value().changed()) active = h.activeMesh();  // rebuild the solver
///   h.renderPositions(renderPositions, renderNormals);
class GarmentHierarchy {
public:
    static constexpr uint32_t kNone = 0xffffffffu;

    /// A node of the bintree forest (a triangle at some level), active or not.
    struct Triangle {
        std::array<uint32_t, 3> vertices;  ///< apex, base0, base1; counter-clockwise in pattern space
        std::array<Vec2, 3> rest;          ///< [m] pattern (u, v) of each corner in its panel
        uint32_t panel;
        uint32_t level;
        uint32_t parent;                   ///< kNone for a base triangle
        std::array<uint32_t, 2> children;  ///< kNone until first split
        bool active;                       ///< a leaf of the current mesh
    };

    GarmentHierarchy() = default;
    /// Builds the base mesh (level 0 active) and the render mesh at settings.renderLevel.
    static Result<GarmentHierarchy> create(const GarmentPattern& pattern, const HierarchySettings& settings);

    // --- structure ---------------------------------------------------------------------------
    const GarmentPattern& pattern() const { return mPattern; }
    const HierarchySettings& settings() const { return mSettings; }
    /// Stable id of base grid point (i, j) of a panel (a tube's i = columns is i = 0).
    uint32_t baseVertex(uint32_t panel, uint32_t i, uint32_t j) const;
    uint32_t vertexCount() const { return static_cast<uint32_t>(mVertices.size()); }  ///< ever created
    uint32_t activeVertexCount() const { return mActiveVertexCount; }
    uint32_t activeTriangleCount() const { return mActiveTriangleCount; }
    bool isActive(uint32_t vertex) const { return mVertices[vertex].active; }
    uint32_t vertexLevel(uint32_t vertex) const { return mVertices[vertex].level; }
    /// The edge whose midpoint `vertex` is, or {kNone, kNone} for a base vertex.
    std::array<uint32_t, 2> edgeEnds(uint32_t vertex) const { return mVertices[vertex].ends; }
    const Triangle& triangle(uint32_t id) const { return mTriangles[id]; }
    uint32_t triangleCount() const { return static_cast<uint32_t>(mTriangles.size()); }  ///< ever created
    /// Ids of the active triangles, ascending.
    std::vector<uint32_t> activeTriangles() const;

    // --- refinement --------------------------------------------------------------------------
    /// Splits active triangle `id` (and, first, whatever coarser neighbours conformity needs).
    /// outSplit, if given, receives the midpoint vertex of each diamond split, in order; merging them
    /// in reverse order restores the mesh. Fails if `id` is not active or is at maxLevel.
    Status refine(uint32_t id, std::vector<uint32_t>* outSplit = nullptr);
    /// True when `vertex` is an active midpoint whose diamond's children are all leaves.
    bool canCoarsen(uint32_t vertex) const;
    /// Merges the diamond whose midpoint is `vertex`; fails with the reason if !canCoarsen(vertex).
    Status coarsen(uint32_t vertex);
    /// Active vertices that coarsen() accepts now, ascending.
    std::vector<uint32_t> coarsenableVertices() const;
    /// Refines and coarsens until every active triangle is at `level` (<= maxLevel).
    Status setUniformLevel(uint32_t level);
    /// One frame of adaptation by `settings` (see RefinementSettings). The state must be current
    /// (readState after the solver step).
    Result<AdaptStats> adapt(const RefinementSettings& settings, const AdaptInput& input);

    // --- state -------------------------------------------------------------------------------
    const Vec3& position(uint32_t vertex) const { return mVertices[vertex].position; }
    const Vec3& velocity(uint32_t vertex) const { return mVertices[vertex].velocity; }
    double mass(uint32_t vertex) const { return mVertices[vertex].mass; }  ///< [kg] 0 when inactive
    /// Sets an active vertex's position [m] and velocity [m/s].
    Status setState(uint32_t vertex, const Vec3& position, const Vec3& velocity);
    double totalMass() const;
    Vec3 totalMomentum() const;
    double kineticEnergy() const;

    // --- the solver's view -------------------------------------------------------------------
    /// The active mesh as a ClothMesh with index maps, masses and the current state.
    ActiveMesh activeMesh() const;
    /// Takes the solver's state back (positions [m], velocities [m/s] per simulation index of
    /// `active`, which must be the current active mesh). Welded copies are averaged by mass.
    Status readState(const ActiveMesh& active, Span<const Vec3> positions, Span<const Vec3> velocities);
    /// Writes the current state into simulation arrays laid out like `active`.
    void writeState(const ActiveMesh& active, std::vector<Vec3>& outPositions, std::vector<Vec3>& outVelocities) const;
    /// Weights of hierarchy vertices `vertices` over the simulation vertices of `active` (the current
    /// active mesh): piecewise-linear interpolation through the hierarchy's midpoints.
    Result<SparseInterpolation> interpolation(const ActiveMesh& active, Span<const uint32_t> vertices) const;

    // --- render mesh of fixed topology -------------------------------------------------------
    /// Render vertex r is hierarchy vertex r, r < renderVertexCount().
    uint32_t renderVertexCount() const { return mRenderVertexCount; }
    /// Triangles of the render mesh (render vertex indices, CCW in pattern space); never changes.
    const std::vector<std::array<uint32_t, 3>>& renderTriangles() const { return mRenderTriangles; }
    /// Positions [m] of every render vertex, interpolated from the active vertices through the
    /// hierarchy, and area-weighted unit normals. Continuous across refine/coarsen.
    void renderPositions(std::vector<Vec3>& outPositions, std::vector<Vec3>& outNormals) const;
    /// Fades the detail of recently merged vertices by one frame (see HierarchySettings::morphFrames).
    void advanceMorph();

private:
    struct Vertex {
        Vec3 position = Vec3::Zero();
        Vec3 velocity = Vec3::Zero();
        Vec3 morph = Vec3::Zero();     // render detail left by a merge, fading
        double mass = 0.0;
        std::array<uint32_t, 2> ends{kNone, kNone};     // edge this is the midpoint of
        std::array<uint32_t, 2> diamond{kNone, kNone};  // triangles whose split creates it
        uint32_t level = 0;
        uint32_t morphFramesLeft = 0;
        bool morphListed = false;      // in mMorphing
        bool active = false;
    };
    struct EdgeSlots {
        std::array<uint32_t, 2> triangles{kNone, kNone};
    };

    static uint64_t edgeKey(uint32_t a, uint32_t b) {
        return a < b ? (uint64_t(a) << 32 | b) : (uint64_t(b) << 32 | a);
    }
    double restArea(uint32_t t) const;
    uint32_t neighbour(uint32_t t, uint32_t a, uint32_t b) const;
    void activate(uint32_t t);
    void deactivate(uint32_t t);
    uint32_t makeChild(uint32_t parent, uint32_t midpoint, int which, const Vec2& restMid);
    Status splitLeaf(uint32_t t, std::vector<uint32_t>* outSplit, int depth);
    void splitDiamond(uint32_t t, uint32_t n, std::vector<uint32_t>* outSplit);
    double triangleDemand(uint32_t t, const RefinementSettings& settings, const AdaptInput& input,
                          const std::vector<uint32_t>& vertexToSim) const;
    /// Simulation vertex numbering of the current active mesh (see ActiveMesh); fills what is asked.
    void numberSimVertices(ActiveMesh& out, bool withMesh) const;

    GarmentPattern mPattern;
    HierarchySettings mSettings;
    std::vector<uint32_t> mBaseVertexIds;   // per panel, (columns + 1) * (rows + 1) grid ids
    std::vector<uint32_t> mPanelBaseOffset;
    std::vector<Vertex> mVertices;
    std::vector<Triangle> mTriangles;
    std::vector<uint32_t> mQuiet;           // per triangle: consecutive quiet adapt() calls
    std::unordered_map<uint64_t, uint32_t> mMidpoints;  // edge -> midpoint vertex
    std::unordered_map<uint64_t, EdgeSlots> mEdges;     // edge -> the active triangles beside it
    std::vector<uint32_t> mMorphing;        // vertices with a fading morph offset, ascending
    uint32_t mActiveVertexCount = 0;
    uint32_t mActiveTriangleCount = 0;
    uint32_t mRenderVertexCount = 0;
    std::vector<std::array<uint32_t, 3>> mRenderTriangles;
};

} // namespace cc::lod

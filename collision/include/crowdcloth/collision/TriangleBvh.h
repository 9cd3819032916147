#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"

namespace cc::collision {

/// Axis-aligned box [m].
struct Aabb {
    Vec3 lo = Vec3::Constant(1e300);
    Vec3 hi = Vec3::Constant(-1e300);

    void grow(const Vec3& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    void inflate(double margin) {
        lo.array() -= margin;
        hi.array() += margin;
    }
    /// Closed test: boxes that only touch overlap. Without short circuits: the broad phases ask it
    /// of neighbours about as often true as false, where a branch per axis is mispredicted.
    bool overlaps(const Aabb& o) const {
        const unsigned all = unsigned(lo.x() <= o.hi.x()) & unsigned(o.lo.x() <= hi.x()) &
                             unsigned(lo.y() <= o.hi.y()) & unsigned(o.lo.y() <= hi.y()) &
                             unsigned(lo.z() <= o.hi.z()) & unsigned(o.lo.z() <= hi.z());
        return all != 0;
    }
};

/// Bounding-volume tree over a fixed set of primitive boxes (a garment's triangles): the topology is
/// built once by median splits, and refit() only recomputes the boxes, so a deforming garment keeps
/// its tree for its whole life.
///
/// Why not Embree: rtcCollide needs user geometry and calls back concurrently, so its pairs would
/// have to be gathered and sorted anyway; a garment of a few thousand triangles is small enough that
/// a refit binary tree and plain per-primitive queries cost well under a millisecond, stay
/// deterministic by construction, and keep this code free of Embree.
///
/// Not thread-safe for build/refit; query() is const and may run concurrently.
class TriangleBvh {
public:
    /// Builds the tree over `boxes` (one per primitive, indexed by position).
    void build(Span<const Aabb> boxes);
    /// Recomputes node boxes from new primitive boxes, same count and order as in build().
    void refit(Span<const Aabb> boxes);
    /// Appends every primitive whose box overlaps `query` to outHits (in tree order, unsorted).
    void query(const Aabb& query, std::vector<uint32_t>& outHits) const;

    /// Appends every pair (a, b), a < b, of primitives whose boxes overlap, by one descent of the
    /// tree against itself (unsorted). Far cheaper than a query() per primitive: each pair of
    /// overlapping nodes is visited once instead of every primitive walking down from the root.
    /// Stops, returning false, once more than `maxPairs` are appended (what is appended then is
    /// a part of them); true when complete.
    bool overlappingPairs(std::vector<std::array<uint32_t, 2>>& outPairs, std::size_t maxPairs = SIZE_MAX);
    /// The same pairs less those where neither primitive is marked (`marked[i]` != 0, one flag per
    /// primitive): the descent skips node pairs without a marked primitive, so a few marked
    /// primitives cost far less than a query each.
    bool overlappingPairs(Span<const uint8_t> marked, std::vector<std::array<uint32_t, 2>>& outPairs,
                          std::size_t maxPairs = SIZE_MAX);

    uint32_t primitiveCount() const { return static_cast<uint32_t>(mOrder.size()); }

private:
    struct Node {
        Aabb box;
        uint32_t first = 0;  ///< leaf: first index into mOrder; inner: left child (right = left + 1)
        uint32_t count = 0;  ///< leaf: primitives; 0 = inner node
    };
    void buildNode(Span<const Aabb> boxes, const std::vector<Vec3>& centres, uint32_t node, uint32_t begin,
                   uint32_t end);

    std::vector<Node> mNodes;
    std::vector<uint32_t> mOrder;  ///< primitive indices, leaves own contiguous ranges
    std::vector<Aabb> mBoxes;      ///< primitive boxes of the last build/refit
    std::vector<std::array<uint32_t, 2>> mPairStack;  ///< overlappingPairs' node pairs
    std::vector<uint8_t> mNodeMarked;                 ///< overlappingPairs' per node: holds a marked one
    /// The descent of overlappingPairs; `marked` empty = every pair.
    bool descend(Span<const uint8_t> marked, std::vector<std::array<uint32_t, 2>>& outPairs, std::size_t maxPairs);
};

} // namespace cc::collision

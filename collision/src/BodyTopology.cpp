#include "crowdcloth/collision/BodyTopology.h"

#include <algorithm>
#include <string>

namespace cc::collision {
namespace {

uint64_t edgeKey(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

/// For every vertex the lowest index of a vertex at exactly the same position.
std::vector<uint32_t> weldByPosition(Span<const Vec3> positions) {
    std::vector<uint32_t> order(positions.size());
    for (uint32_t v = 0; v < order.size(); ++v) order[v] = v;
    auto before = [&](uint32_t a, uint32_t b) {
        const Vec3 &p = positions[a], &q = positions[b];
        if (p.x() != q.x()) return p.x() < q.x();
        if (p.y() != q.y()) return p.y() < q.y();
        if (p.z() != q.z()) return p.z() < q.z();
        return a < b;
    };
    std::sort(order.begin(), order.end(), before);
    std::vector<uint32_t> welded(positions.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        const bool same = i > 0 && positions[order[i]] == positions[order[i - 1]];
        welded[order[i]] = same ? welded[order[i - 1]] : order[i];
    }
    return welded;
}

} // namespace

Result<std::shared_ptr<const BodyTopology>> BodyTopology::build(Span<const std::array<uint32_t, 3>> triangles,
                                                                Span<const Vec3> weldPositions) {
    if (triangles.empty()) return Status::invalidArgument("BodyCollider: the body has zero triangles");
    if (weldPositions.empty()) return Status::invalidArgument("BodyCollider: the body has zero vertices");
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            if (triangles[t][k] >= weldPositions.size()) {
                return Status::invalidArgument("BodyCollider: triangle " + std::to_string(t) + " corner " +
                                               std::to_string(k) + " indexes vertex " +
                                               std::to_string(triangles[t][k]) + ", out of range (body has " +
                                               std::to_string(weldPositions.size()) + " vertices)");
            }
        }
    }
    for (std::size_t i = 0; i < weldPositions.size(); ++i)
        if (!isFinite(weldPositions[i]))
            return Status::invalidArgument("BodyCollider: body vertex " + std::to_string(i) +
                                           " has a non-finite position");
    auto out = std::make_shared<BodyTopology>();
    BodyTopology& b = *out;
    const uint32_t nv = uint32_t(weldPositions.size()), nt = uint32_t(triangles.size());
    b.vertexCount = nv;
    b.triangles.assign(triangles.begin(), triangles.end());
    const std::vector<uint32_t> weld = weldByPosition(weldPositions);
    b.welded.resize(nt);
    for (uint32_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) b.welded[t][k] = weld[triangles[t][k]];

    b.vertexStart.assign(nv + 1, 0);
    for (const auto& tri : b.welded)
        for (uint32_t v : tri) ++b.vertexStart[v + 1];
    for (uint32_t v = 0; v < nv; ++v) b.vertexStart[v + 1] += b.vertexStart[v];
    b.vertexTriangles.resize(b.vertexStart.back());
    {
        std::vector<uint32_t> fill(b.vertexStart.begin(), b.vertexStart.end() - 1);
        for (uint32_t t = 0; t < nt; ++t)
            for (uint32_t v : b.welded[t]) b.vertexTriangles[fill[v]++] = t;
    }

    std::vector<std::pair<uint64_t, uint32_t>> keyed;
    keyed.reserve(3 * std::size_t(nt));
    for (uint32_t t = 0; t < nt; ++t) {
        const auto& tri = b.welded[t];
        for (uint32_t k = 0; k < 3; ++k) keyed.push_back({edgeKey(tri[k], tri[(k + 1) % 3]), 3 * t + k});
    }
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t i = 0; i < keyed.size(); ++i) {
        if (i == 0 || keyed[i].first != keyed[i - 1].first) b.edgeStart.push_back(uint32_t(i));
        b.edgeSlots.push_back(keyed[i].second);
    }
    b.edgeStart.push_back(uint32_t(keyed.size()));

    std::vector<uint32_t> parent(nv);
    for (uint32_t v = 0; v < nv; ++v) parent[v] = v;
    auto find = [&](uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const auto& tri : b.welded)
        for (int k = 1; k < 3; ++k) {
            const uint32_t a = find(tri[0]), c = find(tri[k]);
            if (a != c) parent[std::max(a, c)] = std::min(a, c);
        }
    std::vector<uint32_t> index(nv, UINT32_MAX);
    b.part.resize(nt);
    for (uint32_t t = 0; t < nt; ++t) {
        const uint32_t root = find(b.welded[t][0]);
        if (index[root] == UINT32_MAX) index[root] = b.partCount++;
        b.part[t] = index[root];
    }
    // Closed: every edge of the part shared by exactly two of its triangles, once each way round.
    b.partClosed.assign(b.partCount, 1);
    for (std::size_t g = 0; g + 1 < b.edgeStart.size(); ++g) {
        const uint32_t first = b.edgeStart[g], count = b.edgeStart[g + 1] - first;
        const uint32_t slotA = b.edgeSlots[first];
        const uint32_t part = b.part[slotA / 3];
        bool twoWays = count == 2;
        if (twoWays) {
            // The edge runs a -> b in one triangle and b -> a in the other (consistent winding).
            const uint32_t slotB = b.edgeSlots[first + 1];
            const auto& ta = b.welded[slotA / 3];
            const auto& tb = b.welded[slotB / 3];
            twoWays = ta[slotA % 3] == tb[(slotB % 3 + 1) % 3] && ta[(slotA % 3 + 1) % 3] == tb[slotB % 3];
        }
        if (!twoWays) b.partClosed[part] = 0;
    }
    return std::shared_ptr<const BodyTopology>(std::move(out));
}

} // namespace cc::collision

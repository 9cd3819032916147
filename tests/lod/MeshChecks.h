#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "crowdcloth/lod/GarmentHierarchy.h"

namespace cc::test {

/// What an intact garment of a given pattern looks like, worked out by hand.
struct GarmentExpectation {
    double area = 0.0;            ///< [m^2] total pattern area
    double boundaryLength = 0.0;  ///< [m] open border (seams and tube wraps are not border)
    int eulerCharacteristic = 1;  ///< V - E + F: a disk 1, an open tube 0
};

/// Checks the active mesh of `h` from its triangle list alone (not the hierarchy's own bookkeeping):
/// every edge has one or two triangles, walked in opposite directions when two; the border is
/// exactly the expected length (so seams and wraps are closed); V - E + F and the total area match;
/// every vertex's triangles form one fan; no active vertex sits at the midpoint of an active edge
/// in world space (a T-junction; the garment must not have moved); neighbours across an edge
/// differ by at most one level. Returns the first failure, or an empty string.
inline std::string checkConforming(const lod::GarmentHierarchy& h, const GarmentExpectation& expect) {
    using Key = std::pair<uint32_t, uint32_t>;
    std::map<Key, std::vector<uint32_t>> directed;  // (from, to) -> triangles
    std::map<Key, std::vector<uint32_t>> undirected;
    std::map<uint32_t, int> vertexTriangles;
    double area = 0.0;
    const std::vector<uint32_t> active = h.activeTriangles();
    for (uint32_t t : active) {
        const auto& tri = h.triangle(t);
        const Vec2 e1 = tri.rest[1] - tri.rest[0], e2 = tri.rest[2] - tri.rest[0];
        const double a = 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
        if (!(a > 0.0)) return "triangle " + std::to_string(t) + " is not counter-clockwise in pattern space";
        area += a;
        for (int k = 0; k < 3; ++k) {
            const uint32_t u = tri.vertices[k], v = tri.vertices[(k + 1) % 3];
            directed[{u, v}].push_back(t);
            undirected[{std::min(u, v), std::max(u, v)}].push_back(t);
            vertexTriangles[u] += 1;
        }
    }
    double border = 0.0;
    std::map<uint32_t, int> vertexEdges, vertexBorderEdges;
    for (const auto& [key, tris] : undirected) {
        vertexEdges[key.first] += 1;
        vertexEdges[key.second] += 1;
        if (tris.size() > 2) return "edge (" + std::to_string(key.first) + ", " + std::to_string(key.second) + ") has " +
                                    std::to_string(tris.size()) + " triangles";
        if (tris.size() == 2) {
            if (directed[key].size() != 1 || directed[{key.second, key.first}].size() != 1) {
                return "edge (" + std::to_string(key.first) + ", " + std::to_string(key.second) +
                       ") is walked the same way by both triangles";
            }
            const int la = int(h.triangle(tris[0]).level), lb = int(h.triangle(tris[1]).level);
            if (std::abs(la - lb) > 1) return "triangles beside edge differ by " + std::to_string(std::abs(la - lb)) + " levels";
        } else {
            const auto& tri = h.triangle(tris[0]);
            int ka = 0, kb = 0;
            for (int k = 0; k < 3; ++k) {
                if (tri.vertices[k] == key.first) ka = k;
                if (tri.vertices[k] == key.second) kb = k;
            }
            border += (tri.rest[ka] - tri.rest[kb]).norm();
            vertexBorderEdges[key.first] += 1;
            vertexBorderEdges[key.second] += 1;
        }
    }
    // One fan per vertex: an inner vertex has as many edges as triangles, a border vertex one more
    // and exactly two border edges.
    for (const auto& [v, nt] : vertexTriangles) {
        const int ne = vertexEdges[v], nb = vertexBorderEdges.count(v) ? vertexBorderEdges[v] : 0;
        if (!((nb == 0 && ne == nt) || (nb == 2 && ne == nt + 1))) {
            return "vertex " + std::to_string(v) + " is not a single fan (" + std::to_string(nt) + " triangles, " +
                   std::to_string(ne) + " edges, " + std::to_string(nb) + " border edges)";
        }
    }
    const long V = long(vertexTriangles.size()), E = long(undirected.size()), F = long(active.size());
    if (V != long(h.activeVertexCount())) return "active vertex count disagrees with the triangles";
    if (V - E + F != expect.eulerCharacteristic) return "Euler characteristic " + std::to_string(V - E + F);
    if (std::abs(area - expect.area) > 1e-12 * expect.area) return "area " + std::to_string(area);
    if (std::abs(border - expect.boundaryLength) > 1e-9 * expect.boundaryLength) {
        return "border length " + std::to_string(border) + " != " + std::to_string(expect.boundaryLength);
    }
    // T-junctions: a 4-8 hanging vertex sits exactly at an edge's world midpoint.
    std::map<std::array<double, 3>, uint32_t> at;
    for (const auto& [v, nt] : vertexTriangles) {
        const Vec3& p = h.position(v);
        at[{p.x(), p.y(), p.z()}] = v;
    }
    for (const auto& [key, tris] : undirected) {
        const Vec3 m = 0.5 * (h.position(key.first) + h.position(key.second));
        auto it = at.find({m.x(), m.y(), m.z()});
        if (it != at.end()) {
            return "vertex " + std::to_string(it->second) + " lies on edge (" + std::to_string(key.first) + ", " +
                   std::to_string(key.second) + ")";
        }
    }
    return {};
}

} // namespace cc::test

// Cloth edges that pass through the body (GarmentInstance::untangleEdges).
//
// The body's contacts hold the cloth's vertices outside it, not its edges: a limb that slips
// between two vertices (a hand through a hem, a thigh through a skirt's stride, an arm pressed
// into a poncho's side) leaves both ends of an edge outside on opposite faces of the limb. Each
// end's push keeps it there and the strain limit pulls the two together through the limb, so the
// edge stays stretched across it for as long as the limb is there. Measured over the humanoid suite
// (tests/engine/HumanoidGarmentTest.cpp), of the edges still over the limit at the end of an
// update, 88-100 % crossed the body in six of seven bad cases (a dress on the running mannequin
// 1,829 of 1,864; RobotExpressive's running skirt 16,352 of 19,689).
//
// Such an edge is moved round the limb: from the middle of its stretch inside the body, rays
// across the edge find the nearest way out, and both ends move that way until the edge clears
// the surface (Baraff, Witkin & Kass 2003 untangle cloth by its intersection's geometry in the
// same spirit; here the body is rigid over the step, so only the cloth moves).
#include "GarmentInstance.h"

#include <algorithm>
#include <cmath>

namespace cc::detail {
namespace {

/// Directions across an edge in which the middle of its crossing looks for the way out.
constexpr int kEscapeRays = 8;

/// Two unit vectors spanning the plane across the unit vector u.
void across(const Vec3& u, Vec3& e1, Vec3& e2) {
    const Vec3 helper = std::abs(u.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    e1 = u.cross(helper).normalized();
    e2 = u.cross(e1);
}

} // namespace

Status GarmentInstance::untangleEdges(const cloth::SubstepSettings& strainSettings,
                                      UpdateScratch& scratch, uint32_t& outMoved) {
    outMoved = 0;
    const cloth::ClothLevel& level = *mAsset->levels[mLevel].cloth;
    const auto& vertexOfNode = level.vertexOfNode();
    const auto& edges = level.limitedEdges();
    // 1. The stretched edges, traced both ways: an edge whose ends are outside and whose ray from
    //    either end enters the body before reaching the other end crosses the body. Open parts
    //    count (RayParts::All): an edge through a plate or an uncapped tube is held on both sides
    //    by contacts of opposite normals, and the limit and the pushes undo each other (the poncho
    //    on RobotExpressive walking, 39 of whose 63 parts are open: 89 -> 26 updates over the
    //    limit of 90).
    scratch.stretchedEdges.clear();
    scratch.origins.clear();
    scratch.directions.clear();
    const double over = 1.0 + strainSettings.strainLimit + kStrainSlack;
    for (uint32_t k = 0; k < uint32_t(edges.size()); ++k) {
        const Vec3& a = mPositions[vertexOfNode[edges[k].a]];
        const Vec3& b = mPositions[vertexOfNode[edges[k].b]];
        const double length = (b - a).norm();
        if (!(length > over * edges[k].restLength)) continue;
        const Vec3 u = (b - a) / length;
        scratch.stretchedEdges.push_back(k);
        scratch.origins.push_back(a);
        scratch.directions.push_back(u);
        scratch.origins.push_back(b);
        scratch.directions.push_back(-u);
    }
    if (scratch.stretchedEdges.empty()) return Status::ok();
    scratch.traces.resize(scratch.origins.size());
    if (Status s = context.collider->traceRays(scratch.origins, scratch.directions,
                                               collision::RayParts::All, scratch.traces);
        !s)
        return s;

    // 2. From the middle of each crossing's stretch inside the body, rays across the edge.
    std::size_t crossing = 0;
    scratch.escapeOrigins.clear();
    scratch.escapeDirections.clear();
    for (std::size_t i = 0; i < scratch.stretchedEdges.size(); ++i) {
        const collision::RayTrace& fromA = scratch.traces[2 * i];
        const collision::RayTrace& fromB = scratch.traces[2 * i + 1];
        const Vec3& a = scratch.origins[2 * i];
        const double length = (scratch.origins[2 * i + 1] - a).norm();
        if (fromA.partsInside != 0 || fromB.partsInside != 0)
            continue; // an end inside: the pushes' work
        if (!(fromA.firstEntry >= 0.0 && fromA.firstEntry < length && fromB.firstEntry >= 0.0))
            continue;
        const double enter = fromA.firstEntry, leave = std::max(enter, length - fromB.firstEntry);
        const Vec3& u = scratch.directions[2 * i];
        const Vec3 middle = a + 0.5 * (enter + leave) * u;
        Vec3 e1, e2;
        across(u, e1, e2);
        scratch.stretchedEdges[crossing++] = scratch.stretchedEdges[i]; // crossing <= i
        for (int r = 0; r < kEscapeRays; ++r) {
            const double angle = 2.0 * kPi * r / kEscapeRays;
            scratch.escapeOrigins.push_back(middle);
            scratch.escapeDirections.push_back(std::cos(angle) * e1 + std::sin(angle) * e2);
        }
    }
    if (crossing == 0) return Status::ok();
    scratch.stretchedEdges.resize(crossing);
    scratch.traces.resize(scratch.escapeOrigins.size());
    if (Status s = context.collider->traceRays(scratch.escapeOrigins, scratch.escapeDirections,
                                               collision::RayParts::All, scratch.traces);
        !s)
        return s;

    // 3. Each crossing edge's free ends move along its nearest way out, past the surface by the
    //    thickness (twice as far for one end when the other is held by its attachment: the edge
    //    turns about it); a node that several edges move goes by their mean.
    const uint32_t free = level.freeNodeCount();
    scratch.nodeMoves.assign(level.nodeCount(), Vec3::Zero());
    scratch.nodeMoveCounts.assign(level.nodeCount(), 0.0);
    for (std::size_t i = 0; i < crossing; ++i) {
        double nearest = -1.0;
        Vec3 way = Vec3::Zero();
        for (int r = 0; r < kEscapeRays; ++r) {
            const collision::RayTrace& t = scratch.traces[kEscapeRays * i + std::size_t(r)];
            if (t.partsInside <= 0 || t.firstExit < 0.0) continue;
            if (nearest < 0.0 || t.firstExit < nearest) {
                nearest = t.firstExit;
                way = scratch.escapeDirections[kEscapeRays * i + std::size_t(r)];
            }
        }
        if (nearest < 0.0) continue;
        const cloth::LimitedEdge& e = edges[scratch.stretchedEdges[i]];
        const bool aFree = e.a < free, bFree = e.b < free;
        const Vec3 move = (nearest + mAsset->desc.thickness) * way;
        if (aFree) {
            scratch.nodeMoves[e.a] += bFree ? move : 2.0 * move;
            scratch.nodeMoveCounts[e.a] += 1.0;
        }
        if (bFree) {
            scratch.nodeMoves[e.b] += aFree ? move : 2.0 * move;
            scratch.nodeMoveCounts[e.b] += 1.0;
        }
    }
    const auto& nodeOfVertex = level.nodeOfVertex();
    for (std::size_t v = 0; v < mPositions.size() && v < nodeOfVertex.size(); ++v) {
        const uint32_t n = nodeOfVertex[v];
        if (scratch.nodeMoveCounts[n] == 0.0) continue;
        mPositions[v] += scratch.nodeMoves[n] / scratch.nodeMoveCounts[n];
        mMoved[v] = 1;
        ++outMoved;
    }
    return Status::ok();
}

} // namespace cc::detail

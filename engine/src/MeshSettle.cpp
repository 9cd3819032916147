// A garment's first update against the body mesh after the capsules, sleep or a coarser level:
// its state is moved out of the mesh before the solve sees it (GarmentInstance::settleOntoMesh).
//
// Far away a garment runs at a coarse level against capsule proxies. The capsules are not the
// mesh, and a coarse level's chords cut through the body's curves: a cape far away, then close
// up after a camera cut, refined at once from level 0 to the finest, lay up to a tenth of a metre
// inside the torso. The update's contacts reach only as far as the cloth moves, and pushed to its
// nearest surface a vertex that deep may come out on the far side of a limb or the torso from its
// neighbours: the cloth wraps through the body (measured on the walking mannequin: 160-500 %
// strain for seconds after a cut; tests/engine/CameraCutTest.cpp).
#include "GarmentInstance.h"

#include <algorithm>

#include "crowdcloth/cloth/ContactResponse.h"

namespace cc::detail {
namespace {

constexpr int kSettleRounds = 4;                 ///< pushes out of the mesh, each followed by the strain limit
constexpr int kSideSweeps = 16;                  ///< neighbour-to-neighbour steps a side travels into the body
constexpr double kSideReach = 0.05;              ///< [m] how far an outside vertex looks for the surface it is on
constexpr double kTangledShare = 0.04;           ///< of the vertices: more left inside after a settle is a tangle
constexpr double kEntangledStrainFactor = 3.0;   ///< of the strain limit: more left after a settle is a tangle
constexpr double kEntangledStrainFloor = 0.1;    ///< the strain limit assumed when there is none
/// After the solve that follows a settle: a garment's own motion close up stretches some edges
/// 45-58 % (a dress's sides on the walk); one tangled with the body, 165-500 %.
constexpr double kSolvedTangleStrain = 1.0;
const Vec3 kProbe = Vec3(0.27, 0.80, 0.53).normalized();  ///< a ray for inside tests: no mesh is aligned with it

} // namespace

double GarmentInstance::tangledStrain() const {
    return kEntangledStrainFactor * std::max(context.strainLimit, kEntangledStrainFloor);
}

Status GarmentInstance::settleOntoMesh(CharacterInstance& character, UpdateScratch& scratch,
                                       GarmentUpdateReport& outReport) {
    // The state goes back to the level it was stepped at (exactly: it was refined from there) and
    // is settled out of the mesh (near the skin: its vertices were kept outside the capsules), then
    // refined and settled again: a refined vertex lies at most a chord's sag inside. Coarsened from
    // a level stepped against the mesh, a state is already outside it (a coarse level's vertices
    // are some of the fine level's).
    const int target = mLevel;
    while (mLevel > std::min(target, mSteppedLevel)) transferOneLevel(-1);
    uint32_t inside = 0;
    if (!mSteppedOnMesh) {
        if (Status s = settleLevel(scratch, inside); !s) return s;
    }
    if (mLevel < target) {
        while (mLevel < target) transferOneLevel(1);
        if (Status s = settleLevel(scratch, inside); !s) return s;
    }
    // A coarse state can be tangled with the body beyond what a settle undoes (a coarse cape's hem
    // between the legs, a chord across a limb): what the pushes take out, the strain limit pulls
    // back in, or the cloth stays stretched round the limb. It starts again from its fitted
    // placement, carried by the torso to this pose, and falls from there. A few vertices held
    // inside are a garment's ordinary state where limbs overlap the torso (a dress hung under the
    // arms: 2 % of its vertices); a tangle left 7-16 % inside, or the cloth stretched far past
    // its limit (tests/engine/CameraCutTest.cpp). A state stepped against the mesh and only
    // refined was outside the body at its coarser level: the strain its settle leaves is mostly
    // the pushes' (capes 31-58 %), which the next solve's limit takes back, so it counts as a
    // tangle only past what a tangle after a solve reads (restartIfTangled). Judged at three
    // times the limit here, capes refined as the crowd's camera came near went back to their
    // flat placements, a board on screen for a few frames.
    const double tangled =
        mSteppedOnMesh ? std::max(kSolvedTangleStrain, tangledStrain()) : tangledStrain();
    const bool stretched = maxEdgeStrain() > tangled;
    if (double(inside) > kTangledShare * double(mPositions.size()) || stretched) {
        if (Status s = placeAtRest(character); !s) return s;
        if (Status s = settleLevel(scratch, inside); !s) return s;
        outReport.restarted = true;
    }
    mSettled = !outReport.restarted;
    mContacts.clear();
    return Status::ok();
}

Status GarmentInstance::restartIfTangled(CharacterInstance& character, UpdateScratch& scratch,
                                         GarmentUpdateReport& inOutReport) {
    mSettled = false;
    if (maxEdgeStrain() <= std::max(kSolvedTangleStrain, tangledStrain())) return Status::ok();
    if (Status s = placeAtRest(character); !s) return s;
    uint32_t inside = 0;
    if (Status s = settleLevel(scratch, inside); !s) return s;
    inOutReport.restarted = true;
    return Status::ok();
}

Status GarmentInstance::sideNormals(UpdateScratch& scratch) {
    // An outside vertex near the body knows its side: the outward normal of the part it is nearest
    // to. One inside does not (its nearest surface may be a limb's far side), so it takes its
    // neighbours' side, passed from vertex to vertex along the cloth's edges into the body.
    collision::BodyContactSettings settings = contactSettings();
    settings.continuous = false;
    settings.query.margin = kSideReach;
    const collision::Collider* colliders[1] = {context.collider};
    if (Status s = scratch.contacts.gather(colliders, mPositions, mPositions, settings, mContacts); !s) return s;
    const std::size_t n = mPositions.size();
    scratch.sides.assign(n, Vec3::Zero());
    scratch.sideDepths.assign(n, -1e30);
    for (const Contact& c : mContacts) {
        if (scratch.traces[c.vertex].partsInside > 0 || c.depth <= scratch.sideDepths[c.vertex]) continue;
        scratch.sideDepths[c.vertex] = c.depth, scratch.sides[c.vertex] = c.normal;
    }
    const auto& triangles = mAsset->levels[mLevel].active.mesh.triangles;
    for (int sweep = 0; sweep < kSideSweeps; ++sweep) {
        scratch.sideSums.assign(n, Vec3::Zero());  // this sweep's sums of the neighbours' sides
        bool open = false;
        for (const auto& t : triangles)
            for (int k = 0; k < 3; ++k) {
                scratch.sideSums[t[k]] += scratch.sides[t[(k + 1) % 3]] + scratch.sides[t[(k + 2) % 3]];
            }
        for (std::size_t v = 0; v < n; ++v) {
            if (scratch.traces[v].partsInside <= 0 || scratch.sides[v] != Vec3::Zero()) continue;
            const double length = scratch.sideSums[v].norm();
            if (length > 0.0) scratch.sides[v] = scratch.sideSums[v] / length;
            else open = true;
        }
        if (!open) break;
    }
    return Status::ok();
}

Status GarmentInstance::settleLevel(UpdateScratch& scratch, uint32_t& outStillInside) {
    // Rays tell what is inside the body however deep (a closed part's inside is exact). A vertex
    // inside leaves along its side, where that ray leaves the body; one with no side (or no exit)
    // goes to its nearest surface (a proximity query of just those, as far as they may be deep).
    // The strain limit brings the neighbours along. It moves the state, not its motion: velocities
    // are kept.
    const cloth::ClothLevel& cloth = *mAsset->levels[mLevel].cloth;
    const std::size_t n = mPositions.size();
    collision::BodyContactSettings settings = contactSettings();
    settings.continuous = false;
    settings.query.margin = kMaxContactReach;
    const collision::Collider* colliders[1] = {context.collider};
    cloth::ContactResponse response;
    response.thickness = mAsset->desc.thickness;
    const cloth::SubstepSettings limit = solverSettings(1, 1, context.strainLimit);
    scratch.velocities.assign(mVelocities.begin(), mVelocities.end());
    for (int round = 0;; ++round) {
        scratch.directions.assign(n, kProbe);
        scratch.traces.resize(n);
        if (Status s = context.collider->traceRays(mPositions, scratch.directions,
                                                   collision::RayParts::Closed, scratch.traces);
            !s)
            return s;
        outStillInside = 0;
        for (std::size_t v = 0; v < n; ++v) {
            if (cloth.nodeOfVertex()[v] >= cloth.freeNodeCount()) scratch.traces[v].partsInside = 0;  // driven
            outStillInside += scratch.traces[v].partsInside > 0;
        }
        if (outStillInside == 0 || round == kSettleRounds) break;
        if (Status s = sideNormals(scratch); !s) return s;
        // Out along each side: the rays of the vertices inside, in place of the probes.
        scratch.vertices.clear();
        scratch.origins.clear();
        for (std::size_t v = 0; v < n; ++v) {
            if (scratch.traces[v].partsInside <= 0 || scratch.sides[v] == Vec3::Zero()) continue;
            scratch.vertices.push_back(uint32_t(v));
            scratch.origins.push_back(mPositions[v]);
        }
        scratch.directions.clear();
        for (uint32_t v : scratch.vertices) scratch.directions.push_back(scratch.sides[v]);
        scratch.sideTraces.resize(scratch.vertices.size());
        if (Status s = context.collider->traceRays(scratch.origins, scratch.directions,
                                                   collision::RayParts::Closed, scratch.sideTraces);
            !s)
            return s;
        mMoved.assign(n, 0);
        uint32_t moved = 0;
        for (std::size_t k = 0; k < scratch.vertices.size(); ++k) {
            if (scratch.sideTraces[k].firstExit < 0.0) continue;
            mPositions[scratch.vertices[k]] +=
                (scratch.sideTraces[k].firstExit + response.thickness) * scratch.directions[k];
            mMoved[scratch.vertices[k]] = 1, ++moved;
        }
        // The rest to their nearest surface.
        scratch.vertices.clear();
        scratch.origins.clear();
        for (std::size_t v = 0; v < n; ++v) {
            if (scratch.traces[v].partsInside <= 0 || mMoved[v]) continue;
            scratch.vertices.push_back(uint32_t(v));
            scratch.origins.push_back(mPositions[v]);
        }
        if (!scratch.vertices.empty()) {
            if (Status s = scratch.contacts.gather(colliders, scratch.origins, scratch.origins,
                                                   settings, mContacts);
                !s)
                return s;
            for (Contact& c : mContacts) c.vertex = scratch.vertices[c.vertex];  // still sorted by vertex
            uint32_t pushed = 0;
            if (Status s = cloth::resolveContacts(mContacts, response, cloth, mPositions,
                                                  mVelocities, &pushed, mMoved);
                !s)
                return s;
            moved += pushed;
        }
        if (moved == 0) break;  // deeper than any query reaches
        if (limit.strainLimit > 0.0) {
            if (Status s = limitAroundMoved(limit); !s) return s;
        }
    }
    mVelocities.assign(scratch.velocities.begin(), scratch.velocities.end());
    return Status::ok();
}

} // namespace cc::detail

#include "crowdcloth/cloth/SubstepSimulation.h"

#include <cmath>
#include <string>

#include "crowdcloth/core/Hash.h"

namespace cc::cloth {

Result<std::unique_ptr<SubstepSimulation>> SubstepSimulation::create(const ClothMesh& mesh, const ClothMaterial& material,
                                                                     Span<const uint32_t> attached,
                                                                     Span<const std::array<uint32_t, 2>> welds) {
    auto level = ClothLevel::cookMesh(mesh, material, attached, welds);
    if (!level.isOk()) return level.status();
    return fromLevel(std::move(level).value(), mesh.positions);
}

Result<std::unique_ptr<SubstepSimulation>> SubstepSimulation::create(const ClothLevelDesc& desc,
                                                                     std::vector<Vec3> positions) {
    auto level = ClothLevel::cook(desc);
    if (!level.isOk()) return level.status();
    return fromLevel(std::move(level).value(), std::move(positions));
}

Result<std::unique_ptr<SubstepSimulation>> SubstepSimulation::fromLevel(std::shared_ptr<const ClothLevel> level,
                                                                        std::vector<Vec3> positions) {
    if (positions.size() != level->vertexCount())
        return Status::invalidArgument("SubstepSimulation: " + std::to_string(positions.size()) + " positions for " +
                                       std::to_string(level->vertexCount()) + " vertices");
    for (std::size_t v = 0; v < positions.size(); ++v)
        if (!isFinite(positions[v]))
            return Status::invalidArgument("SubstepSimulation: vertex " + std::to_string(v) + " has a non-finite position");
    std::unique_ptr<SubstepSimulation> sim(new SubstepSimulation());
    sim->mTargets.resize(level->attachedNodeCount());
    for (uint32_t k = 0; k < level->attachedNodeCount(); ++k)
        sim->mTargets[k] = positions[level->vertexOfNode()[level->freeNodeCount() + k]];
    sim->mVelocities.assign(positions.size(), Vec3::Zero());
    sim->mPositions = std::move(positions);
    sim->mLevel = std::move(level);
    return sim;
}

Status SubstepSimulation::step(double dt, const SubstepSettings& settings) {
    if (Status s = settings.validate(); !s) return s;
    if (!(dt > 0.0 && dt <= 1.0)) return Status::invalidArgument("SubstepSimulation::step: dt = " + std::to_string(dt) + " s is outside (0, 1]");
    const double h = dt / settings.substeps;
    auto& factor = mFactors[h];
    if (!factor) {
        auto built = mLevel->buildFactor(h);
        if (!built.isOk()) {
            mFactors.erase(h);
            return built.status();
        }
        factor = std::move(built).value();
    }
    SubstepLane lane;
    lane.positions = mPositions;
    lane.velocities = mVelocities;
    lane.targets = mTargets;
    lane.contacts = mContacts;
    lane.acceleration = mAcceleration;
    lane.frameAngularVelocity = mAngularVelocity;
    lane.frameAngularAcceleration = mAngularAcceleration;
    lane.fictitiousScale = mFictitiousScale;
    lane.velocityDamping = mVelocityDamping;
    if (Status s = stepSubsteps(*mLevel, *factor, dt, settings, Span<const SubstepLane>(&lane, 1), mWorkspace,
                                Span<SubstepLaneReport>(&mReport, 1));
        !s)
        return s;
    return mReport.status;
}

double SubstepSimulation::maxEdgeStrain() const {
    std::vector<Vec3> node(mLevel->nodeCount());
    for (uint32_t k = 0; k < mLevel->nodeCount(); ++k) node[k] = mPositions[mLevel->vertexOfNode()[k]];
    double worst = 0.0;
    for (const LimitedEdge& e : mLevel->limitedEdges())
        worst = std::max(worst, (node[e.b] - node[e.a]).norm() / e.restLength - 1.0);
    return worst;
}

double SubstepSimulation::kineticEnergy() const {
    double e = 0.0;
    for (uint32_t k = 0; k < mLevel->freeNodeCount(); ++k)
        e += 0.5 * mLevel->nodeMasses()[k] * mVelocities[mLevel->vertexOfNode()[k]].squaredNorm();
    return e;
}

uint64_t SubstepSimulation::stateHash() const {
    const uint64_t h = hashBytes(mPositions.data(), mPositions.size() * sizeof(Vec3));
    return hashBytes(mVelocities.data(), mVelocities.size() * sizeof(Vec3), h);
}

} // namespace cc::cloth

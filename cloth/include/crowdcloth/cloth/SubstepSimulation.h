#pragma once

#include <map>
#include <memory>
#include <vector>

#include "crowdcloth/cloth/ClothLevel.h"
#include "crowdcloth/cloth/SubstepSolver.h"

namespace cc::cloth {

/// One garment on the substepped local/global solver, on its own: a cooked level, the factors it
/// has needed (one per substep size), its state, its targets and contacts. The World steps many
/// instances together through stepSubsteps() instead; this is the one-instance form for tests,
/// benchmarks and hosts with a single cloth.
///
///   auto mesh = RectanglePanel{1.0, 1.0, 32, 32}.build().value();
///   const uint32_t top[] = {1056, 1088};
///   auto sim = SubstepSimulation::create(mesh, ClothMaterial{}, top).value();
///   SubstepSettings settings;  // 10 substeps
///   for (int i = 0; i < 60; ++i) if (!sim->step(1.0 / 60, settings)) break;
class SubstepSimulation {
public:
    /// Provot springs over `mesh`; `attached` vertices hold their initial positions until moved.
    static Result<std::unique_ptr<SubstepSimulation>> create(const ClothMesh& mesh, const ClothMaterial& material,
                                                             Span<const uint32_t> attached,
                                                             Span<const std::array<uint32_t, 2>> welds = {});
    /// Any spring network (desc), starting at `positions` [m].
    static Result<std::unique_ptr<SubstepSimulation>> create(const ClothLevelDesc& desc, std::vector<Vec3> positions);

    /// Advances by dt [s], (0, 1]; builds the factor for dt / settings.substeps on first need.
    Status step(double dt, const SubstepSettings& settings);

    /// Where attached node `index` (ClothLevel order) must be at the end of the next steps [m].
    void setTarget(uint32_t index, const Vec3& position) { mTargets[index] = position; }
    /// Contacts for the next steps (until replaced); vertex indices of the level.
    void setContacts(std::vector<Contact> contacts) { mContacts = std::move(contacts); }
    void setAcceleration(const Vec3& a) { mAcceleration = a; }
    /// The simulation's frame turns at `angularVelocity` [rad/s] about its origin (see SubstepLane).
    void setFrameRotation(const Vec3& angularVelocity, const Vec3& angularAcceleration = Vec3::Zero(),
                          double scale = 1.0) {
        mAngularVelocity = angularVelocity;
        mAngularAcceleration = angularAcceleration;
        mFictitiousScale = scale;
    }
    void setVelocityDamping(double rate) { mVelocityDamping = rate; }  ///< [1/s]

    const ClothLevel& level() const { return *mLevel; }
    std::vector<Vec3>& positions() { return mPositions; }
    std::vector<Vec3>& velocities() { return mVelocities; }
    const std::vector<Vec3>& positions() const { return mPositions; }
    const std::vector<Vec3>& velocities() const { return mVelocities; }
    const SubstepLaneReport& lastReport() const { return mReport; }
    /// Largest (length / rest length - 1) over the level's limited edges.
    double maxEdgeStrain() const;
    /// [J] kinetic energy of the nodes.
    double kineticEnergy() const;
    uint64_t stateHash() const;

private:
    SubstepSimulation() = default;
    static Result<std::unique_ptr<SubstepSimulation>> fromLevel(std::shared_ptr<const ClothLevel> level,
                                                                std::vector<Vec3> positions);

    std::shared_ptr<const ClothLevel> mLevel;
    std::map<double, std::shared_ptr<const SubstepFactor>> mFactors;
    std::vector<Vec3> mPositions, mVelocities, mTargets;
    std::vector<Contact> mContacts;
    Vec3 mAcceleration{0.0, -9.81, 0.0};
    Vec3 mAngularVelocity = Vec3::Zero(), mAngularAcceleration = Vec3::Zero();
    double mFictitiousScale = 1.0;
    double mVelocityDamping = 0.0;
    SubstepWorkspace mWorkspace;
    SubstepLaneReport mReport;
};

} // namespace cc::cloth

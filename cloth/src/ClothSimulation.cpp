#include "crowdcloth/cloth/ClothSimulation.h"

#include <cmath>
#include <string>

#include "crowdcloth/cloth/ContinuumModel.h"
#include "crowdcloth/cloth/MassSpringModel.h"

namespace cc::cloth {

const char* integratorKindName(IntegratorKind kind) {
    switch (kind) {
    case IntegratorKind::SymplecticEuler: return "symplectic-euler";
    case IntegratorKind::ImplicitPcg: return "implicit-pcg";
    case IntegratorKind::ImplicitCholmod: return "implicit-cholmod";
    case IntegratorKind::ImplicitMultigrid: return "implicit-multigrid";
    }
    return "unknown";
}

Status SimulationSettings::validate() const {
    if (!isFinite(gravity)) return Status::invalidArgument("SimulationSettings.gravity is not finite");
    if (int(integrator) < 0 || int(integrator) > int(IntegratorKind::ImplicitMultigrid)) {
        return Status::invalidArgument(
            "SimulationSettings.integrator = " + std::to_string(int(integrator)) +
            " is not an IntegratorKind");
    }
    if (implicit.newtonIterations < 1 || implicit.newtonIterations > 1000) {
        return Status::invalidArgument("SimulationSettings.implicit.newtonIterations = " +
                                       std::to_string(implicit.newtonIterations) +
                                       " is outside [1, 1000]");
    }
    if (!(implicit.newtonTolerance >= 0.0 && implicit.newtonTolerance < 1.0)) {
        return Status::invalidArgument("SimulationSettings.implicit.newtonTolerance = " +
                                       std::to_string(implicit.newtonTolerance) +
                                       " is outside [0, 1)");
    }
    if (Status s = implicit.multigrid.validate(); !s) {
        return Status::invalidArgument("SimulationSettings.implicit.multigrid: " + s.message());
    }
    const auto& pcg = implicit.pcg;
    if (!(pcg.relativeTolerance > 0.0 && pcg.relativeTolerance < 1.0)) {
        return Status::invalidArgument("SimulationSettings.implicit.pcg.relativeTolerance = " +
                                       std::to_string(pcg.relativeTolerance) + " is outside (0, 1)");
    }
    if (pcg.maxIterations < 1) return Status::invalidArgument("SimulationSettings.implicit.pcg.maxIterations must be >= 1");
    if (explicitEuler.maxSubsteps < 1) return Status::invalidArgument("SimulationSettings.explicitEuler.maxSubsteps must be >= 1");
    if (explicitEuler.fixedSubsteps < 0) return Status::invalidArgument("SimulationSettings.explicitEuler.fixedSubsteps must be >= 0");
    if (!(explicitEuler.stabilitySafety > 0.0 && explicitEuler.stabilitySafety <= 1.0)) {
        return Status::invalidArgument("SimulationSettings.explicitEuler.stabilitySafety must be in (0, 1]");
    }
    if (!(strainLimit >= 0.0 && strainLimit <= 10.0)) {
        return Status::invalidArgument("SimulationSettings.strainLimit = " + std::to_string(strainLimit) +
                                       " is outside [0, 10]");
    }
    if (strainLimitPasses < 1) return Status::invalidArgument("SimulationSettings.strainLimitPasses must be >= 1");
    return Status::ok();
}

Result<std::unique_ptr<ClothSimulation>> ClothSimulation::create(const ClothMesh& mesh, const ClothMaterial& material,
                                                                 const SimulationSettings& settings) {
    if (Status s = mesh.validate(); !s) return s;
    if (Status s = material.validate(); !s) return s;
    if (Status s = settings.validate(); !s) return s;
    auto topology = ClothTopology::build(mesh);
    if (!topology.isOk()) return topology.status();

    std::unique_ptr<ForceModel> model;
    if (settings.forceModel == ForceModelKind::MassSpring) {
        auto m = MassSpringModel::fromMesh(mesh, topology.value(), material);
        if (!m.isOk()) return m.status();
        model = std::move(m.value());
    } else {
        auto m = ContinuumModel::fromMesh(mesh, topology.value(), material);
        if (!m.isOk()) return m.status();
        model = std::move(m.value());
    }
    auto sim = create(std::move(model), mesh.positions, lumpedMasses(mesh, material.arealDensity), material.damping,
                      settings);
    if (!sim.isOk()) return sim;
    std::vector<LimitedEdge> edges;
    for (const auto& [a, b] : topology.value().edges) {
        edges.push_back({a, b, (mesh.restPositions[b] - mesh.restPositions[a]).norm()});
    }
    sim.value()->mEdges = StrainLimiter(static_cast<uint32_t>(mesh.vertexCount()), edges, mesh.restPositions);
    return sim;
}

Result<std::unique_ptr<ClothSimulation>> ClothSimulation::create(std::unique_ptr<ForceModel> model,
                                                                 std::vector<Vec3> positions, std::vector<double> masses,
                                                                 double damping, const SimulationSettings& settings) {
    if (Status s = settings.validate(); !s) return s;
    if (!model || model->vertexCount() != positions.size() || masses.size() != positions.size()) {
        return Status::invalidArgument("ClothSimulation: force model, positions and masses must cover the same vertices");
    }
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (!isFinite(positions[i])) {
            return Status::invalidArgument("ClothSimulation: vertex " + std::to_string(i) + " has a non-finite position");
        }
        if (!(masses[i] > 0.0) || !std::isfinite(masses[i])) {
            return Status::invalidArgument("ClothSimulation: vertex " + std::to_string(i) + " has mass " +
                                           std::to_string(masses[i]) + "; need finite > 0");
        }
    }
    if (!(damping >= 0.0) || !std::isfinite(damping)) return Status::invalidArgument("ClothSimulation: damping must be >= 0");

    std::unique_ptr<ClothSimulation> sim(new ClothSimulation());
    sim->mSettings = settings;
    sim->mState.velocities.assign(positions.size(), Vec3::Zero());
    sim->mState.positions = std::move(positions);
    sim->mState.masses = std::move(masses);
    sim->mConstraints = ConstraintSet(sim->mState.vertexCount());
    if (Status s = sim->init(std::move(model), damping); !s) return s;
    return sim;
}

Status ClothSimulation::init(std::unique_ptr<ForceModel> model, double damping) {
    mModel = std::move(model);
    IntegratorSettings common;
    common.gravity = mSettings.gravity;
    common.damping = damping;
    common.parallel = mSettings.parallel;
    if (mSettings.integrator == IntegratorKind::SymplecticEuler) {
        mIntegrator = std::make_unique<SymplecticEulerIntegrator>(*mModel, common, mSettings.explicitEuler);
    } else {
        ImplicitEulerIntegrator::Settings implicit = mSettings.implicit;
        implicit.solver =
            mSettings.integrator == IntegratorKind::ImplicitPcg       ? LinearSolverKind::Pcg
            : mSettings.integrator == IntegratorKind::ImplicitCholmod ? LinearSolverKind::Cholmod
                                                                      : LinearSolverKind::Multigrid;
        if (implicit.solver == LinearSolverKind::Multigrid) {
            // Checked here so that a bad hierarchy fails create(), not the first step.
            const Status s = MultigridHierarchy::checkProlongations(
                mModel->vertexCount(), implicit.multigrid.prolongations);
            if (!s) {
                return Status::invalidArgument("SimulationSettings.implicit.multigrid: " +
                                               s.message());
            }
        }
        mIntegrator = std::make_unique<ImplicitEulerIntegrator>(*mModel, common, implicit);
    }
    return Status::ok();
}

Status ClothSimulation::step(double dt) {
    if (!(dt > 0.0 && dt <= 1.0)) {
        return Status::invalidArgument("ClothSimulation::step: dt = " + std::to_string(dt) + " s is outside (0, 1]");
    }
    // The host may write positions and velocities between steps: refuse to start from garbage.
    if (const uint32_t bad = mState.firstNonFinite(); bad < mState.vertexCount()) {
        return Status::invalidArgument("ClothSimulation::step: vertex " + std::to_string(bad) +
                                       " has a non-finite position or velocity before the step");
    }
    mBackup.positions = mState.positions;
    mBackup.velocities = mState.velocities;
    Status status = mIntegrator->step(dt, mConstraints, mState, mStats);
    if (status && mSettings.strainLimit > 0.0) {
        mStats.strainLimitPasses =
            mEdges.apply(mSettings.strainLimit, mSettings.strainLimitPasses, dt, mConstraints, mState, mSettings.parallel);
    }
    if (status) {
        const uint32_t bad = mState.firstNonFinite();
        if (bad < mState.vertexCount()) {
            status = Status::error(StatusCode::NumericalFailure,
                                   std::string(mIntegrator->name()) + " produced a non-finite state at vertex " +
                                       std::to_string(bad) + "; the step was undone");
        }
    }
    if (!status) {
        mState.positions.swap(mBackup.positions);
        mState.velocities.swap(mBackup.velocities);
    }
    return status;
}

double ClothSimulation::totalEnergy() const {
    return mModel->energy(mState.positions) + mState.kineticEnergy() + mState.gravityEnergy(mSettings.gravity);
}

} // namespace cc::cloth

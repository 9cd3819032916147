#pragma once

#include <memory>
#include <vector>

#include "crowdcloth/cloth/ClothMaterial.h"
#include "crowdcloth/cloth/ClothState.h"
#include "crowdcloth/cloth/ConstraintSet.h"
#include "crowdcloth/cloth/ImplicitEulerIntegrator.h"
#include "crowdcloth/cloth/StrainLimiter.h"
#include "crowdcloth/cloth/SymplecticEulerIntegrator.h"
#include "crowdcloth/core/ClothMesh.h"

namespace cc::cloth {

enum class ForceModelKind { MassSpring, Continuum };
enum class IntegratorKind {
    SymplecticEuler,    ///< explicit, stability-bounded substeps (SymplecticEulerIntegrator)
    ImplicitPcg,        ///< implicit Euler, block-Jacobi filtered PCG
    ImplicitCholmod,    ///< implicit Euler, CHOLMOD
    ImplicitMultigrid,  ///< implicit Euler, multigrid-preconditioned filtered PCG (MultigridPcg)
};

/// "symplectic-euler", "implicit-pcg", "implicit-cholmod", "implicit-multigrid"; "unknown" for a
/// value outside the enum.
const char* integratorKindName(IntegratorKind kind);

/// Everything that chooses how one garment is simulated. Defaults are the accurate implicit setup.
struct SimulationSettings {
    ForceModelKind forceModel = ForceModelKind::Continuum;
    IntegratorKind integrator = IntegratorKind::ImplicitPcg;
    Vec3 gravity{0.0, -9.81, 0.0};          ///< [m/s^2] finite
    ImplicitEulerIntegrator::Settings implicit;
    SymplecticEulerIntegrator::Settings explicitEuler;
    double strainLimit = 0.0;               ///< [-] Provot limit on edge strain, e.g. 0.1; 0 = off; [0, 10]
    int strainLimitPasses = 8;              ///< [-] maximum sweeps per step; >= 1. Gauss-Seidel converges
                                            ///< slowly near pins: on a 10 x 10 sheet hung by two
                                            ///< corners, 8 sweeps hold 20%, 50 hold 11%, 200 hold 10%
    ParallelSettings parallel;

    /// Names the first invalid field.
    Status validate() const;
};

/// One garment: a mesh, a material, a force model and an integrator, with its state and
/// constraints. Not thread-safe; distinct simulations may step concurrently.
///
///   auto mesh = RectanglePanel{1.0, 1.0, 32, 32}.build().value();
///   auto sim = ClothSimulation::create(mesh, ClothMaterial{}, SimulationSettings{}).value();
///   sim->constraints().pin(mesh.vertexCount() - 1, mesh.positions.back());
///   for (int i = 0; i < 60; ++i) if (!sim->step(1.0 / 60)) break;
///
/// A step that produces a non-finite value is undone: the state returns to where it was before
/// the step and the Status says which vertex failed (NumericalFailure).
class ClothSimulation {
public:
    static Result<std::unique_ptr<ClothSimulation>> create(const ClothMesh& mesh, const ClothMaterial& material,
                                                           const SimulationSettings& settings);
    /// A simulation over any force model (e.g. a spring network that is not a surface), with
    /// explicit masses [kg]; damping [s] as in ClothMaterial. No strain limiting.
    static Result<std::unique_ptr<ClothSimulation>> create(std::unique_ptr<ForceModel> model, std::vector<Vec3> positions,
                                                           std::vector<double> masses, double damping,
                                                           const SimulationSettings& settings);

    /// Advances by dt [s], (0, 1].
    Status step(double dt);

    ClothState& state() { return mState; }
    const ClothState& state() const { return mState; }
    ConstraintSet& constraints() { return mConstraints; }
    const ForceModel& forceModel() const { return *mModel; }
    const Integrator& integrator() const { return *mIntegrator; }
    const StepStats& lastStats() const { return mStats; }
    const SimulationSettings& settings() const { return mSettings; }

    /// [J] elastic + kinetic + gravitational energy.
    double totalEnergy() const;
    /// Largest edge strain (length / rest - 1) over the mesh edges; 0 without a mesh.
    double maxEdgeStrain() const { return mEdges.maxStrain(mState.positions); }
    uint64_t stateHash() const { return mState.hash(); }

private:
    ClothSimulation() = default;
    Status init(std::unique_ptr<ForceModel> model, double damping);

    SimulationSettings mSettings;
    std::unique_ptr<ForceModel> mModel;
    std::unique_ptr<Integrator> mIntegrator;
    ClothState mState;
    ClothState mBackup;
    ConstraintSet mConstraints;
    StrainLimiter mEdges;
    StepStats mStats;
};

} // namespace cc::cloth

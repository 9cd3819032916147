#pragma once

#include <memory>
#include <vector>

#include "crowdcloth/cloth/CholmodSolver.h"
#include "crowdcloth/cloth/FilteredPcg.h"
#include "crowdcloth/cloth/Integrator.h"

namespace cc::cloth {

enum class LinearSolverKind {
    Pcg,      ///< filtered block-Jacobi PCG, warm-started from the previous step
    Cholmod,  ///< CHOLMOD Cholesky factorisation each step (symbolic analysis kept)
};

/// Linearised backward Euler (Baraff & Witkin 1998, "Large steps in cloth simulation"): one Newton
/// step of the implicit update, with Rayleigh damping f_d = -beta K v,
///   (M + h (h + beta) K) dv = h (f(x0) + M g - (h + beta) K v0),   v1 = v0 + dv,  x1 = x0 + h v1,
/// where K is the definite stiffness at x0 and dv is filtered by the constraints. Unconditionally
/// stable for the linear problem: at any dt and stiffness it dissipates instead of exploding.
///
/// One Newton step is not enough when a stiff cloth rotates far within a step: the linearised
/// update over-stretches it (energy spikes of 1e7 J were measured at 1e7 N/m and dt = 1/15 s). As
/// in Baraff & Witkin's step-size control, a step that *creates* energy,
///   dE_elastic + dE_kinetic + dE_gravity - W_constraints > energyTolerance * scale,
/// is undone and taken as two half steps (recursively, at most maxHalvings deep), where
/// W_constraints = (A dv - b) . dx / h is the work of pins, attachments and contacts over the step
/// (plus that of the friction impulse, applied after the solve; ConstraintSet::applyFriction), and
/// scale = E_elastic + E_kinetic + |dE_gravity| + |W_constraints| at the step.
class ImplicitEulerIntegrator final : public Integrator {
public:
    struct Settings {
        LinearSolverKind solver = LinearSolverKind::Pcg;
        PcgSettings pcg;
        bool warmStart = true;  ///< start PCG from the previous step's dv
        double energyTolerance = 0.01;  ///< [-] relative energy a step may create before it is split
        int maxHalvings = 6;            ///< [-] split depth limit (dt / 64); 0 = no step-size control
    };

    /// Binds the model to this integrator's matrix pattern (so the model must outlive it and not be
    /// shared with another implicit integrator of a different pattern).
    ImplicitEulerIntegrator(ForceModel& model, const IntegratorSettings& common, const Settings& settings);
    const char* name() const override;
    Status step(double dt, const ConstraintSet& constraints, ClothState& state, StepStats& outStats) override;

    /// The system matrix of the last step (for tests and benchmarks).
    const BlockSparseMatrix& systemMatrix() const { return mSystem; }
    const CholmodSolver& cholmod() const { return mCholmod; }

private:
    // Advances the part of the outer step that ends at `fraction1` (of mOuterDt) and lasts h;
    // targets are interpolated from mStepStart, so split steps reach them at the end.
    Status substep(double h, double fraction1, const ConstraintSet& constraints, ClothState& state, int depth,
                   StepStats& stats);
    Status solveOnce(double h, double fraction1, const ConstraintSet& constraints, ClothState& state,
                     StepStats& stats);
    double createdEnergy(double h, const ClothState& before, const ClothState& after, double elasticBefore,
                         double& outScale);

    double mOuterDt = 0.0;
    ForceModel& mModel;
    IntegratorSettings mCommon;
    Settings mSettings;
    BlockSparseMatrix mSystem;
    std::vector<Vec3> mForces, mStiffV, mRhs, mFixed, mDv, mStepStart, mScratch, mFrictionImpulse;
    std::vector<ClothState> mSaved;  // per split depth, so the hot path reuses its storage
    std::vector<VertexFilter> mFilters;
    PcgWorkspace mPcg;
    CholmodSolver mCholmod;
};

} // namespace cc::cloth

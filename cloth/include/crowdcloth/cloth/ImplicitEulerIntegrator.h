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
class ImplicitEulerIntegrator final : public Integrator {
public:
    struct Settings {
        LinearSolverKind solver = LinearSolverKind::Pcg;
        PcgSettings pcg;
        bool warmStart = true;  ///< start PCG from the previous step's dv
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
    ForceModel& mModel;
    IntegratorSettings mCommon;
    Settings mSettings;
    BlockSparseMatrix mSystem;
    std::vector<Vec3> mForces, mStiffV, mRhs, mFixed, mDv;
    std::vector<VertexFilter> mFilters;
    PcgWorkspace mPcg;
    CholmodSolver mCholmod;
};

} // namespace cc::cloth

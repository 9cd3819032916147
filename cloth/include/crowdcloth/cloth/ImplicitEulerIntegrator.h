#pragma once

#include <memory>
#include <vector>

#include "crowdcloth/cloth/CholmodSolver.h"
#include "crowdcloth/cloth/FilteredPcg.h"
#include "crowdcloth/cloth/Integrator.h"
#include "crowdcloth/cloth/MultigridPcg.h"

namespace cc::cloth {

enum class LinearSolverKind {
    Pcg,        ///< filtered block-Jacobi PCG, warm-started from the previous step
    Cholmod,    ///< CHOLMOD Cholesky factorisation each step (symbolic analysis kept)
    Multigrid,  ///< filtered PCG preconditioned by a multigrid V-cycle (MultigridPcg), warm-started
};

/// What the Newton iterations of the last step did (ImplicitEulerIntegrator::newtonStats()).
struct NewtonStats {
    int iterations = 0;             ///< [-] linear solves of the last (sub)step, >= 1
    double relativeResidual = 0.0;  ///< [-] |S r(dv)| / |S r(-v0)| at the end; 0 when not measured
    int backtracks = 0;             ///< [-] halvings of the line search
    bool converged = true;          ///< false if newtonIterations ran out above newtonTolerance or
                                    ///< the line search found no decrease
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
///
/// Newton to convergence (newtonIterations > 1) solves the nonlinear backward Euler step with the
/// damping matrix frozen at x0 (K0, as in the linearised step),
///   r(dv) = h (f(x1) + M g - beta K0 v1) - M dv = 0,   v1 = v0 + dv,  x1 = x0 + h v1,
/// on the free directions (the filter and z of the step are kept; constraint forces take up
/// the rest). r is minus the gradient of the incremental potential (Martin et al. 2011; Gast et
/// al. 2015, "Optimization integrator for large time steps")
///   Phi(dv) = 1/2 dv^T M dv + E(x1) - x1^T M g + h beta / 2 v1^T K0 v1,
/// so each iteration solves (M + h^2 K(x1) + h beta K0) delta = r with the definite K(x1) (a
/// descent direction even where the true Hessian is indefinite; so this is a quasi-Newton method
/// that converges linearly, about 0.35 per iteration on a hanging sheet at dt = 1/30 s) and
/// backtracks delta until Phi decreases enough (Armijo). Near convergence Phi's change drops below
/// its rounding noise; then a full step is taken only if it lowers |S r|. The first iteration is
/// the linearised step above, unchanged. A step whose line search fails keeps its best iterate;
/// the energy check then splits it if needed.
class ImplicitEulerIntegrator final : public Integrator {
public:
    struct Settings {
        LinearSolverKind solver = LinearSolverKind::Pcg;
        PcgSettings pcg;
        MultigridSettings multigrid;  ///< the preconditioner of LinearSolverKind::Multigrid
        bool warmStart = true;  ///< start PCG (both kinds) from the previous step's dv
        double energyTolerance = 0.01;  ///< [-] relative energy a step may create before it is split
        int maxHalvings = 6;            ///< [-] split depth limit (dt / 64); 0 = no step-size control
        /// [-] Newton iterations (linear solves) per step at most; [1, 1000]. 1 = the linearised
        /// step of Baraff & Witkin (default); more = Newton on the nonlinear step (see above).
        int newtonIterations = 1;
        /// [-] Newton stops when |S r(dv)| <= newtonTolerance * |S r(-v0)|, where r(-v0) =
        /// h (f(x0) + M g) + M v0 is the residual of x1 = x0 (where the linearised step starts);
        /// [0, 1), 0 = always run newtonIterations. Default 1e-6. The linear solves must be at
        /// least this accurate (pcg.relativeTolerance, or CHOLMOD) for Newton to get there.
        double newtonTolerance = 1e-6;
    };

    /// Binds the model to this integrator's matrix pattern (so the model must outlive it and not be
    /// shared with another implicit integrator of a different pattern).
    ImplicitEulerIntegrator(ForceModel& model, const IntegratorSettings& common, const Settings& settings);
    const char* name() const override;
    Status step(double dt, const ConstraintSet& constraints, ClothState& state, StepStats& outStats) override;

    /// The system matrix of the last step (for tests and benchmarks).
    const BlockSparseMatrix& systemMatrix() const { return mSystem; }
    const CholmodSolver& cholmod() const { return mCholmod; }
    const MultigridPcg& multigrid() const { return mMultigrid; }
    /// Newton iterations of the last solve (of the last substep when a step was split).
    const NewtonStats& newtonStats() const { return mNewton; }

private:
    // Advances the part of the outer step that ends at `fraction1` (of mOuterDt) and lasts h;
    // targets are interpolated from mStepStart, so split steps reach them at the end.
    Status substep(double h, double fraction1, const ConstraintSet& constraints, ClothState& state, int depth,
                   StepStats& stats);
    Status solveOnce(double h, double fraction1, const ConstraintSet& constraints, ClothState& state,
                     StepStats& stats);
    double createdEnergy(double h, const ClothState& before, const ClothState& after, double elasticBefore,
                         double& outScale);
    // Solves the filtered system of mSystem with the configured solver into inOutDv.
    Status solveLinear(const std::vector<Vec3>& rhs, const std::vector<Vec3>& fixed,
                       std::vector<Vec3>& inOutDv, StepStats& stats);
    // Newton iterations after the linearised solve (mDv holds its dv); leaves the constraint
    // impulse -r(dv) in mImpulse.
    Status newton(double h, const ClothState& state, StepStats& stats);
    // Phi(dv) of the Newton line search (without constant terms); outScale: the sum of its terms'
    // magnitudes, which bounds its rounding error.
    double incrementalPotential(double h, const ClothState& state, const std::vector<Vec3>& dv,
                                double& outScale);
    // |S r(dv)|^2; leaves r in mResidual, -r in mImpulse, f(x1) in mForces and K(x1) in mSystem.
    double newtonResidual(double h, const ClothState& state, const std::vector<Vec3>& dv);

    double mOuterDt = 0.0;
    ForceModel& mModel;
    IntegratorSettings mCommon;
    Settings mSettings;
    BlockSparseMatrix mSystem;
    std::vector<Vec3> mForces, mStiffV, mRhs, mFixed, mDv, mStepStart, mScratch, mFrictionImpulse;
    std::vector<Vec3> mImpulse;     // h f_c = A dv - b (or -r(dv) after Newton), per vertex
    BlockSparseMatrix mStiffness0;  // K0, kept for Newton's damping term
    std::vector<Vec3> mResidual, mDelta, mZero, mTrialDv, mTrialX, mVelocity1;
    std::vector<ClothState> mSaved;  // per split depth, so the hot path reuses its storage
    std::vector<VertexFilter> mFilters;
    PcgWorkspace mPcg;
    CholmodSolver mCholmod;
    MultigridPcg mMultigrid;
    NewtonStats mNewton;
};

} // namespace cc::cloth

#include "crowdcloth/cloth/ImplicitEulerIntegrator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cc::cloth {

ImplicitEulerIntegrator::ImplicitEulerIntegrator(ForceModel& model, const IntegratorSettings& common,
                                                 const Settings& settings)
    : mModel(model), mCommon(common), mSettings(settings), mMultigrid(settings.multigrid) {
    std::vector<std::pair<uint32_t, uint32_t>> couplings;
    model.appendCouplings(couplings);
    mSystem.buildPattern(model.vertexCount(), std::move(couplings));
    model.bindMatrix(mSystem);
    mDv.assign(model.vertexCount(), Vec3::Zero());
    mSaved.resize(std::max(settings.maxHalvings, 0) + 1);
}

const char* ImplicitEulerIntegrator::name() const {
    switch (mSettings.solver) {
    case LinearSolverKind::Pcg: return "implicit-euler-pcg";
    case LinearSolverKind::Cholmod: return "implicit-euler-cholmod";
    case LinearSolverKind::Multigrid: return "implicit-euler-multigrid";
    }
    return "implicit-euler";
}

Status ImplicitEulerIntegrator::step(double dt, const ConstraintSet& constraints, ClothState& state,
                                     StepStats& outStats) {
    mOuterDt = dt;
    mStepStart = state.positions;
    outStats = StepStats{};
    return substep(dt, 1.0, constraints, state, 0, outStats);
}

Status ImplicitEulerIntegrator::substep(double h, double fraction1, const ConstraintSet& constraints,
                                        ClothState& state, int depth, StepStats& stats) {
    if (depth >= mSettings.maxHalvings) return solveOnce(h, fraction1, constraints, state, stats);

    ClothState& saved = mSaved[depth];
    saved.positions = state.positions;
    saved.velocities = state.velocities;
    const double elasticBefore = mModel.energy(state.positions);
    const StepStats statsBefore = stats;
    if (Status s = solveOnce(h, fraction1, constraints, state, stats); !s) return s;

    double scale = 0.0;
    const double created = createdEnergy(h, saved, state, elasticBefore, scale);
    if (created <= mSettings.energyTolerance * scale) return Status::ok();

    // The step created energy (or produced NaN): undo it and take two half steps.
    state.positions = saved.positions;
    state.velocities = saved.velocities;
    stats = statsBefore;
    const double middle = fraction1 - 0.5 * h / mOuterDt;
    if (Status s = substep(0.5 * h, middle, constraints, state, depth + 1, stats); !s) return s;
    return substep(0.5 * h, fraction1, constraints, state, depth + 1, stats);
}

double ImplicitEulerIntegrator::createdEnergy(double h, const ClothState& before, const ClothState& after,
                                              double elasticBefore, double& outScale) {
    // The work of the constraint forces: h f_c = A dv - b (mImpulse) on the constrained directions.
    const uint32_t n = after.vertexCount();
    double kinetic0 = 0.0, kinetic1 = 0.0, gravityWork = 0.0, constraintWork = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double m = after.masses[i];
        const Vec3 dx = after.positions[i] - before.positions[i];
        kinetic0 += 0.5 * m * before.velocities[i].squaredNorm();
        kinetic1 += 0.5 * m * after.velocities[i].squaredNorm();
        gravityWork += m * mCommon.gravity.dot(dx);
        const Vec3& impulse = mImpulse[i];
        constraintWork += (impulse - mFilters[i].project(impulse) + mFrictionImpulse[i]).dot(dx) / h;
    }
    const double elastic1 = mModel.energy(after.positions);
    outScale = elasticBefore + kinetic0 + std::abs(gravityWork) + std::abs(constraintWork);
    const double created = (elastic1 - elasticBefore) + (kinetic1 - kinetic0) - gravityWork - constraintWork;
    return std::isfinite(created) ? created : INFINITY;
}

Status ImplicitEulerIntegrator::solveLinear(const std::vector<Vec3>& rhs,
                                            const std::vector<Vec3>& fixed, std::vector<Vec3>& dv,
                                            StepStats& stats) {
    const ParallelSettings& par = mCommon.parallel;
    if (mSettings.solver == LinearSolverKind::Cholmod)
        return mCholmod.solve(mSystem, mFilters, rhs, fixed, dv);
    PcgResult r;
    if (mSettings.solver == LinearSolverKind::Pcg) {
        r = solveFilteredPcg(mSystem, mFilters, rhs, fixed, dv, mSettings.pcg, par, mPcg);
    } else if (Status s =
                   mMultigrid.solve(mSystem, mFilters, rhs, fixed, dv, mSettings.pcg, par, r);
               !s) {
        return s;
    }
    stats.iterations += r.iterations;
    stats.relativeResidual = std::max(stats.relativeResidual, r.relativeResidual);
    stats.converged = stats.converged && r.converged;
    return Status::ok();
}

double ImplicitEulerIntegrator::incrementalPotential(double h, const ClothState& state,
                                                     const std::vector<Vec3>& dv,
                                                     double& outScale) {
    const uint32_t n = state.vertexCount();
    for (uint32_t i = 0; i < n; ++i) {
        mVelocity1[i] = state.velocities[i] + dv[i];
        mTrialX[i] = state.positions[i] + h * mVelocity1[i];
    }
    mStiffness0.multiply(mVelocity1, mScratch, mCommon.parallel);
    const double elastic = mModel.energy(mTrialX);
    double inertia = 0.0, gravity = 0.0, damping = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double m = state.masses[i];
        inertia += 0.5 * m * dv[i].squaredNorm();
        gravity -= m * mCommon.gravity.dot(mTrialX[i]);
        damping += 0.5 * h * mCommon.damping * mVelocity1[i].dot(mScratch[i]);
    }
    outScale = std::abs(elastic) + inertia + std::abs(gravity) + std::abs(damping);
    return elastic + inertia + gravity + damping;
}

double ImplicitEulerIntegrator::newtonResidual(double h, const ClothState& state,
                                               const std::vector<Vec3>& dv) {
    const uint32_t n = state.vertexCount();
    const ParallelSettings& par = mCommon.parallel;
    for (uint32_t i = 0; i < n; ++i) {
        mVelocity1[i] = state.velocities[i] + dv[i];
        mTrialX[i] = state.positions[i] + h * mVelocity1[i];
        mForces[i].setZero();
    }
    mSystem.setZero(par);
    ForceEvaluation eval;
    eval.positions = mTrialX;
    eval.outForces = mForces;
    eval.outStiffness = &mSystem;
    eval.parallel = par;
    mModel.evaluate(eval);
    mStiffness0.multiply(mVelocity1, mScratch, par);
    double residual2 = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double m = state.masses[i];
        mResidual[i] =
            h * (mForces[i] + m * mCommon.gravity - mCommon.damping * mScratch[i]) - m * dv[i];
        mImpulse[i] = -mResidual[i];
        residual2 += mFilters[i].project(mResidual[i]).squaredNorm();
    }
    return residual2;
}

Status ImplicitEulerIntegrator::newton(double h, const ClothState& state, StepStats& stats) {
    const uint32_t n = state.vertexCount();
    const ParallelSettings& par = mCommon.parallel;
    for (auto* vec : {&mResidual, &mDelta, &mZero, &mTrialDv, &mTrialX, &mVelocity1})
        vec->assign(n, Vec3::Zero());

    // Reference: the residual of x1 = x0 (dv = -v0), with mForces still f(x0).
    double reference2 = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double m = state.masses[i];
        reference2 += mFilters[i]
                          .project(h * (mForces[i] + m * mCommon.gravity) + m * state.velocities[i])
                          .squaredNorm();
    }
    const double tolerance2 = mSettings.newtonTolerance * mSettings.newtonTolerance * reference2;
    double scale = 0.0;
    double phi = incrementalPotential(h, state, mDv, scale);
    double residual2 = newtonResidual(h, state, mDv);
    mNewton = NewtonStats{1, 0.0, 0, false};
    for (;;) {
        mNewton.relativeResidual = reference2 > 0.0 ? std::sqrt(residual2 / reference2) : 0.0;
        if (residual2 <= tolerance2) {
            mNewton.converged = true;
            return Status::ok();
        }
        if (mNewton.iterations >= mSettings.newtonIterations) return Status::ok();

        // J = M + h^2 K(x1) + h beta K0 (mSystem holds K(x1)), then (S J S) delta = S r with
        // delta's fixed part zero.
        parallelFor(n, par, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) {
                for (uint32_t k = mSystem.rowStart()[i]; k < mSystem.rowStart()[i + 1]; ++k) {
                    mSystem.block(k) =
                        h * h * mSystem.block(k) + h * mCommon.damping * mStiffness0.block(k);
                }
                mSystem.block(mSystem.diagonalSlot(uint32_t(i))).diagonal().array() +=
                    state.masses[i];
            }
        });
        std::fill(mDelta.begin(), mDelta.end(), Vec3::Zero());
        if (Status s = solveLinear(mResidual, mZero, mDelta, stats); !s) return s;
        ++mNewton.iterations;
        double slope = 0.0;  // -dPhi/dalpha at alpha = 0
        for (uint32_t i = 0; i < n; ++i) slope += mResidual[i].dot(mDelta[i]);
        if (!(slope > 0.0)) {  // no descent left (the solve is at roundoff): keep dv
            newtonResidual(h, state, mDv);
            return Status::ok();
        }

        // Backtracking (Armijo, c = 1e-4): halve the step until Phi decreases enough. Once the
        // decrease asked for is below Phi's rounding noise (n eps scale), Phi cannot tell; then
        // the full step is taken if it lowers the residual, else Newton stops where it is.
        constexpr int kMaxBacktracks = 30;
        const double noise = double(n) * std::numeric_limits<double>::epsilon() * scale;
        bool accepted = false;
        double alpha = 1.0;
        for (int t = 0; t < kMaxBacktracks && !accepted; ++t, alpha *= 0.5) {
            mNewton.backtracks += t > 0;
            for (uint32_t i = 0; i < n; ++i) mTrialDv[i] = mDv[i] + alpha * mDelta[i];
            double trialScale = 0.0;
            const double trial = incrementalPotential(h, state, mTrialDv, trialScale);
            if (trial <= phi - 1e-4 * alpha * slope) {
                accepted = true;
                phi = trial;
                scale = trialScale;
                mDv.swap(mTrialDv);
                residual2 = newtonResidual(h, state, mDv);
            } else if (1e-4 * alpha * slope <= noise) {
                const double trialResidual2 = newtonResidual(h, state, mTrialDv);
                if (trialResidual2 < residual2) {
                    accepted = true;
                    phi = trial;
                    scale = trialScale;
                    mDv.swap(mTrialDv);
                    residual2 = trialResidual2;
                } else {
                    newtonResidual(h, state, mDv);  // restores r, the impulse and K at dv
                }
                break;
            }
        }
        if (!accepted) return Status::ok();  // keeps the best iterate and its residual
    }
}

Status ImplicitEulerIntegrator::solveOnce(double h, double fraction1, const ConstraintSet& constraints,
                                          ClothState& state, StepStats& stats) {
    const uint32_t n = state.vertexCount();
    const auto& x = state.positions;
    auto& v = state.velocities;
    const ParallelSettings& par = mCommon.parallel;
    mForces.resize(n);
    mStiffV.resize(n);
    mRhs.resize(n);
    mFixed.resize(n);
    mFilters.resize(n);
    mScratch.resize(n);
    mFrictionImpulse.resize(n);

    // Elastic forces and definite stiffness K at x0.
    parallelFor(n, par, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) mForces[i].setZero();
    });
    mSystem.setZero(par);
    ForceEvaluation eval;
    eval.positions = x;
    eval.outForces = mForces;
    eval.outStiffness = &mSystem;
    eval.parallel = par;
    mModel.evaluate(eval);
    mSystem.multiply(v, mStiffV, par);

    // A = M + h (h + beta) K and b = h (f + M g - (h + beta) K v0), in place.
    const double damping = h + mCommon.damping;
    const double scale = h * damping;
    if (mSettings.newtonIterations > 1) {
        // Newton's damping term needs K0 after A has overwritten it.
        if (mStiffness0.rowStart() != mSystem.rowStart() ||
            mStiffness0.columns() != mSystem.columns()) {
            mStiffness0 = mSystem;
        }
        parallelFor(int64_t(mSystem.blockCount()), par, [&](int64_t b, int64_t e) {
            for (int64_t k = b; k < e; ++k)
                mStiffness0.block(uint32_t(k)) = mSystem.block(uint32_t(k));
        });
    }
    parallelFor(n, par, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            for (uint32_t k = mSystem.rowStart()[i]; k < mSystem.rowStart()[i + 1]; ++k) mSystem.block(k) *= scale;
            mSystem.block(mSystem.diagonalSlot(uint32_t(i))).diagonal().array() += state.masses[i];
            mRhs[i] = h * (mForces[i] + state.masses[i] * mCommon.gravity - damping * mStiffV[i]);
            const Vec3 goal = mStepStart[i] + fraction1 * (constraints.target(uint32_t(i)) - mStepStart[i]);
            mFilters[i] = constraints.filter(uint32_t(i), x[i], v[i], h, goal, mRhs[i] / state.masses[i],
                                              (1.0 - fraction1) * mOuterDt, mFixed[i]);
        }
    });

    ++stats.substeps;
    if (mSettings.solver != LinearSolverKind::Cholmod && !mSettings.warmStart) {
        std::fill(mDv.begin(), mDv.end(), Vec3::Zero());
    }
    if (Status s = solveLinear(mRhs, mFixed, mDv, stats); !s) return s;
    mImpulse.resize(n);
    if (mSettings.newtonIterations > 1) {
        if (Status s = newton(h, state, stats); !s) return s;
    } else {
        // The constraint impulse h f_c = A dv - b on the constrained directions, for friction and
        // the energy check.
        mNewton = NewtonStats{1, 0.0, 0, true};
        mSystem.multiply(mDv, mScratch, par);
        parallelFor(n, par, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) mImpulse[i] = mScratch[i] - mRhs[i];
        });
    }

    // Friction needs each contact's normal impulse. Its own impulse is kept for the energy check:
    // dragged along by a moving body, cloth gains kinetic energy that friction's work accounts for.
    const bool friction = constraints.hasFriction();
    parallelFor(n, par, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            v[i] += mDv[i];
            mFrictionImpulse[i].setZero();
            if (friction && mFilters[i].kind == ConstraintKind::ContactPlane) {
                const double normalDv = mFilters[i].normal.dot(mImpulse[i]) / state.masses[i];
                const Vec3 before = v[i];
                constraints.applyFriction(uint32_t(i), normalDv, v[i]);
                mFrictionImpulse[i] = state.masses[i] * (v[i] - before);
            }
            state.positions[i] += h * v[i];
        }
    });
    return Status::ok();
}

} // namespace cc::cloth

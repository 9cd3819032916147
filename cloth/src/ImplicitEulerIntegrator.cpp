#include "crowdcloth/cloth/ImplicitEulerIntegrator.h"

#include <cmath>

namespace cc::cloth {

ImplicitEulerIntegrator::ImplicitEulerIntegrator(ForceModel& model, const IntegratorSettings& common,
                                                 const Settings& settings)
    : mModel(model), mCommon(common), mSettings(settings) {
    std::vector<std::pair<uint32_t, uint32_t>> couplings;
    model.appendCouplings(couplings);
    mSystem.buildPattern(model.vertexCount(), std::move(couplings));
    model.bindMatrix(mSystem);
    mDv.assign(model.vertexCount(), Vec3::Zero());
    mSaved.resize(std::max(settings.maxHalvings, 0) + 1);
}

const char* ImplicitEulerIntegrator::name() const {
    return mSettings.solver == LinearSolverKind::Pcg ? "implicit-euler-pcg" : "implicit-euler-cholmod";
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
    // The work of the constraint forces: h f_c = A dv - b on the constrained directions.
    const uint32_t n = after.vertexCount();
    mScratch.resize(n);
    mSystem.multiply(mDv, mScratch, mCommon.parallel);
    double kinetic0 = 0.0, kinetic1 = 0.0, gravityWork = 0.0, constraintWork = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
        const double m = after.masses[i];
        const Vec3 dx = after.positions[i] - before.positions[i];
        kinetic0 += 0.5 * m * before.velocities[i].squaredNorm();
        kinetic1 += 0.5 * m * after.velocities[i].squaredNorm();
        gravityWork += m * mCommon.gravity.dot(dx);
        const Vec3 impulse = mScratch[i] - mRhs[i];
        constraintWork += (impulse - mFilters[i].project(impulse) + mFrictionImpulse[i]).dot(dx) / h;
    }
    const double elastic1 = mModel.energy(after.positions);
    outScale = elasticBefore + kinetic0 + std::abs(gravityWork) + std::abs(constraintWork);
    const double created = (elastic1 - elasticBefore) + (kinetic1 - kinetic0) - gravityWork - constraintWork;
    return std::isfinite(created) ? created : INFINITY;
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
    if (mSettings.solver == LinearSolverKind::Pcg) {
        if (!mSettings.warmStart) std::fill(mDv.begin(), mDv.end(), Vec3::Zero());
        const PcgResult r = solveFilteredPcg(mSystem, mFilters, mRhs, mFixed, mDv, mSettings.pcg, par, mPcg);
        stats.iterations += r.iterations;
        stats.relativeResidual = std::max(stats.relativeResidual, r.relativeResidual);
        stats.converged = stats.converged && r.converged;
    } else {
        if (Status s = mCholmod.solve(mSystem, mFilters, mRhs, mFixed, mDv); !s) return s;
    }

    // Friction needs each contact's normal impulse: h f_c = A dv - b on the constrained directions.
    // Its own impulse is kept for the energy check: dragged along by a moving body, cloth gains
    // kinetic energy that friction's work accounts for.
    const bool friction = constraints.hasFriction();
    if (friction) mSystem.multiply(mDv, mScratch, par);
    parallelFor(n, par, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            v[i] += mDv[i];
            mFrictionImpulse[i].setZero();
            if (friction && mFilters[i].kind == ConstraintKind::ContactPlane) {
                const double normalDv = mFilters[i].normal.dot(mScratch[i] - mRhs[i]) / state.masses[i];
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

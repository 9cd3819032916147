#include "crowdcloth/cloth/ImplicitEulerIntegrator.h"

namespace cc::cloth {

ImplicitEulerIntegrator::ImplicitEulerIntegrator(ForceModel& model, const IntegratorSettings& common,
                                                 const Settings& settings)
    : mModel(model), mCommon(common), mSettings(settings) {
    std::vector<std::pair<uint32_t, uint32_t>> couplings;
    model.appendCouplings(couplings);
    mSystem.buildPattern(model.vertexCount(), std::move(couplings));
    model.bindMatrix(mSystem);
    mDv.assign(model.vertexCount(), Vec3::Zero());
}

const char* ImplicitEulerIntegrator::name() const {
    return mSettings.solver == LinearSolverKind::Pcg ? "implicit-euler-pcg" : "implicit-euler-cholmod";
}

Status ImplicitEulerIntegrator::step(double h, const ConstraintSet& constraints, ClothState& state,
                                     StepStats& outStats) {
    const uint32_t n = state.vertexCount();
    const auto& x = state.positions;
    auto& v = state.velocities;
    const ParallelSettings& par = mCommon.parallel;
    mForces.resize(n);
    mStiffV.resize(n);
    mRhs.resize(n);
    mFixed.resize(n);
    mFilters.resize(n);

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
            mFilters[i] = constraints.filter(uint32_t(i), x[i], v[i], h, mFixed[i]);
        }
    });

    outStats = StepStats{};
    outStats.substeps = 1;
    if (mSettings.solver == LinearSolverKind::Pcg) {
        if (!mSettings.warmStart) std::fill(mDv.begin(), mDv.end(), Vec3::Zero());
        const PcgResult r = solveFilteredPcg(mSystem, mFilters, mRhs, mFixed, mDv, mSettings.pcg, par, mPcg);
        outStats.iterations = r.iterations;
        outStats.relativeResidual = r.relativeResidual;
        outStats.converged = r.converged;
    } else {
        if (Status s = mCholmod.solve(mSystem, mFilters, mRhs, mFixed, mDv); !s) return s;
    }

    parallelFor(n, par, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            v[i] += mDv[i];
            state.positions[i] += h * v[i];
        }
    });
    return Status::ok();
}

} // namespace cc::cloth

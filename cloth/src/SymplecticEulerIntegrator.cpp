#include "crowdcloth/cloth/SymplecticEulerIntegrator.h"

#include <cmath>
#include <string>

namespace cc::cloth {

SymplecticEulerIntegrator::SymplecticEulerIntegrator(const ForceModel& model, const IntegratorSettings& common,
                                                     const Settings& settings)
    : mModel(model), mCommon(common), mSettings(settings) {}

double SymplecticEulerIntegrator::maxFrequencyBound(const ClothState& state) {
    const uint32_t n = state.vertexCount();
    mForces.assign(n, Vec3::Zero());
    mRowBound.assign(n, Vec3::Zero());
    ForceEvaluation eval;
    eval.positions = state.positions;
    eval.outForces = mForces;
    eval.outStiffnessRowBound = mRowBound;
    eval.parallel = mCommon.parallel;
    mModel.evaluate(eval);
    double omega2 = 0.0;
    for (uint32_t i = 0; i < n; ++i) omega2 = std::max(omega2, mRowBound[i].maxCoeff() / state.masses[i]);
    return std::sqrt(omega2);
}

int SymplecticEulerIntegrator::requiredSubsteps(double dt, const ClothState& state) {
    const double omega = maxFrequencyBound(state);
    if (omega == 0.0) return 1;
    const double zeta = 0.5 * mCommon.damping * omega;
    const double hMax = mSettings.stabilitySafety * 2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta) / omega;
    const double n = std::ceil(dt / hMax);
    return n > 1e9 ? 1000000000 : std::max(1, static_cast<int>(n));
}

Status SymplecticEulerIntegrator::step(double dt, const ConstraintSet& constraints, ClothState& state,
                                       StepStats& outStats) {
    const int substeps = mSettings.fixedSubsteps > 0 ? mSettings.fixedSubsteps : requiredSubsteps(dt, state);
    if (substeps > mSettings.maxSubsteps) {
        return Status::invalidArgument(
            "symplectic Euler needs " + std::to_string(substeps) + " substeps for dt = " + std::to_string(dt) +
            " s at this stiffness and mass (maxSubsteps = " + std::to_string(mSettings.maxSubsteps) +
            "); use the implicit integrator or raise maxSubsteps");
    }
    const uint32_t n = state.vertexCount();
    const double h = dt / substeps;
    auto& x = state.positions;
    auto& v = state.velocities;
    mStartPositions = x;
    mForces.resize(n);
    ForceEvaluation eval;
    eval.positions = x;
    eval.velocities = v;
    eval.dampingCoefficient = mCommon.damping;
    eval.outForces = mForces;
    eval.parallel = mCommon.parallel;
    for (int s = 1; s <= substeps; ++s) {
        parallelFor(n, mCommon.parallel, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) mForces[i] = state.masses[i] * mCommon.gravity;
        });
        mModel.evaluate(eval);
        const double alpha = double(s) / substeps;  // targets are reached linearly over the step
        parallelFor(n, mCommon.parallel, [&](int64_t b, int64_t e) {
            for (int64_t i = b; i < e; ++i) {
                Vec3 vi = v[i] + (h / state.masses[i]) * mForces[i];
                if (constraints.kind(i) == ConstraintKind::Target) {
                    const Vec3 goal = mStartPositions[i] + alpha * (constraints.target(i) - mStartPositions[i]);
                    vi = (goal - x[i]) / h;
                } else if (constraints.kind(i) == ConstraintKind::ContactPlane) {
                    Vec3 z;
                    const VertexFilter f = constraints.filter(uint32_t(i), x[i], vi, h, x[i], Vec3::Zero(), (1.0 - alpha) * dt, z);
                    if (f.kind == ConstraintKind::ContactPlane) {
                        const Vec3 pushed = f.project(vi) + f.normal * (f.normal.dot(vi) + f.normal.dot(z));
                        const double normalDv = f.normal.dot(pushed - vi);
                        vi = pushed;
                        constraints.applyFriction(uint32_t(i), normalDv, vi);
                    }
                }
                v[i] = vi;
                x[i] += h * vi;
            }
        });
    }
    outStats = StepStats{};
    outStats.substeps = substeps;
    return Status::ok();
}

} // namespace cc::cloth

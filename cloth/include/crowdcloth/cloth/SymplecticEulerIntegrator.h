#pragma once

#include <vector>

#include "crowdcloth/cloth/Integrator.h"

namespace cc::cloth {

/// Symplectic (semi-implicit) Euler: v += h M^-1 f(x, v); x += h v.
///
/// Stable only while h * omega_max < 2 (less with damping), so each step first bounds the stiffest
/// mode with Gershgorin's theorem on M^-1 K (row sums of |K| over the vertex mass, an upper bound
/// on omega_max^2) and takes n = ceil(dt / h_max) substeps with
///   h_max = safety * 2 (sqrt(1 + zeta^2) - zeta) / omega_max,  zeta = beta omega_max / 2.
/// When n exceeds maxSubsteps it refuses with InvalidArgument instead of exploding.
class SymplecticEulerIntegrator final : public Integrator {
public:
    struct Settings {
        int maxSubsteps = 2000;        ///< [-] refuse steps needing more; >= 1
        int fixedSubsteps = 0;         ///< [-] > 0 overrides the stability estimate (tests only)
        double stabilitySafety = 0.9;  ///< [-] fraction of the stability limit used; (0, 1]
    };

    SymplecticEulerIntegrator(const ForceModel& model, const IntegratorSettings& common, const Settings& settings);
    const char* name() const override { return "symplectic-euler"; }
    Status step(double dt, const ConstraintSet& constraints, ClothState& state, StepStats& outStats) override;

    /// [1/s] Gershgorin upper bound on the highest angular frequency at `positions`.
    double maxFrequencyBound(const ClothState& state);
    /// Substeps a step of dt needs at the current state.
    int requiredSubsteps(double dt, const ClothState& state);

private:
    const ForceModel& mModel;
    IntegratorSettings mCommon;
    Settings mSettings;
    std::vector<Vec3> mForces, mRowBound, mStartPositions;
};

} // namespace cc::cloth

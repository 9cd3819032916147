#pragma once

#include "crowdcloth/cloth/ClothState.h"
#include "crowdcloth/cloth/ConstraintSet.h"
#include "crowdcloth/cloth/ForceModel.h"
#include "crowdcloth/core/ParallelFor.h"
#include "crowdcloth/core/Status.h"

namespace cc::cloth {

/// What one step did; filled by every integrator.
struct StepStats {
    int substeps = 0;             ///< [-] substeps taken (implicit: more than 1 when steps were split)
    int iterations = 0;           ///< [-] PCG iterations over all substeps (0 for explicit and CHOLMOD)
    double relativeResidual = 0;  ///< [-] final |r| / |rhs| of the linear solve
    bool converged = true;        ///< false if PCG stopped at its iteration cap
    int strainLimitPasses = 0;    ///< [-] Provot sweeps run
};

/// Settings every integrator reads.
struct IntegratorSettings {
    Vec3 gravity{0.0, -9.81, 0.0};  ///< [m/s^2] uniform acceleration
    double damping = 0.0;           ///< [s] Rayleigh stiffness-proportional damping beta; >= 0
    ParallelSettings parallel;
};

/// Advances a garment's state by one step under a force model and constraints.
class Integrator {
public:
    virtual ~Integrator() = default;
    virtual const char* name() const = 0;
    /// Advances `state` by dt [s]. On error the state may be partially advanced; ClothSimulation
    /// restores it.
    virtual Status step(double dt, const ConstraintSet& constraints, ClothState& state, StepStats& outStats) = 0;
};

} // namespace cc::cloth

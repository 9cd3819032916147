#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/cloth/ClothLevel.h"
#include "crowdcloth/cloth/ConstraintSet.h"
#include "crowdcloth/core/Contact.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::cloth {

/// Per-step choices of the substepped local/global solver; arguments of the step, never of the
/// cooked data, so changing them rebuilds nothing.
struct SubstepSettings {
    int substeps = 10;             ///< [-] substeps per step; [1, 4096]. Accuracy comes from
                                   ///< substeps, not iterations (Macklin et al. 2019, "Small
                                   ///< steps in physical simulation")
    int iterations = 1;            ///< [-] local/global iterations per substep; [1, 1000]. They
                                   ///< converge to the backward Euler substep
    double strainLimit = 0.0;      ///< [-] Provot limit on edge strain after the step, with tethers
                                   ///< to the attached nodes; 0 = off; [0, 10]
    int strainLimitPasses = 8;     ///< [-] most sweeps of the limit; [1, 1000]
    double contactThickness = 0.0; ///< [m] contact planes lie this far outside the body surface; [0, 1]
    Friction friction;             ///< Coulomb friction against contact surfaces

    /// Names the first invalid field.
    Status validate() const;
};

/// One instance of a batch: its state and this step's inputs. Spans must stay valid for the call.
struct SubstepLane {
    Span<Vec3> positions;          ///< [m] per simulation vertex of the level; in and out
    Span<Vec3> velocities;         ///< [m/s] per simulation vertex; in and out
    Span<const Vec3> targets;      ///< [m] per attached node (ClothLevel order): where it must be at
                                   ///< the end of the step; it moves there linearly over the substeps
    Span<const Contact> contacts;  ///< body contacts for the step (geometry at its end), by vertex
    Vec3 acceleration{0.0, -9.81, 0.0};  ///< [m/s^2] uniform external acceleration (gravity in the
                                         ///< simulation's frame)
};

/// What the step did to one lane.
struct SubstepLaneReport {
    Status status;                 ///< failed lanes keep their state as it was before the step
    int strainLimitPasses = 0;     ///< [-] sweeps of the strain limit
    uint32_t contactCorrections = 0; ///< [-] vertex pushes out of contact planes over all substeps
};

/// The most instances one kernel call steps together.
constexpr int kMaxSubstepLanes = 8;

/// Scratch of the solver, instance-major (every array holds [node][x, y, z][lane]); sized on first
/// use and kept, so a warm workspace does not allocate. One per thread.
struct SubstepWorkspace {
    std::vector<double> positions, velocities, previous, predicted, solution, attachedStart, attachedEnd;
    struct LaneContact {
        uint32_t node = 0;
        Vec3 normal = Vec3::Zero();
        Vec3 surfaceVelocity = Vec3::Zero();
        double offsetAtEnd = 0.0;  ///< [m] the plane is {x : normal . x = offset}, at the step's end
    };
    std::vector<LaneContact> contacts[kMaxSubstepLanes];
};

/// Shared-factor local/global in small steps (Liu, Bargteil, O'Brien & Kavan 2013, "Fast simulation
/// of mass-spring systems"; Bouaziz et al. 2014, "Projective dynamics"): per substep of
/// h = dt / substeps, the inertial prediction y = x + h v + h^2 a, then local/global iterations
/// from x = y: the local step projects each spring of x to its rest length (p_s), the global step
/// solves (M / h^2 + L) x = M / h^2 y + sum k_s A_s^T p_s with the level's prefactored matrix (the
/// iterations converge to the backward Euler substep; one is what small steps need), then contacts as projections with
/// Coulomb friction (Macklin et al. 2014, section 6) and v = (x - x_prev) / h. After the last
/// substep, Provot's strain limit (with tethers) if asked. Attached nodes are eliminated: they move
/// linearly to their targets.
///
/// Every lane is an independent instance of the same level: the kernel runs them side by side
/// (SIMD across instances), and a lane's result is bit for bit the same whatever else is in the
/// batch, and alone.
///
/// Fails (InvalidArgument) on mismatched sizes or a factor for another substep size; a lane with a
/// non-finite input or result reports NumericalFailure in its report and keeps its state.
Status stepSubsteps(const ClothLevel& level, const SubstepFactor& factor, double dt, const SubstepSettings& settings,
                    Span<const SubstepLane> lanes, SubstepWorkspace& workspace, Span<SubstepLaneReport> outReports);

} // namespace cc::cloth

#pragma once

#include <cstdint>
#include <vector>

#include "crowdcloth/cloth/ClothLevel.h"
#include "crowdcloth/cloth/ConstraintSet.h"
#include "crowdcloth/core/Contact.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::cloth {

/// How a substep solves backward Euler with the level's shared factor.
enum class SubstepMethod : uint8_t {
    /// One Newton step from the inertial prediction, its linear system solved by `iterations`
    /// conjugate-gradient iterations preconditioned by the shared factor: Baraff-Witkin's step with
    /// a preconditioner that already knows the whole mesh's stiffness. The accurate mode.
    Newton,
    /// Local/global iterations (projective dynamics): the cheapest mode, stiff but damped.
    LocalGlobal,
};

/// Per-step choices of the substepped solver; arguments of the step, never of the cooked data,
/// so changing them rebuilds nothing.
struct SubstepSettings {
    SubstepMethod method = SubstepMethod::Newton;
    int substeps = 4;              ///< [-] substeps per step; [1, 4096]. Accuracy comes from
                                   ///< substeps more than from iterations (Macklin et al. 2019,
                                   ///< "Small steps in physical simulation")
    int iterations = 4;            ///< [-] per substep: CG iterations (Newton) or local/global
                                   ///< iterations; [1, 1000]. Both converge to the backward
                                   ///< Euler substep
    bool warmStart = true;         ///< Newton: a substep after the first starts its CG from the
                                   ///< best multiple of the previous substep's correction (a line
                                   ///< search on the step's quadratic model); measured 0.4-0.7x
                                   ///< the error from zero at 4-8 substeps x 3-6 iterations
    double strainLimit = 0.0;      ///< [-] Provot limit on edge strain after the step, with tethers
                                   ///< to the attached nodes; 0 = off; [0, 10]
    int strainLimitPasses = 8;     ///< [-] most sweeps of the limit; [1, 1000]
    double contactThickness = 0.0; ///< [m] contact planes lie this far outside the body surface; [0, 1]
    /// [-] stiffness of a stretch or shear spring shorter than its rest length, as a fraction of its
    /// stiffness in tension; bending springs keep theirs. Woven cloth buckles rather than shortens
    /// (Choi & Ko 2002, "Stable but responsive cloth"): a mesh too coarse for its folds holds them
    /// as compression, and at full stiffness a circle skirt hung in folds springs back out flat.
    /// 1 = symmetric springs; [0, 1]
    double compressionStiffness = 1.0;
    /// [s] Rayleigh stiffness-proportional damping beta (Baraff & Witkin 1998): the springs resist
    /// motion with beta K v, K their Hessian (with the tension's stiffness across them), implicit in
    /// Newton's step. It damps a mode of frequency w by beta w / 2 of critical, so it settles the
    /// fast stretch and shear vibrations that contact pushes feed on a resting garment and barely
    /// touches a swing (0.01 s: 4 % of critical at 4 rad/s; a translation not at all). Newton only:
    /// local/global iterations damp those modes already; [0, 10]
    double stiffnessDamping = 0.0;
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
    /// The workspace keeps room for this many of the lane's contacts (the caller's list's
    /// capacity), so its copy allocates only when that list has grown, not when a lane with more
    /// contacts than its last takes the workspace; 0 = as many as given.
    std::size_t contactCapacity = 0;
    Vec3 acceleration{0.0, -9.81, 0.0};  ///< [m/s^2] uniform external acceleration (gravity in the
                                         ///< simulation's frame, less the frame origin's acceleration)
    /// The simulation's frame turns about its origin at this rate (rad/s, in the frame's axes):
    /// Coriolis -2 w x v, centrifugal -w x (w x r) and Euler -dw/dt x r act on every vertex, scaled
    /// by fictitiousScale (1 = full physics; an artist's inertia scale below, as NvCloth's).
    Vec3 frameAngularVelocity = Vec3::Zero();
    Vec3 frameAngularAcceleration = Vec3::Zero();  ///< [rad/s^2] dw/dt over the step
    double fictitiousScale = 1.0;                  ///< [-] scale of the rotation's forces; [0, 10]
    /// [1/s] velocities in the simulation's frame decay at this rate (exactly, per substep): the
    /// air and the cloth's internal friction, which let a swing settle (NvCloth's damping); >= 0
    double velocityDamping = 0.0;
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
    std::vector<double> residual, search, product, correction;  // Newton's conjugate gradients
    std::vector<double> lastCorrection;  // Newton's warm start: the previous substep's correction
    std::vector<double> springFrames;  // Newton: per spring and lane, its Hessian (n, k (1 - t), k t)
    struct LaneContact {
        uint32_t node = 0;
        Vec3 normal = Vec3::Zero();
        Vec3 surfaceVelocity = Vec3::Zero();
        double offsetAtEnd = 0.0;  ///< [m] the plane is {x : normal . x = offset}, at the step's end
        bool pushed = false;       ///< pushed in the current substep
    };
    std::vector<LaneContact> contacts[kMaxSubstepLanes];
    std::vector<uint8_t> fixedNodes;  // [node][lane]: held in place by the strain limit
    std::vector<double> permuted;     // the factor's own ordering, when it has one
};

/// Backward Euler in small steps with a shared prefactored matrix. Per substep of h = dt / substeps,
/// from the inertial prediction y = x + h v + h^2 a, backward Euler's position x minimises
/// |x - y|^2_M / (2 h^2) + E(x), E the springs' energy. The level's factor of P = M / h^2 + L
/// (L = sum_s k_s (e_a - e_b)(e_a - e_b)^T, the springs' Laplacian) serves both methods:
/// - Newton: one Newton step from y, (M / h^2 + H(y)) d = -grad E(y), x = y + d, with H the
///   springs' definite Hessian, solved by CG preconditioned with P (the issue's "Newton step
///   with PCG preconditioned by the constant matrix"; cf. Liu, Bouaziz & Kavan 2017, who use P as
///   quasi-Newton's initial Hessian). P equals H along the springs and overestimates it across
///   them, so few iterations resolve what P misses.
/// - LocalGlobal (Liu, Bargteil, O'Brien & Kavan 2013, "Fast simulation of mass-spring systems";
///   Bouaziz et al. 2014, "Projective dynamics"): from x = y, the local step projects each spring
///   of x to its rest length (p_s), the global step solves P x = M / h^2 y + sum k_s A_s^T p_s.
/// Soft bending springs the factor leaves out are explicit forces in the prediction (both methods). Then contacts as projections with Coulomb
/// friction (Macklin et al. 2014, section 6) and v = (x - x_prev) / h. After the last substep,
/// Provot's strain limit (with tethers) if asked. Attached nodes are eliminated: they move
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

/// Provot's strain limit (with tethers) alone, after a step's contact corrections: vertices flagged
/// in `fixedVertices` (one flag per simulation vertex, or empty) stay where the body put them and
/// their neighbours follow, instead of a pushed vertex standing out from the cloth. Uses
/// settings.strainLimit and strainLimitPasses; velocities change by the shift / dt.
Status limitStrain(const ClothLevel& level, double dt, const SubstepSettings& settings, const SubstepLane& lane,
                   Span<const uint8_t> fixedVertices, SubstepWorkspace& workspace, int* outPasses = nullptr);

} // namespace cc::cloth

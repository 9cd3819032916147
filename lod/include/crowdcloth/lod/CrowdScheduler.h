#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "crowdcloth/core/Math.h"
#include "crowdcloth/core/Span.h"
#include "crowdcloth/core/Status.h"

namespace cc::lod {

/// A camera as the scheduler sees it: where things land on screen.
struct SchedulerCamera {
    Mat4 viewProjection = Mat4::Identity(); ///< world -> clip space, column vectors, OpenGL
                                            ///< convention (visible: -w <= x, y, z <= w, w > 0)
    double viewportWidth = 1920.0;          ///< [px] > 0
    double viewportHeight = 1080.0;         ///< [px] > 0
};

/// The substepped solver's two methods (cloth/SubstepSolver.h): Newton steps with CG on the shared
/// factor (accurate), local/global iterations (cheapest).
enum class SolverChoice : uint8_t { SubstepNewton = 0, SubstepLocalGlobal = 1 };
constexpr int kSolverChoiceCount = 2;

/// How a garment meets its body, cheapest first.
enum class CollisionDetail : uint8_t {
    None = 0,            ///< asleep: nothing moves
    Proxies = 1,         ///< capsules/spheres fitted to the skeleton
    Mesh = 2,            ///< the skinned body mesh, proximity only
    MeshContinuous = 3,  ///< the skinned body mesh with continuous tests for fast limbs
};
constexpr int kCollisionDetailCount = 4;

/// What one cooked garment asset offers at one level (shared by every instance of the asset).
struct LevelProfile {
    double errorMetres = 0.0;  ///< [m] deviation of this level's result from the finest level's
                               ///< (e.g. p95 vertex distance of the drape); >= 0, finest = 0
    /// [-] measured error as a fraction of the garment's radius (an error table's), at the body
    /// speeds errorSpeeds: interpolated in the garment's speed (held beyond them) and added to
    /// errorMetres; >= 0, 0 = not measured
    double errorPerRadius[2] = {0.0, 0.0};
    double errorSpeeds[2] = {0.0, 1.0};  ///< [m/s] finite, ascending
    double costMs[kSolverChoiceCount] = {0.0, 0.0}; ///< [ms] one update per solver; <= 0 means the
                                                    ///< solver is not offered here
    double collisionCostMs[kCollisionDetailCount] = {0.0, 0.0, 0.0, 0.0}; ///< [ms] added to one
                               ///< update by each collision detail (mesh queries and continuous tests
                               ///< cost 10-30x the capsules a solver cost is measured with); >= 0
    int substeps = 4;          ///< [-] solver substeps per update; >= 1
    int iterations = 4;        ///< [-] solver iterations per substep; >= 1
    double selfCollisionCostMs = 0.0;  ///< [ms] added to one update by self-collision, which a
                               ///< garment seen large takes at the finest two levels
                               ///< (wantsSelfCollision): counted in the budget wherever it is on; >= 0
};

/// The levels of one asset, coarsest first.
struct GarmentProfile {
    std::vector<LevelProfile> levels;
};

/// What the scheduler decided for one garment.
struct GarmentSchedule {
    int level = -1;                       ///< index into the asset's levels (coarsest = 0); -1 = none yet
    SolverChoice solver = SolverChoice::SubstepNewton;
    int substeps = 4;                     ///< [-] solver substeps per update
    int iterations = 4;                   ///< [-] solver iterations per substep
    CollisionDetail collision = CollisionDetail::None;
    bool selfCollision = false;
    int updateInterval = 1;               ///< [frames] 1, 2, 4, ...: updated every n-th frame and
                                          ///< extrapolated in between; 0 = asleep
    bool visible = false;                 ///< inside at least one camera's frustum
    double screenRadiusPx = 0.0;          ///< [px] projected bounding-sphere radius (largest camera)
    double predictedErrorPx = 0.0;        ///< [px] level error plus update-rate lag, on screen
    double predictedCostMs = 0.0;         ///< [ms] per frame (one update's cost / updateInterval)
};

/// One garment's inputs for this frame.
struct GarmentRequest {
    uint64_t id = 0;          ///< unique; orders ties so the result never depends on input order
    uint32_t profile = 0;     ///< index into the profiles span
    Vec3 center = Vec3::Zero(); ///< [m] bounding-sphere centre (world)
    double radius = 1.0;      ///< [m] bounding-sphere radius; > 0
    double speed = 0.0;       ///< [m/s] body speed; >= 0
    double importance = 1.0;  ///< [-] weight of this garment's error; > 0
    bool atRest = false;      ///< cloth and body are still: may sleep when unseen
    GarmentSchedule previous; ///< last frame's decision (level -1 for a new garment)
};

/// Policy knobs. Every error is measured in pixels on the camera that sees the garment largest.
struct SchedulerSettings {
    double budgetMs = 30.0;             ///< [ms] CPU time per frame for all garments (sum over
                                        ///< threads: a 16.7 ms frame on 2 threads gives ~30); > 0
    double pixelTolerance = 1.0;        ///< [px] allowed error of a visible garment; > 0
    double hysteresis = 0.25;           ///< [-] a coarser setting must be this fraction under the
                                        ///< tolerance before it is taken; [0, 1)
    double frameDt = 1.0 / 60.0;        ///< [s] frame time; > 0
    double typicalAcceleration = 20.0;  ///< [m/s^2] cloth acceleration per 1 m/s of body speed used
                                        ///< to predict the lag of extrapolated frames; >= 0
    int maxUpdateInterval = 8;          ///< [frames] power of two in [1, 64]
    bool refineWithSlack = true;        ///< spend budget left over on the largest error gains
    double slackHeadroom = 0.1;         ///< [-] spending slack stops this fraction under the budget,
                                        ///< so a cost that jitters around it cannot flip a garment
                                        ///< back and forth (measured costs jitter by a few percent
                                        ///< summed over a frame's hundreds of updates); [0, 1)
    double meshCollisionRadiusPx = 40.0;  ///< [px] at or above: collide with the body mesh; >= 0
    double continuousSpeed = 1.5;       ///< [m/s] at or above (with mesh collision): continuous tests
    double selfCollisionRadiusPx = 250.0; ///< [px] at or above (finest two levels): self-collision

    /// Names the first invalid field.
    Status validate() const;
};

/// Chooses each garment's level, solver, substeps, collision detail and update rate for a frame.
///
/// A pure function of its inputs (no state, no clock, no threads):
/// 1. unseen garments take the coarsest level at the slowest rate, or sleep when at rest;
/// 2. seen ones take the coarsest level and slowest rate whose predicted screen error stays under
///    the tolerance, or where no level does the coarsest level with the least error (with
///    hysteresis against last frame's choice, so a still camera at a threshold never makes a
///    garment flicker); with slack spent (refineWithSlack), a seen garment keeps
///    last frame's finer choice as its start. Each garment's collision detail follows from its
///    size on screen and its body's speed, and its cost is counted in every choice;
/// 3. over budget, degrade where the least importance-weighted error per millisecond is lost;
///    with slack, refine where the most is gained up to budget * (1 - slackHeadroom). Between the
///    two nothing moves: a cost that jitters around the budget cannot flip a garment back and forth.
/// Ties are broken by id. `outSchedules[i]` answers `requests[i]`.
Status scheduleGarments(const SchedulerSettings& settings, Span<const SchedulerCamera> cameras,
                        Span<const GarmentProfile> profiles, Span<const GarmentRequest> requests,
                        Span<GarmentSchedule> outSchedules);

/// The scheduler's self-collision rule: a garment seen at one of its finest two levels and at least
/// selfCollisionRadiusPx large on screen (with the settings' hysteresis against `wasOn`, last
/// frame's answer). Exposed for a host's forced level, which replaces the scheduler's.
bool wantsSelfCollision(const GarmentSchedule& schedule, int level, int levelCount, bool wasOn,
                        const SchedulerSettings& settings);

/// Scratch of scheduleGarments kept between frames, so that a frame's schedule allocates nothing
/// once the crowd's size is steady. Holds no decision: results never depend on it.
class SchedulerWorkspace {
public:
    SchedulerWorkspace();
    ~SchedulerWorkspace();
    SchedulerWorkspace(SchedulerWorkspace&&) noexcept;
    SchedulerWorkspace& operator=(SchedulerWorkspace&&) noexcept;
    struct Buffers;

private:
    friend Status scheduleGarments(const SchedulerSettings&, Span<const SchedulerCamera>, Span<const GarmentProfile>,
                                   Span<const GarmentRequest>, Span<GarmentSchedule>, SchedulerWorkspace&);
    std::unique_ptr<Buffers> mBuffers;
};

/// scheduleGarments with kept scratch (the World's every frame).
Status scheduleGarments(const SchedulerSettings& settings, Span<const SchedulerCamera> cameras,
                        Span<const GarmentProfile> profiles, Span<const GarmentRequest> requests,
                        Span<GarmentSchedule> outSchedules, SchedulerWorkspace& work);

/// [px per m] at `point` for `camera`, and whether a sphere there is inside the frustum.
struct ScreenProjection {
    bool visible = false;
    double pixelsPerMetre = 0.0;
};
ScreenProjection projectSphere(const SchedulerCamera& camera, const Vec3& center, double radius);

} // namespace cc::lod

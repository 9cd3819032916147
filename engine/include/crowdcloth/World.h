#pragma once

#include <cstdint>
#include <cstddef>
#include <string>
#include <vector>

#include "crowdcloth/ErrorTable.h"
#include "crowdcloth/Export.h"
#include "crowdcloth/Ids.h"
#include "crowdcloth/Status.h"

namespace cc {

struct Character;  // engine/character: an imported or generated character (skeleton, skin, clips)

using AssetId = cc_asset_id;
using BodyId = cc_body_id;
using CharacterId = cc_character_id;
using GarmentId = cc_garment_id;

/// A host's job system (cc_task_runner in crowdcloth/Ids.h): runs task(context, i) for every i in
/// [0, count), in any order and on any threads, and returns when all have finished.
using TaskRunner = cc_task_runner;

/// Speed against accuracy in one choice: the solver effort and the pixel tolerance of a World,
/// picked from the configurations `cc_crowd --tradeoff` measures (README, "Speed against accuracy").
enum class QualityPreset : uint32_t {
    Fast = 0,      ///< 1 substep x 1 iteration at the finest level; 4 px tolerance
    Balanced = 1,  ///< 2 x 1; the default 1 px tolerance
    Quality = 2,   ///< 4 x 4 (the default WorldDesc's effort); 0.5 px tolerance
};

/// World-wide choices, fixed at creation.
struct CC_API WorldDesc {
    uint32_t maxThreads = 0;          ///< [-] threads that step garments; 0 = all OpenMP offers
    double frameBudgetMs = 12.0;      ///< [ms] wall time per frame the cloth may use; > 0
    uint32_t budgetThreads = 0;       ///< [-] threads the budget is spread over (CPU budget =
                                      ///< frameBudgetMs x this); 0 = the threads stepping garments.
                                      ///< Fix it (with fixedCostModel) for results that do not
                                      ///< depend on the thread count
    double pixelTolerance = 1.0;      ///< [px] error a visible garment may show; > 0
    bool fixedCostModel = false;      ///< deterministic cost predictions (tests, replays) instead
                                      ///< of learning them from measured times; with learned costs
                                      ///< the chosen levels follow this machine's timing
    double gravity[3] = {0.0, -9.81, 0.0}; ///< [m/s^2] finite
    TaskRunner taskRunner = nullptr;  ///< the host's job system for the garment tasks; null = OpenMP
    void* taskRunnerUserData = nullptr;
    uint32_t maxUpdateInterval = 16;  ///< [frames] slowest update of a far garment, power of two
    uint32_t substeps = 4;            ///< [-] solver substeps per update of a 1/60 s frame at an
                                      ///< asset's finest level (backward Euler in small steps;
                                      ///< accuracy grows with them); every second coarser level
                                      ///< takes half; a longer frame takes more (effortAt); [1, 64]
    uint32_t solverIterations = 4;    ///< [-] conjugate-gradient iterations per substep on the
                                      ///< shared factor at the finest level; each coarser level one
                                      ///< fewer (at least 1); [1, 100]
    uint32_t batchSize = 4;           ///< [-] garments of one asset and level stepped together per
                                      ///< solver call (SIMD across them; results never depend on
                                      ///< it); [1, 8]
    double strainLimit = 0.1;         ///< [-] Provot limit on edge strain after each update (with tethers
                                      ///< to the attachments); 0 = off; [0, 10]
    bool selfCollision = false;       ///< let the scheduler turn garment self-collision on for the largest
                                      ///< garments on screen (separating planes in the solve, a
                                      ///< continuous pass after it; its cost counted in the budget);
                                      ///< 1.0-2.3x a garment's own solve on a walking mannequin
                                      ///< (cc_crowd --self-collision). Off by default: in the crowd,
                                      ///< turned on for a garment already crossing itself, it holds
                                      ///< the crossings and runs the fail-safe at 8-25 ms an update
                                      ///< (README, Self-collision); a garment at rest moves more
    bool spendSlack = true;           ///< budget left after every garment meets the tolerance refines
                                      ///< the garments that gain most (false: stop at the tolerance)
    Status validate() const;
    /// Sets pixelTolerance, substeps and solverIterations to `preset`'s (everything else, threads
    /// and budget included, stays the host's). An unknown preset is an error naming its value.
    Status applyPreset(QualityPreset preset);

    /// The solver work per update a garment gets at `level` of an asset with `levelCount` levels:
    /// substeps and iterations at the finest level; each coarser level one iteration fewer and
    /// every second one half the substeps (at least one each), since a coarse level's heavier nodes
    /// condition its system better and its picture is coarse anyway. The substeps are those of a
    /// 1/60 s frame: a frame of `frameDt` [s] gets them in proportion (rounded, at least one), so
    /// a substep stays as long whatever the host's frame rate (as NvCloth's solver frequency is
    /// per second), at most 64. A host at 30 Hz then pays per second what one at 60 Hz does, and
    /// its cloth stretches less: the humanoid suite's 30 Hz cases went from 333 to 298 of 540
    /// updates past the strain limit, a poncho on the walking mannequin from 75 % to 24 % median
    /// strain (README, Any humanoid).
    struct Effort {
        uint32_t substeps, iterations;
    };
    static constexpr double kEffortFrame = 1.0 / 60.0; ///< [s] the frame `substeps` is given for
    Effort effortAt(uint32_t level, uint32_t levelCount, double frameDt = kEffortFrame) const;
};

enum class GarmentKind : uint32_t {
    Cape = 0,    ///< hangs from the back of the neck, over the shoulders and down the back
    Skirt = 1,   ///< a tube hung from the waist
    Dress = 2,   ///< front and back panels sewn along both sides, hung from the chest under the arms
    Poncho = 3,  ///< a tube hung from the neck over the shoulders, all round
};

/// How a garment's panels are cut (the pattern's flare).
enum class GarmentCut : uint32_t {
    Straight = 0,  ///< as wide at the hem as where it hangs from (the old rectangles and tubes); a
                   ///< skirt or dress cut as wide as the body below needs, a poncho widening as
                   ///< far as it must to pass over the arms
    ALine = 1,     ///< widening to the hem: a skirt or dress then clears the legs in a stride, a cape
                   ///< or poncho spreads over the back and arms
    Circle = 2,    ///< as much flare as cloth can be cut with: a circle skirt (its pattern an annulus),
                   ///< a half-circle cape
};

/// A garment design, cooked for every body that wears it (once per body) and shared by every
/// character with that body. Sizes left at 0 are fitted to the body: measured from its skeleton
/// and geometry (or the landmarks a host hands in, see setBodyLandmarks). Sizes given are checked
/// against the body: a skirt whose waist is smaller than the wearer's gives an error.
struct CC_API ClothAssetDesc {
    GarmentKind kind = GarmentKind::Cape;
    GarmentCut cut = GarmentCut::ALine;
    double width = 0.0;              ///< [m] where it hangs from the body: cape across the shoulders
                                     ///< (along the back, tip to tip); skirt the waist, dress the chest,
                                     ///< poncho round the shoulders (circumferences); 0 = fitted (the
                                     ///< body's plus ease); [0, 10]
    double length = 0.0;             ///< [m] from where it hangs down to the hem; 0 = relativeLength
                                     ///< body heights; [0, 10]
    double relativeLength = 0.0;     ///< [body heights] length when `length` is 0; 0 = the kind's
                                     ///< default (cape 0.5, skirt 0.3, dress 0.45, poncho 0.3); [0, 1]
    double hemWidth = 0.0;           ///< [m] width of the hem (circumference for a skirt, dress or
                                     ///< poncho, along the cloth for a cape); 0 = the cut's; [0, 50]
    double ease = 0.04;              ///< [m] girth added to the body's where the garment hangs (and
                                     ///< clearance elsewhere); [0, 0.5]
    double cellSize = 0.2;           ///< [m] base (level 0) grid spacing; (0, 1]
    uint32_t levelCount = 5;         ///< [-] uniform levels 0..levelCount-1, each halving triangle
                                     ///< area; [1, 10]
    uint32_t renderLevel = 4;        ///< [-] level of the fixed render mesh; >= levelCount - 1, <= 10
    double arealDensity = 0.15;      ///< [kg/m^2] > 0
    double stretchStiffness = 5.0e3; ///< [N/m] > 0
    double shearStiffness = 5.0e2;   ///< [N/m] > 0
    double bendStiffness = 1.0e-5;   ///< [N m] >= 0
    double compressionStiffness = 0.1; ///< [-] stiffness of stretch and shear shorter than rest, as a
                                     ///< fraction of theirs in tension: cloth buckles into folds finer
                                     ///< than the mesh instead (at 1 a circle skirt, hung in folds,
                                     ///< springs out flat; at 0 a cape narrows to a strip); [0, 1]
    double damping = 7.0e-4;         ///< [s] Rayleigh stiffness-proportional (beta K v, implicit in
                                     ///< Newton's substeps): damps a mode of frequency w by beta w / 2
                                     ///< of critical, so the default damps the cloth's stretch
                                     ///< vibrations (0.35-4x critical over the finest level's
                                     ///< ~1,000-12,000 rad/s) and leaves a swing (0.1 % at 4 rad/s)
                                     ///< alone.
                                     ///< Without it, the energy a few CG iterations leave in those
                                     ///< vibrations is not damped at small substeps: 32 substeps x 4
                                     ///< iterations were 4x further from the converged reference than
                                     ///< 4 x 4 (README, Garments at rest). 0.01 s also settles a
                                     ///< garment at rest (0.05-0.2 mm RMS a frame instead of 0.5-3.1
                                     ///< at the default on a still mannequin) but lets the body's
                                     ///< pushes stretch a walking cape past the strain limit more
                                     ///< often; [0, 10]
    double velocityDamping = 0.0;    ///< [1/s] the cloth's velocity relative to its character decays
                                     ///< at this rate (air, friction: a swing settles in ~3 / this
                                     ///< seconds; NvCloth's damping); [0, 100]
    double thickness = 0.01;         ///< [m] collision offset from the body; > 0
    double friction = 0.3;           ///< [-] Coulomb coefficient against the body; [0, 2]
    double foldRadius = 0.1;         ///< [m] typical fold radius of the drape: a level with edges h
                                     ///< misses about h^2 / (8 foldRadius) of it (error model); > 0
    Status validate() const;
};

/// Proportions of a built-in procedural mannequin (see engine/character's MannequinParams).
struct MannequinDesc {
    double height = 1.80;         ///< [m] [1.0, 2.5]
    double shoulderWidth = 0.40;  ///< [m] [0.25, 0.6]
    double hipWidth = 0.34;       ///< [m] [0.22, 0.55]
    double waistWidth = 0.28;     ///< [m] [0.18, 0.5]
    double limbGirth = 1.0;       ///< [-] [0.6, 1.6]
};

/// How an imported character becomes a body (see World::addCharacterBody).
struct BodyDesc {
    double height = 0.0;  ///< [m] scales the character uniformly to this standing height (a rig
                          ///< authored in other units, a giant); 0 = as authored; [0, 100]
};

/// Where garments sit on a body, for a host that knows better than the measurements: heights of
/// the rings garments hang from, in the body's bind space (metres, Y up). Girths and widths left
/// at 0 are measured at the heights given.
struct BodyLandmarkDesc {
    double forward[3] = {0, 0, 1};  ///< horizontal direction the body faces; non-zero
    double neckY = 0.0;             ///< [m] base of the neck (a cape's or poncho's collar)
    double shoulderY = 0.0;         ///< [m] shoulder joints
    double chestY = 0.0;            ///< [m] under the arms (a dress's top)
    double waistY = 0.0;            ///< [m] natural waist (a skirt's waistband)
    double hipY = 0.0;              ///< [m] widest part of the hips
    double neckGirth = 0.0;         ///< [m] 0 = measured at neckY
    double chestGirth = 0.0;        ///< [m] 0 = measured at chestY
    double waistGirth = 0.0;        ///< [m] 0 = measured at waistY
    double hipGirth = 0.0;          ///< [m] 0 = measured at hipY
    double shoulderWidth = 0.0;     ///< [m] outer shoulder to outer shoulder; 0 = measured
    double stride = 0.0;            ///< [rad] how far each thigh swings from the vertical in the
                                    ///< body's widest stride, seen from the side: skirts and
                                    ///< dresses are cut to clear the knees there (30 degrees at
                                    ///< least, 75 at most); 0 = measured from the body's clips (a
                                    ///< host-skinned body has none: 30 degrees); [0, pi/2)
};

/// One animated character in the world.
struct CharacterDesc {
    BodyId body{};                   ///< from addMannequinBody / addCharacterBody / addSkinnedBody
    const char* clip = "walk";       ///< clip name (exact, else ignoring case); nullptr or "" = the
                                     ///< rest pose; ignored when clipIndex >= 0
    int32_t clipIndex = -1;          ///< [-] clip by its index in the body's clips (file order); -1 =
                                     ///< by name
    double clipTime = 0.0;           ///< [s] where the clip starts; advanced by step(dt)
    double clipPhase = 0.0;          ///< [-] fraction of the clip's duration added to clipTime (crowds
                                     ///< out of step); [0, 1]
    double playbackRate = 1.0;       ///< [-] clip seconds per world second; [0, 10]
    double position[3] = {0, 0, 0};  ///< [m] root position on the ground
    double yaw = 0.0;                ///< [rad] heading about +Y (0 faces +Z)
};

/// One garment worn by a character.
struct GarmentDesc {
    double importance = 1.0;  ///< [-] weight of its error when the budget is tight; > 0
    int32_t forceLevel = -1;  ///< [-] simulate at this uniform level every frame, whatever the
                              ///< schedule says (cut-scenes, reference runs); -1 = scheduled
    double inertiaScale = 1.0; ///< [-] how much of the character's motion the cloth feels: the
                              ///< forces of its root's acceleration and turning (linear, centrifugal,
                              ///< Coriolis, Euler); 1 = full physics, 0 = carried rigidly with the
                              ///< root (NvCloth's and Unity's inertia scale); [0, 2]
};

/// A camera: how the world lands on screen (column-major, OpenGL clip convention).
struct CameraDesc {
    double viewProjection[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    double viewportWidth = 1920.0;   ///< [px] > 0
    double viewportHeight = 1080.0;  ///< [px] > 0
};

/// A garment's render mesh: fixed topology, valid until the next step() or removal.
struct RenderMeshView {
    const float* positions = nullptr;  ///< [m] xyz per vertex, tightly packed
    const float* normals = nullptr;    ///< unit xyz per vertex
    uint32_t vertexCount = 0;
    const uint32_t* indices = nullptr; ///< 3 per triangle, counter-clockwise seen from the front
    uint32_t triangleCount = 0;
};

/// The substepped solver's methods: Newton steps by CG on a shared factor, local/global iterations.
enum class SolverKind : uint32_t { SubstepNewton = 0, SubstepLocalGlobal = 1 };
enum class CollisionKind : uint32_t { None = 0, Proxies = 1, Mesh = 2, MeshContinuous = 3 };

/// What happened to one garment in the last frame.
struct GarmentStats {
    int32_t level = -1;              ///< uniform level simulated
    uint32_t vertexCount = 0;        ///< simulated vertices
    SolverKind solver = SolverKind::SubstepNewton;
    uint32_t substeps = 1;           ///< solver substeps of the update
    uint32_t iterations = 0;         ///< solver iterations over the update (substeps x per substep)
    uint32_t updateInterval = 1;     ///< [frames] 0 = asleep
    bool updated = false;            ///< stepped this frame (else carried with its character, or asleep)
    bool levelSwitched = false;      ///< changed level or solver this frame
    CollisionKind collision = CollisionKind::None;
    bool selfCollision = false;
    uint32_t contacts = 0;
    uint32_t failSafes = 0;          ///< self-collision impact zones that had to be frozen
    bool failed = false;             ///< the step failed; the garment kept its last good state
    double screenRadiusPx = 0.0;
    double predictedErrorPx = 0.0;
    double predictedMs = 0.0;        ///< [ms] predicted cost of this frame's update
    double measuredMs = 0.0;         ///< [ms] measured (0 when not updated)
    double collisionMs = 0.0;        ///< [ms] of measuredMs spent on contacts
    double selfCollisionMs = 0.0;    ///< [ms] of collisionMs spent on self-collision (the separating
                                     ///< planes before the solve, the continuous resolve after it)
    double maxStrain = 0.0;          ///< [-] largest edge strain after the update
    double maxAttachmentError = 0.0; ///< [m] largest distance of an attached vertex from its skinned
                                     ///< target after the update
    bool restarted = false;          ///< met the body mesh tangled with it (after capsules far away,
                                     ///< a coarse level, a camera cut) and started again from its
                                     ///< fitted placement, carried by the torso to this pose
};

/// Totals of the last frame.
struct FrameStats {
    uint64_t frame = 0;
    double scheduleMs = 0.0;  ///< [ms] wall: costing and scheduling every garment
    double simulateMs = 0.0;  ///< [ms] wall: posing bodies, updating and publishing garments (parallel)
    double totalMs = 0.0;     ///< [ms] wall: the whole step
    double predictedCpuMs = 0.0;     ///< [ms] sum of predicted garment costs
    double measuredCpuMs = 0.0;      ///< [ms] sum of measured garment costs
    double budgetCpuMs = 0.0;        ///< [ms] what the scheduler was allowed (frame budget x threads)
    uint32_t garments = 0, updated = 0, asleep = 0, visible = 0, failed = 0, levelSwitches = 0;
    uint32_t batches = 0;            ///< solver calls that stepped the updated garments together
    uint32_t garmentsPerLevel[16] = {};
    uint32_t threads = 1;
};

/// The shadow check (World::setShadowCheck): what the scheduler predicts, measured in the crowd as
/// it runs. A garment seen and just updated is followed: a reference copy runs at its asset's
/// finest level under the reference effort against colliders of its own (the body mesh, continuous
/// tests). After a 0.5 s warm-up, windows are restarted from the reference's state: a copy
/// restricted to the garment's level runs as the scheduler ran the garment when the window opened
/// (effort, update interval, collision detail); at the window's end it is compared with the
/// reference on every camera. Four windows per garment, then the next garment in handle order.
/// Costs a reference solve per followed garment per frame, run after the frame's stats are taken
/// (outside the budget and FrameStats::totalMs); the crowd's own results do not change.
struct ShadowCheckDesc {
    uint32_t garments = 0;        ///< [-] garments followed at once; 0 = off; [0, 64]
    double windowSeconds = 0.25;  ///< [s] one window; [0.05, 2]
    uint32_t substeps = 64;       ///< [-] the reference's substeps per frame; [2, 64]
    uint32_t iterations = 40;     ///< [-] its iterations per substep; [1, 100]
    Status validate() const;
};

/// One window of the shadow check, at its end.
struct ShadowCheckResult {
    GarmentId garment{};
    int32_t level = -1;               ///< the garment's level when the window opened
    int32_t referenceLevel = -1;      ///< the level the reference ran at (the asset's finest)
    uint32_t updateInterval = 1;      ///< [frames] the garment's then
    double screenRadiusPx = 0.0;      ///< [px] its projected radius then
    double predictedErrorPx = 0.0;    ///< [px] the scheduler's prediction then
    double measuredErrorPx = 0.0;     ///< [px] at the window's end, largest on-screen distance of a
                                      ///< render vertex of the copy run as scheduled from the
                                      ///< reference's, over every camera
    double measuredRmsMetres = 0.0;   ///< [m] render vertex distances, root mean square
    double measuredMaxMetres = 0.0;   ///< [m] and largest
    double referenceCheckPx = 0.0;    ///< [px] the reference restarted at half its substeps, from
                                      ///< the reference, measured as measuredErrorPx: how far the
                                      ///< reference is resolved (errors below it are not)
    double measuredRmsPx = 0.0;       ///< [px] root mean square of the on-screen distances of the
                                      ///< copy's render vertices from the reference's (the largest
                                      ///< over cameras): the garment's typical error, where
                                      ///< measuredErrorPx is its worst vertex's
    double referenceCheckRmsPx = 0.0; ///< [px] the same of the half-substep reference
};

/// What a restoreState may change of the saved run.
enum class RestoreMode : uint32_t {
    Continue = 0,     ///< the World's desc is the saved one's: the run continues bit for bit
    OtherSolver = 1,  ///< this World's substeps, solverIterations and strainLimit may differ: the
                      ///< saved state restarted under other solver settings (error studies, a
                      ///< quality preset switched mid-run); everything else must match
};

/// The crowd: characters, the garments they wear, cameras and the frame budget.
///
/// Not thread-safe: call it from one thread. step() runs garments in parallel with OpenMP (or the
/// desc's taskRunner; or the host runs the tasks itself, see beginStep). With
/// the fixed cost model and budgetThreads set, the result is bit for bit the same for any thread
/// count; with learned costs the levels follow the measured times, as a budget must.
///
///   cc::World* world = cc::World::create({}).value();
///   cc::AssetId cape = world->addClothAsset({}).value();
///   cc::BodyId body = world->addMannequinBody({}).value();
///   cc::CharacterDesc c; c.body = body;
///   cc::CharacterId walker = world->addCharacter(c).value();
///   cc::GarmentId g = world->addGarment(cape, walker, {}).value();
///   for (int frame = 0; frame < 600; ++frame) { world->step(1.0 / 60); draw(world->renderMesh(g).value()); }
///   cc::World::destroy(world);
class CC_API World {
public:
    static Result<World*> create(const WorldDesc& desc);
    static void destroy(World* world);

    Result<AssetId> addClothAsset(const ClothAssetDesc& desc);
    /// Hands the scheduler a design's measured errors (cookErrorTable, loadOrCookErrorTable) in
    /// place of its h^2 / (8 foldRadius) formula, for every body the design is fitted to: a level's
    /// predicted error is then the table's error per radius (interpolated in the garment's speed)
    /// times the fitted garment's radius. The table must be measured for this design and this
    /// World's effort (its key); else an error names the mismatch. Cooked data: not in snapshots.
    Status setErrorTable(AssetId design, const ErrorTable& table);
    /// setErrorTable with the design's table for this World's effort from `directory`, cooked and
    /// written there first when it is not cached (loadOrCookErrorTable: about half a minute per
    /// design at the defaults; the cache makes it once per design and effort).
    Status loadErrorTable(AssetId design, const char* directory);
    Result<BodyId> addMannequinBody(const MannequinDesc& desc);
    /// An imported (or generated) character as a body the World skins itself, like the mannequin:
    /// its skeleton is posed by its clips (chosen per character by name or index) and its skin
    /// drives garments and collisions. The character is copied. Fails naming what is wrong with it;
    /// a body that is not a humanoid is accepted (it can be posed and drawn) but garments then fail
    /// with the reason. The character type is declared in crowdcloth/character/Character.h;
    /// crowdcloth/import/CharacterIO.h reads one from any skinned format assimp reads.
    Result<BodyId> addCharacterBody(const Character& character, const BodyDesc& desc = {});
    /// A body the host skins itself: bind-pose vertices (xyz floats, `stride` bytes apart) and
    /// triangles; its characters then take setCharacterSkinnedVertices() every frame.
    Result<BodyId> addSkinnedBody(const float* bindPositions, uint32_t vertexCount, uint32_t strideBytes,
                                  const uint32_t* triangles, uint32_t triangleCount);

    /// Replaces the measured landmarks of a body with the host's, for garments added afterwards.
    Status setBodyLandmarks(BodyId body, const BodyLandmarkDesc& landmarks);
    /// The landmarks garments on this body are fitted to (measured or handed in), with every girth
    /// and width filled in; fails with the reason when the body is not a humanoid.
    Result<BodyLandmarkDesc> bodyLandmarks(BodyId body) const;
    /// Clip names of a body, in index order (empty for the host-skinned bodies).
    Result<uint32_t> bodyClipCount(BodyId body) const;
    Result<const char*> bodyClipName(BodyId body, uint32_t index) const;

    Result<CharacterId> addCharacter(const CharacterDesc& desc);
    Status removeCharacter(CharacterId id);  ///< also removes its garments
    /// Moves a character's root [m] (within 1e7 m of the origin) and heading [rad] for the next
    /// step. Its garments feel the
    /// root's motion (see GarmentDesc::inertiaScale); a move faster than 100 m/s or a turn faster
    /// than four turns a second within one step is a teleport: the garments are carried along.
    Status setCharacterRoot(CharacterId id, const double position[3], double yaw);
    /// Changes how fast a character's clip plays from the next step on [clip seconds per world
    /// second, 0-10]: the clip goes on from where it is, so a walker can slow to a stop (0 holds the
    /// pose) and start again without a jump in its pose.
    Status setCharacterPlaybackRate(CharacterId id, double playbackRate);
    /// Host-skinned bodies: this frame's vertices in world space (xyz floats, `stride` bytes apart).
    Status setCharacterSkinnedVertices(CharacterId id, const float* positions, uint32_t vertexCount,
                                       uint32_t strideBytes);

    Result<GarmentId> addGarment(AssetId asset, CharacterId character, const GarmentDesc& desc);
    Status removeGarment(GarmentId id);
    /// Forces a garment's uniform level from the next step on, as GarmentDesc::forceLevel does
    /// (-1 = scheduled again): a cut-scene's close-up, a reference run, an error study restarting
    /// a saved state at another level. The switch moves the state through the level transfers, as
    /// the scheduler's switches do.
    Status setGarmentLevel(GarmentId id, int32_t forceLevel);

    Status setCameras(const CameraDesc* cameras, uint32_t count);
    Status setFrameBudget(double milliseconds);

    /// Advances the world by dt [s], [1e-6, 0.1]: bodies, schedule, level switches, simulation in
    /// parallel, publishing. A garment whose step fails keeps its last good state and is reported
    /// in its stats; the frame goes on.
    Status step(double dt);

    /// The same step in pieces, for a host that runs its own job system (NvCloth's
    /// begin / simulate chunks / end): the tasks are the ones step(dt) runs, so with the fixed
    /// cost model the result is bit for bit step()'s whoever runs them, on any threads, in any
    /// order (learned costs follow the measured times, here as in step()).
    ///
    ///   world->beginStep(dt);                    // serial: bodies' clocks, the schedule
    ///   do {
    ///       uint32_t n = world->stepTaskCount(); // this phase's tasks
    ///       for each i in [0, n), on any thread: world->runStepTask(i);
    ///       wait until all n have returned;      // a phase's tasks read what the last phase wrote
    ///   } while (world->nextStepPhase());        // serial: forms the next phase's tasks
    ///   world->endStep();                        // serial: totals and stats
    ///
    /// There are two phases today (per garment: level switch, body and contacts; per solver batch:
    /// the simulation); hosts loop until nextStepPhase() returns false. Between beginStep() and
    /// endStep() call only these four (runStepTask concurrently, the others from one thread); the
    /// calls that change or read characters and garments return InvalidOperation meanwhile.
    Status beginStep(double dt);
    uint32_t stepTaskCount() const;
    /// Runs task `index` of the current phase; fails (doing nothing) for an index not below
    /// stepTaskCount() and for a task that has already run in this phase.
    Status runStepTask(uint32_t index);
    /// After every task of the phase has returned: opens the next phase (true) or ends (false).
    /// A task the host left unrun is run here first, so the step stays whole and bit for bit
    /// step()'s; endStep() then reports it.
    bool nextStepPhase();
    /// Ends the step; InvalidOperation (the step nonetheless complete) when tasks were left unrun.
    Status endStep();

    /// The garment's render mesh in world space, valid until the next step() or removal. A
    /// garment not updated this frame is carried to its character's current place here, on
    /// demand (so garments that are not drawn cost nothing); calls for different garments may
    /// run concurrently.
    Result<RenderMeshView> renderMesh(GarmentId id) const;
    /// The character's body skinned at this frame's pose, in world space (skinned on demand, for
    /// drawing and debugging; valid until the next call or step()).
    Result<RenderMeshView> characterMesh(CharacterId id);
    Result<GarmentStats> garmentStats(GarmentId id) const;
    /// The design as cut for this garment's body: width, length and hemWidth filled in.
    Result<ClothAssetDesc> garmentFit(GarmentId id) const;
    const FrameStats& frameStats() const;
    /// The last frame's stats (totals and every garment) as a JSON document.
    std::string statsJson() const;
    /// Bitwise digest of every garment's simulated state, for determinism tests and replays.
    uint64_t stateHash() const;

    /// Turns the shadow check on (desc.garments > 0), changes it, or off; followed garments are
    /// dropped. Not saved in snapshots; a restore drops them.
    Status setShadowCheck(const ShadowCheckDesc& desc);
    /// Windows the last step completed (valid until the next step). A window whose garment was
    /// removed or failed, or whose copies failed, ends without a result.
    const std::vector<ShadowCheckResult>& shadowCheckResults() const;

    /// Everything that carries from one frame to the next, as bytes (a save game, a replay's
    /// checkpoint, a host's rollback): characters and garments with their handles, clocks,
    /// simulated state, levels and schedule, colliders' last poses, cameras, budget and learned
    /// costs. Not the cooked data: assets and bodies are checked by fingerprint, not stored.
    /// The format is versioned and checksummed, in this machine's byte order.
    Result<std::vector<uint8_t>> saveState() const;
    /// Replaces this World's characters and garments (and clocks, cameras, budget, learned costs)
    /// with a snapshot's. The World must have been made with the same WorldDesc (threads and batch
    /// size aside) and have the snapshot's assets and bodies added in the same order; then the run
    /// continues bit for bit as the saved one did (with the fixed cost model), and the snapshot's
    /// handles are valid here (with RestoreMode::OtherSolver the solver settings may differ, and
    /// the run goes on under this World's). A truncated, corrupted, foreign or mismatched snapshot gives an
    /// error naming what is wrong, and the World keeps its state.
    Status restoreState(const void* data, std::size_t size, RestoreMode mode = RestoreMode::Continue);

protected:
    World() = default;
    ~World() = default;
};

} // namespace cc

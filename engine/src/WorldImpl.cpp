#include "WorldImpl.h"
#include "Stopwatch.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "crowdcloth/core/Hash.h"
#include "UpdateStep.h"

#ifdef CC_HAVE_OPENMP
#include <omp.h>
#endif

namespace cc {

Status WorldDesc::validate() const {
    if (!(std::isfinite(frameBudgetMs) && frameBudgetMs > 0.0))
        return Status::invalidArgument("WorldDesc.frameBudgetMs must be > 0");
    if (!(std::isfinite(pixelTolerance) && pixelTolerance > 0.0))
        return Status::invalidArgument("WorldDesc.pixelTolerance must be > 0");
    for (double g : gravity)
        if (!std::isfinite(g)) return Status::invalidArgument("WorldDesc.gravity must be finite");
    if (maxUpdateInterval < 1 || maxUpdateInterval > 64 || (maxUpdateInterval & (maxUpdateInterval - 1)))
        return Status::invalidArgument("WorldDesc.maxUpdateInterval must be a power of two in [1, 64]");
    if (maxThreads > 1024) return Status::invalidArgument("WorldDesc.maxThreads must be <= 1024");
    if (substeps < 1 || substeps > 64) return Status::invalidArgument("WorldDesc.substeps must be in [1, 64]");
    if (solverIterations < 1 || solverIterations > 100)
        return Status::invalidArgument("WorldDesc.solverIterations must be in [1, 100]");
    if (batchSize < 1 || batchSize > uint32_t(cloth::kMaxSubstepLanes))
        return Status::invalidArgument("WorldDesc.batchSize must be in [1, " +
                                       std::to_string(cloth::kMaxSubstepLanes) + "]");
    if (!(std::isfinite(strainLimit) && strainLimit >= 0.0 && strainLimit <= 10.0))
        return Status::invalidArgument("WorldDesc.strainLimit must be in [0, 10]");
    return Status::ok();
}

namespace detail {
namespace {

Status staleHandle(const char* what) {
    return Status::invalidArgument(std::string(what) + " is null, stale or from another world");
}

/// Closed-loop budget, a quantile tracker (stochastic approximation, Robbins & Monro 1951): after a
/// frame within the budget the CPU share grows by this step (as a log), after one over it shrinks
/// by kOverBudgetWeight steps, so at equilibrium one frame in 1 + kOverBudgetWeight exceeds the
/// budget: the budget bounds a frame's p75, not its median. (Tracking the median left the p99 at
/// 1.6x the budget in a 1000-character crowd; tracking the p90 gave no better p99 there and 40 %
/// fewer vertex updates.) The share stays within these bounds.
constexpr double kBudgetStep = 0.004;
constexpr double kOverBudgetWeight = 3.0;
constexpr double kMinBudgetScale = 0.2;
constexpr double kMaxBudgetScale = 1.5;  ///< measured costs may miss what the threads overlap
/// A mesh collider no garment asked for this long [s] goes back to its body's spares (at most
/// kMaxSpareColliders).
constexpr double kColliderIdleSeconds = 1.0;
constexpr std::size_t kPrebuiltColliders = 4;
/// A garment at rest when unseen may sleep: below this kinetic energy per kilogram [J/kg]
/// (~4 mm/s) with a still body.
constexpr double kRestEnergy = 1e-5;
/// [s] the steps a World takes. Below a microsecond the solver's mass term (M / h^2 for substeps
/// of h) leaves double precision (measured: every garment failed at dt = 1e-308), and no host
/// needs it; above 0.1 s a garment would be asked to jump where no substep budget follows.
constexpr double kMinStep = 1e-6, kMaxStep = 0.1;
/// ok, or an error naming `what` and the range (NaN fails the comparison).
Status checkPlaybackRate(const char* what, double rate) {
    if (rate >= 0.0 && rate <= kMaxPlaybackRate) return Status::ok();
    return Status::invalidArgument(std::string(what) + " = " + std::to_string(rate) + " must be in [0, " +
                                   std::to_string(int(kMaxPlaybackRate)) + "]");
}

/// A root moving or turning faster than this in one frame teleported (see setCharacterRoot).
constexpr double kTeleportSpeed = 100.0;          ///< [m/s]
constexpr double kTeleportYawRate = 4.0 * 2.0 * kPi;  ///< [rad/s] four turns a second

} // namespace

WorldImpl::WorldImpl(const WorldDesc& desc, std::unique_ptr<collision::CollisionDevice> device)
    : mDesc(desc), mCostModel(desc.fixedCostModel ? lod::CostModel::Mode::Fixed : lod::CostModel::Mode::Learned),
      mDevice(std::move(device)) {}

Result<WorldImpl*> WorldImpl::create(const WorldDesc& desc) {
    if (Status s = desc.validate(); !s) return s;
    // One Embree device per world, one build thread: its pool must not fight OpenMP's.
    auto device = collision::CollisionDevice::create({});
    if (!device.isOk()) return device.status();
    return new WorldImpl(desc, std::move(device).value());
}

int WorldImpl::threadCount() const {
#ifdef CC_HAVE_OPENMP
    return mDesc.maxThreads > 0 ? int(mDesc.maxThreads) : omp_get_max_threads();
#else
    return mDesc.maxThreads > 0 ? int(mDesc.maxThreads) : int(std::max(1u, std::thread::hardware_concurrency()));
#endif
}

Result<AssetId> WorldImpl::addClothAsset(const ClothAssetDesc& desc) {
    if (Status s = desc.validate(); !s) return s;
    auto record = std::make_unique<DesignRecord>();
    record->desc = desc;
    const auto h = mDesigns.add(std::move(record));
    return AssetId{h.index1, h.generation};
}

Result<BodyId> WorldImpl::addBody(BodyAsset body) {
    auto record = std::make_unique<BodyRecord>();
    record->body = std::make_shared<const BodyAsset>(std::move(body));
    const auto h = mBodies.add(std::move(record));
    return BodyId{h.index1, h.generation};
}

Status WorldImpl::prepareBodyTopology(BodyRecord& body) {
    if (body.topology) return Status::ok();
    auto topology = collision::BodyTopology::build(body.body->mesh().triangles, body.body->mesh().bindPositions);
    if (!topology.isOk()) return Status::invalidArgument("body mesh: " + topology.status().message());
    body.topology = std::move(topology).value();
    // Spare colliders now, while nothing is timed: the first builds of a run are the slowest.
    for (std::size_t k = 0; k < kPrebuiltColliders; ++k) {
        auto made = collision::BodyCollider::create(*mDevice, body.topology, body.body->mesh().bindPositions);
        if (!made.isOk()) return Status::invalidArgument("body mesh: " + made.status().message());
        body.spareColliders.push_back(std::move(made).value());
    }
    return Status::ok();
}

Result<CharacterId> WorldImpl::addCharacter(const CharacterDesc& desc) {
    BodyRecord* body = mBodies.get(desc.body);
    if (!body) return staleHandle("CharacterDesc.body");
    const Vec3 position(desc.position[0], desc.position[1], desc.position[2]);
    if (!isFinite(position) || !std::isfinite(desc.yaw))
        return Status::invalidArgument("CharacterDesc.position and yaw must be finite");
    if (position.cwiseAbs().maxCoeff() > kMaxCoordinate)
        return Status::invalidArgument("CharacterDesc.position beyond " + std::to_string(kMaxCoordinate) + " m");
    if (Status s = checkPlaybackRate("CharacterDesc.playbackRate", desc.playbackRate); !s) return s;
    if (Status s = prepareBodyTopology(*body); !s) return Status::invalidArgument("addCharacter: " + s.message());
    auto c = std::make_unique<CharacterInstance>();
    c->body = body->body;
    c->bodyId = desc.body;
    c->bodyTopology = body->topology;
    if (Status s = resolveClip(*body->body, desc, c->clip, c->clipTime); !s) return s;
    c->playbackRate = desc.playbackRate;
    c->position = c->previousPosition = position;
    c->yaw = c->previousYaw = desc.yaw;
    if (!body->body->hostSkinned) {
        c->pose = CharacterPose(body->body->mannequin.character);
        if (Status s = c->updatePose(); !s) return s;
        // Its capsules now rather than on first need in some frame's step, which then allocates.
        if (auto proxies = c->proxyColliderAt(*mDevice, mTime, 0.0); !proxies.isOk()) return proxies.status();
    } else {
        c->skinnedPositions = body->body->mesh().bindPositions; // until the host hands in a pose
    }
    const auto h = mCharacters.add(std::move(c));
    return CharacterId{h.index1, h.generation};
}

Status WorldImpl::removeCharacter(CharacterId id) {
    CharacterInstance* c = mCharacters.get(id);
    if (!c) return staleHandle("character");
    for (GarmentId g : c->garments) mGarments.remove(g);
    spareMeshCollider(*c);
    mCharacters.remove(id);
    return Status::ok();
}

Status WorldImpl::setCharacterPlaybackRate(CharacterId id, double playbackRate) {
    CharacterInstance* c = mCharacters.get(id);
    if (!c) return staleHandle("character");
    if (Status s = checkPlaybackRate("setCharacterPlaybackRate: playbackRate", playbackRate); !s) return s;
    c->playbackRate = playbackRate;  // clipTime goes on from where it is (step() advances it)
    return Status::ok();
}

Status WorldImpl::setCharacterRoot(CharacterId id, const double position[3], double yaw) {
    CharacterInstance* c = mCharacters.get(id);
    if (!c) return staleHandle("character");
    if (!position) return Status::invalidArgument("setCharacterRoot: position is null");
    const Vec3 p(position[0], position[1], position[2]);
    if (!isFinite(p) || !std::isfinite(yaw))
        return Status::invalidArgument("setCharacterRoot: position and yaw must be finite");
    if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
        return Status::invalidArgument("setCharacterRoot: position beyond " + std::to_string(kMaxCoordinate) +
                                       " m (render meshes are floats: a metre apart there)");
    c->position = p;
    c->yaw = yaw;
    return Status::ok();
}

Status WorldImpl::setCharacterSkinnedVertices(CharacterId id, const float* positions, uint32_t count, uint32_t stride) {
    CharacterInstance* c = mCharacters.get(id);
    if (!c) return staleHandle("character");
    if (!c->body->hostSkinned)
        return Status::error(StatusCode::InvalidOperation,
                             "setCharacterSkinnedVertices: this character's body is skinned by crowdcloth");
    if (count != c->body->mesh().vertexCount())
        return Status::invalidArgument("setCharacterSkinnedVertices: " + std::to_string(count) +
                                       " vertices for a body of " +
                                       std::to_string(c->body->mesh().vertexCount()));
    std::vector<Vec3> world;
    if (Status s = readFloat3(positions, count, stride, "setCharacterSkinnedVertices", world); !s) return s;
    const Mat3 inverse = c->rotation().transpose();
    c->skinnedPositions.resize(count);
    for (uint32_t i = 0; i < count; ++i) c->skinnedPositions[i] = inverse * (world[i] - c->position);
    c->hostVerticesGiven = true;
    c->skinnedCurrent = true;
    return Status::ok();
}

Result<GarmentId> WorldImpl::addGarment(AssetId designId, CharacterId characterId, const GarmentDesc& desc) {
    DesignRecord* design = mDesigns.get(designId);
    if (!design) return staleHandle("asset");
    CharacterInstance* c = mCharacters.get(characterId);
    if (!c) return staleHandle("character");
    auto fitted = fittedAsset(*design, c->body);
    if (!fitted.isOk()) return Status::invalidArgument("addGarment: " + fitted.status().message());
    const AssetId assetId = fitted.value();
    const AssetRecord* asset = mAssets.get(assetId);
    auto g = GarmentInstance::create(asset->asset, assetId.index1, *c, characterId, desc);
    if (!g.isOk()) return g.status();
    g.value()->lastUpdateTime = mTime;
    const auto h = mGarments.add(std::move(g).value());
    const GarmentId id{h.index1, h.generation};
    c->garments.push_back(id);
    return id;
}

Status WorldImpl::removeGarment(GarmentId id) {
    GarmentInstance* g = mGarments.get(id);
    if (!g) return staleHandle("garment");
    if (CharacterInstance* c = mCharacters.get(g->character())) {
        auto& list = c->garments;
        list.erase(std::remove_if(list.begin(), list.end(),
                                  [&](GarmentId x) { return x.index1 == id.index1 && x.generation == id.generation; }),
                   list.end());
    }
    mGarments.remove(id);
    return Status::ok();
}

Status WorldImpl::setGarmentLevel(GarmentId id, int32_t forceLevel) {
    GarmentInstance* g = mGarments.get(id);
    if (!g) return staleHandle("garment");
    return g->setForcedLevel(forceLevel);
}

Status WorldImpl::setCameras(const CameraDesc* cameras, uint32_t count) {
    if (count > 0 && !cameras) return Status::invalidArgument("setCameras: cameras is null");
    // Every camera checked before any is kept (a refused call changes nothing); then copied into
    // the kept vector, which a host moving its camera every frame does not make allocate.
    for (uint32_t c = 0; c < count; ++c) {
        const double* m = cameras[c].viewProjection;
        if (!std::all_of(m, m + 16, [](double v) { return std::isfinite(v); }))
            return Status::invalidArgument("setCameras: camera " + std::to_string(c) + " viewProjection is not finite");
        if (!(cameras[c].viewportWidth > 0.0 && cameras[c].viewportHeight > 0.0 &&
              std::isfinite(cameras[c].viewportWidth) && std::isfinite(cameras[c].viewportHeight)))
            return Status::invalidArgument("setCameras: camera " + std::to_string(c) + " viewport must be > 0 pixels");
    }
    mCameras.resize(count);
    for (uint32_t c = 0; c < count; ++c) {
        for (int k = 0; k < 16; ++k) mCameras[c].viewProjection(k % 4, k / 4) = cameras[c].viewProjection[k];
        mCameras[c].viewportWidth = cameras[c].viewportWidth;
        mCameras[c].viewportHeight = cameras[c].viewportHeight;
    }
    return Status::ok();
}

Status WorldImpl::setFrameBudget(double milliseconds) {
    if (!(std::isfinite(milliseconds) && milliseconds > 0.0))
        return Status::invalidArgument("setFrameBudget: milliseconds must be > 0");
    mDesc.frameBudgetMs = milliseconds;
    return Status::ok();
}

Status WorldImpl::scheduleFrame(double dt) {
    // One profile per asset, costed by the current cost model; the vectors keep their capacity
    // from frame to frame (no allocation after the first frame).
    std::size_t profileCount = 0;
    mAssets.forEach([&](auto handle, const AssetRecord& record) {
        if (handle.index1 >= mProfileOfAsset.size()) mProfileOfAsset.resize(handle.index1 + 1, 0);
        mProfileOfAsset[handle.index1] = uint32_t(profileCount);
        if (profileCount == mProfiles.size()) mProfiles.emplace_back();
        lod::GarmentProfile& profile = mProfiles[profileCount++];
        profile.levels.resize(record.asset->levels.size());
        for (std::size_t l = 0; l < record.asset->levels.size(); ++l) {
            const CookedLevel& level = record.asset->levels[l];
            const std::size_t n = level.active.mesh.vertexCount();
            lod::LevelProfile lp;
            if (record.errors) {  // measured: error per radius at the table's two speeds
                for (uint32_t m = 0; m < ErrorTable::kMotions; ++m) {
                    lp.errorPerRadius[m] = record.errors->error(uint32_t(l), m);
                    lp.errorSpeeds[m] = record.errors->speeds[m];
                }
            } else {
                lp.errorMetres = level.errorMetres;
            }
            const WorldDesc::Effort effort =
                mDesc.effortAt(uint32_t(l), uint32_t(record.asset->levels.size()), dt);
            lp.substeps = int(effort.substeps);
            lp.iterations = int(effort.iterations);
            // The solve with capsules, and what the body mesh adds to it.
            const auto newton = lod::SolverChoice::SubstepNewton;
            auto predict = [&](lod::CollisionDetail detail) {
                return mCostModel.predictMs(handle.index1, int(l), newton, detail, n, lp.substeps, lp.iterations);
            };
            const double solve = predict(lod::CollisionDetail::Proxies);
            lp.costMs[int(newton)] = solve;
            for (auto detail : {lod::CollisionDetail::Mesh, lod::CollisionDetail::MeshContinuous})
                lp.collisionCostMs[int(detail)] = std::max(0.0, predict(detail) - solve);
            // Counted in the budget wherever the scheduler turns it on (a World without it never does).
            lp.selfCollisionCostMs =
                mDesc.selfCollision ? mCostModel.predictSelfCollisionMs(handle.index1, int(l), n)
                                    : 0.0;
            profile.levels[l] = lp;
        }
    });
    mProfiles.resize(profileCount);

    mRequests.resize(mItems.size());
    mSchedules.resize(mItems.size());
    for (std::size_t i = 0; i < mItems.size(); ++i) {
        const GarmentRef& item = mItems[i];
        lod::GarmentRequest& r = mRequests[i];
        r.id = item.id.index1;
        r.profile = mProfileOfAsset[item.garment->assetIndex()];
        r.center = item.character->toWorld(item.garment->localCentre());
        r.radius = item.garment->asset().radius;
        // The lag of an extrapolated frame grows with the body's speed and the cloth's own swing.
        r.speed = item.character->speed + std::sqrt(2.0 * item.garment->specificKineticEnergy());
        r.importance = item.garment->importance();
        r.atRest = item.character->speed < 1e-3 && item.garment->specificKineticEnergy() < kRestEnergy;
        r.previous = item.garment->schedule;
    }
    lod::SchedulerSettings settings;
    settings.budgetMs = mDesc.frameBudgetMs * (mDesc.budgetThreads > 0 ? mDesc.budgetThreads : threadCount()) *
                        mBudgetScale;
    settings.pixelTolerance = mDesc.pixelTolerance;
    settings.frameDt = dt;
    settings.maxUpdateInterval = int(mDesc.maxUpdateInterval);
    settings.refineWithSlack = mDesc.spendSlack;
    if (Status s = lod::scheduleGarments(settings, mCameras, mProfiles, mRequests, mSchedules, mSchedulerWork); !s)
        return s;
    mFrameStats.budgetCpuMs = settings.budgetMs;
    for (std::size_t i = 0; i < mItems.size(); ++i) {
        lod::GarmentSchedule& s = mSchedules[i];
        if (const int forced = mItems[i].garment->forcedLevel(); forced >= 0) {
            const auto& levels = mProfiles[mRequests[i].profile].levels;
            s.level = forced;
            s.updateInterval = 1;
            s.substeps = levels[forced].substeps;
            s.iterations = levels[forced].iterations;
            // Self-collision by the forced level, not the one the scheduler would have chosen.
            s.selfCollision = lod::wantsSelfCollision(
                s, forced, int(levels.size()), mRequests[i].previous.selfCollision, settings);
        }
        mItems[i].garment->schedule = s;
    }
    return Status::ok();
}

template <typename Task>
void WorldImpl::runTasks(std::size_t count, Task& task) {
    if (mDesc.taskRunner) {
        mDesc.taskRunner(mDesc.taskRunnerUserData, uint32_t(count),
                         [](void* context, uint32_t index) { (*static_cast<Task*>(context))(index); }, &task);
    } else {
        if (!mPool) mPool = std::make_unique<TaskPool>(unsigned(threadCount()));  // on first need
        mPool->run(uint32_t(count), [](void* context, uint32_t index) { (*static_cast<Task*>(context))(index); },
                   &task);
    }
}

void WorldImpl::fail(GarmentInstance& g, const Status& status) {
    g.stats.failed = true;
    g.lastError = status.message();
}

void WorldImpl::prepareGarment(const GarmentRef& item) {
    const auto start = Clock::now();
    GarmentInstance& g = *item.garment;
    GarmentStats& stats = g.stats;
    stats.levelSwitched = g.switchLevel(g.schedule.level);
    const lod::GarmentSchedule& schedule = g.schedule;
    g.context.collider = nullptr;
    g.context.continuous = schedule.collision == lod::CollisionDetail::MeshContinuous;
    g.context.proxies = schedule.collision == lod::CollisionDetail::Proxies && !item.character->body->hostSkinned;
    g.context.selfCollision = schedule.selfCollision && mDesc.selfCollision;
    g.context.strainLimit = mDesc.strainLimit;
    Status status;
    if (schedule.collision != lod::CollisionDetail::None) {
        auto collider = schedule.collision == lod::CollisionDetail::Proxies
                            ? item.character->proxyColliderAt(*mDevice, mTime, g.context.dt)
                            : item.character->meshColliderAt(*mDevice, mTime, g.context.dt);
        status = collider.status();
        if (collider.isOk()) g.context.collider = collider.value();
    }
    GarmentUpdateReport report;
    if (status) status = g.prepare(*item.character, *mUpdateScratch.borrow(), report);
    stats.contacts = report.contacts;
    stats.restarted = report.restarted;
    stats.collisionMs = report.collisionMs;
    stats.selfCollisionMs = report.selfCollisionMs;
    if (!status) fail(g, status);
    stats.measuredMs = msSince(start);
}

void WorldImpl::simulateBatch(Batch& batch) {
    const auto start = Clock::now();
    batch.lanes.clear();
    batch.reports.resize(batch.items.size());
    for (std::size_t item : batch.items) batch.lanes.push_back(mItems[item].garment->lane());
    const Status status = cloth::stepSubsteps(*batch.level->cloth, *batch.factor, batch.dt, batch.settings,
                                              batch.lanes, *mWorkspaces.borrow(), batch.reports);
    // The shared solve's time, split evenly: what each garment costs inside a batch.
    const double share = msSince(start) / double(batch.items.size());
    for (std::size_t k = 0; k < batch.items.size(); ++k) {
        const GarmentRef& item = mItems[batch.items[k]];
        GarmentInstance& g = *item.garment;
        const auto own = Clock::now();
        Status result = status ? batch.reports[k].status : status;
        GarmentUpdateReport report;
        report.collisionMs = g.stats.collisionMs;
        report.selfCollisionMs = g.stats.selfCollisionMs;
        if (result) result = g.finish(*item.character, batch.settings, *mUpdateScratch.borrow(), report);
        if (!result) fail(g, result);
        g.stats.collisionMs = report.collisionMs;
        g.stats.selfCollisionMs = report.selfCollisionMs;
        g.stats.failSafes = report.failSafes;
        g.stats.restarted = g.stats.restarted || report.restarted;
        g.stats.substeps = uint32_t(batch.settings.substeps);
        g.stats.iterations = uint32_t(batch.settings.substeps * batch.settings.iterations);
        g.lastUpdateTime = mTime - g.context.carried;
        // Measured here, in parallel: a serial pass over a large crowd's updates costs a millisecond.
        g.stats.maxStrain = g.maxEdgeStrain();
        g.stats.maxAttachmentError = g.attachmentError();
        g.stats.measuredMs += share + msSince(own);
    }
}

Status WorldImpl::step(double dt) {
    if (Status s = beginStep(dt); !s) return s;
    do {
        auto task = [&](uint32_t index) { (void)runStepTask(index); };
        runTasks(stepTaskCount(), task);
    } while (nextStepPhase());
    return endStep();
}

Status WorldImpl::beginStep(double dt) {
    if (mStepPhase != StepPhase::Idle)
        return Status::error(StatusCode::InvalidOperation,
                             "step: the previous step is still open (endStep() not called)");
    if (!(dt >= kMinStep && dt <= kMaxStep)) return Status::invalidArgument("step: dt must be in [1e-6, 0.1] s");
    mFrameStart = Clock::now();
    FrameStats& fs = mFrameStats;
    fs = FrameStats{fs.frame + 1};
    fs.threads = uint32_t(threadCount());

    Status missing;
    mCharacters.forEach([&](auto, const CharacterInstance& c) {
        if (missing && c.body->hostSkinned && !c.hostVerticesGiven && !c.garments.empty())
            missing = Status::error(StatusCode::InvalidOperation,
                                    "step: a host-skinned character has garments but no setCharacterSkinnedVertices() "
                                    "this frame");
    });
    if (!missing) return missing;
    mTime += dt;
    mStepDt = dt;
    mCharacters.forEach([&](auto, CharacterInstance& c) {
        c.clipTime += dt * c.playbackRate;
        c.speed = (c.position - c.previousPosition).norm() / dt;
        // The root's motion drives the cloth's inertial forces; a jump faster than any body moves
        // is a teleport (a cut, a respawn): the cloth is carried along and feels nothing.
        const Vec3 velocity = (c.position - c.previousPosition) / dt;
        const double yawRate = std::remainder(c.yaw - c.previousYaw, 2.0 * kPi) / dt;
        if (velocity.norm() <= kTeleportSpeed && std::abs(yawRate) <= kTeleportYawRate) {
            c.velocity = velocity;
            c.yawRate = yawRate;
        }
        // A character's first motion is how it was spawned (placed, then walking), not a push:
        // its garments start from that motion rather than from rest.
        if (!c.motionKnown) {
            c.motionKnown = true;
            for (GarmentId id : c.garments) {
                if (GarmentInstance* g = mGarments.get(id)) {
                    g->lastRootVelocity = c.velocity;
                    g->lastYawRate = c.yawRate;
                }
            }
        }
        c.previousPosition = c.position;
        c.previousYaw = c.yaw;
        c.poseCurrent = false;
        if (!c.body->hostSkinned) c.skinnedCurrent = false;
    });
    mItems.clear();
    mGarments.forEach([&](auto h, GarmentInstance& g) {
        mItems.push_back({GarmentId{h.index1, h.generation}, &g, mCharacters.get(g.character())});
    });

    // 1. Schedule: it needs only bounding spheres, and it decides which bodies must be posed.
    auto phase = Clock::now();
    if (Status s = scheduleFrame(dt); !s) return s;
    fs.scheduleMs = msSince(phase);

    mUpdates.clear();
    const Vec3 gravity(mDesc.gravity[0], mDesc.gravity[1], mDesc.gravity[2]);
    for (std::size_t i = 0; i < mItems.size(); ++i) {
        GarmentInstance& g = *mItems[i].garment;
        g.advanceFrame();  // before any switch this frame, which starts its fade at full
        g.stats = GarmentStats{};
        const int interval = g.schedule.updateInterval;
        // Spread garments at the same rate over the frames (by id) so the load stays even.
        g.stats.updated = interval > 0 && (fs.frame + mItems[i].id.index1) % uint64_t(interval) == 0;
        if (g.stats.updated) {
            // The step is snapped to a grid of sizes (updateStep) so that garments share factors
            // whatever the frame times; the difference is carried to the next update.
            const double elapsed = std::clamp(mTime - g.lastUpdateTime, dt, dt * mDesc.maxUpdateInterval);
            g.context.dt = updateStep(elapsed, dt);
            g.context.carried = elapsed - g.context.dt;
            setInertialForces(g, *mItems[i].character, gravity, mTime - g.lastUpdateTime, dt * mDesc.maxUpdateInterval);
            mUpdates.push_back(i);
        }
    }
    recycleMeshColliders();
    mStepPhase = StepPhase::Prepare;
    mTasksSkipped = 0;
    openPhaseTasks();
    mPhaseStart = Clock::now();
    return Status::ok();
}

void WorldImpl::openPhaseTasks() {
    const uint32_t count = stepTaskCount();
    if (count > mTaskRanCapacity) {  // grows to the largest phase, then stays
        mTaskRanCapacity = std::max(count, 2 * mTaskRanCapacity);
        mTaskRan = std::make_unique<std::atomic<uint8_t>[]>(mTaskRanCapacity);
    }
    for (uint32_t i = 0; i < count; ++i) mTaskRan[i].store(0, std::memory_order_relaxed);
}

void WorldImpl::runSkippedTasks() {
    // The host has waited for its tasks (the contract), so their flags are visible here.
    for (uint32_t i = 0, count = stepTaskCount(); i < count; ++i)
        if (mTaskRan[i].load(std::memory_order_relaxed) == 0) {
            (void)runStepTask(i);
            ++mTasksSkipped;
        }
}

void WorldImpl::spareMeshCollider(CharacterInstance& c) {
    auto collider = c.takeMeshCollider();
    BodyRecord* record = mBodies.get(c.bodyId);
    if (collider && record && record->spareColliders.size() < kMaxSpareColliders)
        record->spareColliders.push_back(std::move(collider));
}

void WorldImpl::recycleMeshColliders() {
    mCharacters.forEach([&](auto, CharacterInstance& c) {
        if (c.meshColliderIdle(mTime, kColliderIdleSeconds)) spareMeshCollider(c);
    });
    auto needsBuild = [&](std::size_t i) {
        const GarmentInstance& g = *mItems[i].garment;
        const CharacterInstance& c = *mItems[i].character;
        const lod::CollisionDetail detail = g.schedule.collision;
        const bool mesh = detail != lod::CollisionDetail::None &&
                          (detail != lod::CollisionDetail::Proxies || c.body->hostSkinned);
        return mesh && !c.meshCollider;
    };
    // A new collider costs 7-20 ms (Embree's first build of fresh scenes), a spare's reset 0.5.
    // Without a spare, the character's garments keep their capsules this frame and one collider
    // a frame is built beside the solver batches (a task of the Simulate phase), ready for the
    // next. Host-skinned bodies have no capsules: theirs are built when needed; so is one whose
    // deferred build failed (its garments then report the error).
    mColliderBuilds.clear();
    for (std::size_t i : mUpdates) {
        if (!needsBuild(i)) continue;
        CharacterInstance& c = *mItems[i].character;
        BodyRecord* record = mBodies.get(c.bodyId);
        if (record && !record->spareColliders.empty()) {
            c.adoptMeshCollider(std::move(record->spareColliders.back()));
            record->spareColliders.pop_back();
        } else if (!c.body->hostSkinned && !c.meshColliderBuildFailed) {
            mItems[i].garment->schedule.collision = lod::CollisionDetail::Proxies;
            if (mColliderBuilds.empty()) mColliderBuilds.push_back(&c);
        }
    }
    // A build left in this phase is its longest task: started first, the other threads work
    // meanwhile. (In place: there are few, and std::stable_partition would allocate.)
    std::size_t first = 0;
    for (std::size_t j = 0; j < mUpdates.size(); ++j)
        if (needsBuild(mUpdates[j]))
            std::rotate(mUpdates.begin() + first++, mUpdates.begin() + j, mUpdates.begin() + j + 1);
}

void WorldImpl::buildMeshCollider(CharacterInstance& c) {
    // Its garments use their capsules this frame: the collider is only made, at this frame's pose.
    c.meshColliderBuildFailed = !c.meshColliderAt(*mDevice, mTime, 0.0).isOk();
}

uint32_t WorldImpl::stepTaskCount() const {
    switch (mStepPhase) {
    case StepPhase::Prepare: return uint32_t(mUpdates.size());
    case StepPhase::Simulate: return uint32_t(mColliderBuilds.size() + mBatchCount);
    default: return 0;
    }
}

Status WorldImpl::runStepTask(uint32_t index) {
    if (index >= stepTaskCount())
        return Status::invalidArgument(
            "runStepTask: index " + std::to_string(index) +
            " is not below stepTaskCount() = " + std::to_string(stepTaskCount()));
    if (mTaskRan[index].exchange(1, std::memory_order_relaxed) != 0)
        return Status::error(StatusCode::InvalidOperation,
                             "runStepTask: task " + std::to_string(index) + " of this phase has already run");
    if (mStepPhase == StepPhase::Prepare) {
        // 2. Bodies and contacts, in parallel over the updating garments: the first garment of a
        //    character poses (and skins and refits) its body once; each then switches level and
        //    gathers its attachment targets and contact planes.
        prepareGarment(mItems[mUpdates[index]]);
    } else {
        // 4. Simulate, in parallel over batches (see nextStepPhase).
        // Collider builds first: the longest tasks, overlapped by the batches on the other threads.
        if (index < mColliderBuilds.size())
            buildMeshCollider(*mColliderBuilds[index]);
        else
            simulateBatch(mBatches[index - mColliderBuilds.size()]);
    }
    return Status::ok();
}

bool WorldImpl::nextStepPhase() {
    runSkippedTasks();
    if (mStepPhase != StepPhase::Prepare) {
        if (mStepPhase == StepPhase::Simulate) mStepPhase = StepPhase::Finish;
        return false;
    }
    FrameStats& fs = mFrameStats;
    // 3. Batches: garments of one asset, level, substep size and settings step together, in id
    //    order, at most kMaxSubstepLanes at a time (a garment's result does not depend on its
    //    batch). Factors are built here, serially, on first need.
    using Key = BatchKey;
    std::vector<Key>& keys = mBatchKeys;
    keys.clear();
    for (std::size_t i : mUpdates) {
        const GarmentInstance& g = *mItems[i].garment;
        if (g.stats.failed) continue;
        const int substeps = std::max(1, g.schedule.substeps);
        keys.push_back({g.assetIndex(), g.level(), g.context.dt / double(substeps), substeps,
                        std::max(1, g.schedule.iterations), g.compressionStiffness(), i});
    }
    auto sameBatch = [](const Key& a, const Key& b) {
        return a.asset == b.asset && a.level == b.level && a.substep == b.substep &&
               a.substeps == b.substeps && a.iterations == b.iterations &&
               a.compression == b.compression;
    };
    std::sort(keys.begin(), keys.end(), [&](const Key& a, const Key& b) {
        if (a.asset != b.asset) return a.asset < b.asset;
        if (a.level != b.level) return a.level < b.level;
        if (a.substep != b.substep) return a.substep < b.substep;
        if (a.substeps != b.substeps) return a.substeps < b.substeps;
        if (a.iterations != b.iterations) return a.iterations < b.iterations;
        if (a.compression != b.compression) return a.compression < b.compression;
        return mItems[a.item].id.index1 < mItems[b.item].id.index1;
    });
    mBatchCount = 0;
    for (std::size_t k = 0; k < keys.size();) {
        GarmentInstance& g = *mItems[keys[k].item].garment;
        auto factor = mFactors.get(g, g.schedule.level, keys[k].substep, mFrameStats.frame);
        std::size_t end = k + 1;
        while (end < keys.size() && sameBatch(keys[end], keys[k])) ++end;
        if (!factor.isOk()) {
            for (std::size_t j = k; j < end; ++j) fail(*mItems[keys[j].item].garment, factor.status());
            k = end;
            continue;
        }
        for (; k < end; k = std::min<std::size_t>(end, k + mDesc.batchSize)) {
            if (mBatchCount == mBatches.size()) mBatches.emplace_back();
            Batch& batch = mBatches[mBatchCount++];
            batch.level = &g.cookedLevel();
            batch.factor = factor.value();
            batch.dt = g.context.dt;
            batch.settings = g.solverSettings(keys[k].substeps, keys[k].iterations, mDesc.strainLimit);
            batch.items.clear();
            for (std::size_t j = k; j < std::min<std::size_t>(end, k + mDesc.batchSize); ++j)
                batch.items.push_back(keys[j].item);
        }
    }
    fs.batches = uint32_t(mBatchCount);

    // 4. Simulate, in parallel over batches (runStepTask). Render meshes are built by renderMesh()
    //    when the host asks (most garments of a large crowd are not drawn every frame; those that
    //    are can be asked for from several threads).
    mStepPhase = StepPhase::Simulate;
    openPhaseTasks();
    return true;
}

Status WorldImpl::endStep() {
    if (mStepPhase != StepPhase::Finish)
        return Status::error(StatusCode::InvalidOperation,
                             mStepPhase == StepPhase::Idle
                                 ? "endStep: no step begun (beginStep() first)"
                                 : "endStep: a phase's tasks are still to run (nextStepPhase() "
                                   "returns false after the last)");
    mStepPhase = StepPhase::Idle;
    FrameStats& fs = mFrameStats;
    // A garment whose update failed keeps its state; its render mesh still follows the body.
    for (std::size_t i : mUpdates) {
        GarmentInstance& g = *mItems[i].garment;
        if (!g.stats.failed) continue;
        g.lastUpdateTime = mTime;
    }
    fs.simulateMs = msSince(mPhaseStart);

    // 5. Totals and learning, in item order so the sums are the same for any thread count.
    for (const GarmentRef& item : mItems) {
        GarmentInstance& g = *item.garment;
        GarmentStats& s = g.stats;
        const lod::GarmentSchedule& sc = g.schedule;
        s.level = g.level();
        s.vertexCount = g.vertexCount();
        s.solver = SolverKind(sc.solver);
        s.updateInterval = uint32_t(sc.updateInterval);
        s.collision = CollisionKind(sc.collision);
        s.selfCollision = sc.selfCollision && mDesc.selfCollision;
        s.screenRadiusPx = sc.screenRadiusPx;
        s.predictedErrorPx = sc.predictedErrorPx;
        s.predictedMs = sc.updateInterval > 0 ? sc.predictedCostMs * sc.updateInterval : 0.0;
        if (s.updated) {
            if (!s.failed && !s.levelSwitched && !item.character->meshColliderRebuiltAt(mTime)) {
                // Self-collision learned apart: only garments seen large take it, and it costs 1-4
                // solves, which would inflate every other update of the level's entry.
                mCostModel.record(g.assetIndex(), g.level(), sc.solver, sc.collision, s.measuredMs - s.selfCollisionMs);
                if (s.selfCollision) mCostModel.recordSelfCollision(g.assetIndex(), g.level(), s.selfCollisionMs);
            }
            ++fs.updated;
            fs.predictedCpuMs += s.predictedMs;
            fs.measuredCpuMs += s.measuredMs;
        }
        ++fs.garments;
        fs.asleep += sc.updateInterval == 0;
        fs.visible += sc.visible;
        fs.failed += s.failed;
        fs.levelSwitches += s.levelSwitched;
        if (s.level >= 0 && s.level < 16) ++fs.garmentsPerLevel[s.level];
    }
    mCharacters.forEach([&](auto, CharacterInstance& c) {
        if (c.body->hostSkinned) c.hostVerticesGiven = c.skinnedCurrent = false; // needed again next frame
    });
    mFactors.sweep(fs.frame);  // factors of a level or step size the crowd left go
    fs.totalMs = msSince(mFrameStart);
    // With learned costs the budget is closed-loop: what the garment costs do not show (the
    // schedule, the serial parts, threads waiting on each other or on a busy machine) is found by
    // comparing the frame's wall time with the budget, and the CPU budget the scheduler hands out
    // follows, a little each frame. The fixed cost model stays open-loop: it must not depend on
    // timing.
    if (!mDesc.fixedCostModel && fs.totalMs > 0.0) {
        const double step = fs.totalMs <= mDesc.frameBudgetMs ? kBudgetStep : -kOverBudgetWeight * kBudgetStep;
        mBudgetScale = std::clamp(mBudgetScale * std::exp(step), kMinBudgetScale, kMaxBudgetScale);
    }
    // 6. The shadow check, after the frame's time is taken: a measurement, not part of the frame.
    if (mShadow.enabled()) {
        ShadowFrame frame;
        frame.time = mTime;
        frame.dt = mStepDt;
        frame.longestStep = mStepDt * mDesc.maxUpdateInterval;
        frame.gravity = Vec3(mDesc.gravity[0], mDesc.gravity[1], mDesc.gravity[2]);
        frame.strainLimit = mDesc.strainLimit;
        frame.selfCollision = mDesc.selfCollision;
        frame.device = mDevice.get();
        frame.factors = &mFactors;
        frame.frame = fs.frame;
        frame.cameras = Span<const lod::SchedulerCamera>(mCameras.data(), mCameras.size());
        mShadow.step(frame, Span<const GarmentRef>(mItems.data(), mItems.size()));
    }
    if (mTasksSkipped > 0)
        return Status::error(StatusCode::InvalidOperation,
                             "endStep: the step is complete, but " + std::to_string(mTasksSkipped) +
                                 " of its tasks were left unrun by the host and run by nextStepPhase(); run every "
                                 "index below stepTaskCount() in each phase");
    return Status::ok();
}

Result<RenderMeshView> WorldImpl::renderMesh(GarmentId id) const {
    GarmentInstance* g = mGarments.get(id);
    if (!g) return staleHandle("garment");
    // Render meshes are built when the host asks: a garment nobody draws costs nothing.
    if (const CharacterInstance* c = mCharacters.get(g->character())) g->publish(*c);
    return g->renderView();
}

Result<GarmentStats> WorldImpl::garmentStats(GarmentId id) const {
    const GarmentInstance* g = mGarments.get(id);
    if (!g) return staleHandle("garment");
    return g->stats;
}

Result<RenderMeshView> WorldImpl::characterMesh(CharacterId id) {
    CharacterInstance* c = mCharacters.get(id);
    if (!c) return staleHandle("character");
    if (!c->body->hostSkinned) // a host-skinned body shows the vertices last handed in
        if (Status s = c->updateSkin(); !s) return s;
    const SkinnedMesh& mesh = c->body->mesh();
    const std::size_t n = c->skinnedPositions.size();
    c->drawPositions.resize(3 * n);
    c->drawNormals.assign(3 * n, 0.0f);
    std::vector<Vec3> normals(n, Vec3::Zero());
    for (const auto& t : mesh.triangles) {
        const Vec3 areaNormal = (c->skinnedPositions[t[1]] - c->skinnedPositions[t[0]])
                                    .cross(c->skinnedPositions[t[2]] - c->skinnedPositions[t[0]]);
        for (uint32_t v : t) normals[v] += areaNormal;
    }
    const Mat3 rotation = c->rotation();
    for (std::size_t v = 0; v < n; ++v) {
        const Vec3 p = c->toWorld(c->skinnedPositions[v]);
        const Vec3 nrm = rotation * normals[v].normalized();
        for (int k = 0; k < 3; ++k)
            c->drawPositions[3 * v + k] = float(p[k]), c->drawNormals[3 * v + k] = float(nrm[k]);
    }
    if (c->drawIndices.empty())
        for (const auto& t : mesh.triangles) c->drawIndices.insert(c->drawIndices.end(), t.begin(), t.end());
    RenderMeshView view;
    view.positions = c->drawPositions.data();
    view.normals = c->drawNormals.data();
    view.vertexCount = uint32_t(n);
    view.indices = c->drawIndices.data();
    view.triangleCount = uint32_t(mesh.triangles.size());
    return view;
}

uint64_t WorldImpl::stateHash() const {
    uint64_t h = kHashSeed;
    mGarments.forEach([&](auto handle, const GarmentInstance& g) {
        const uint64_t parts[3] = {handle.index1, uint64_t(g.level()), g.hash()};
        h = hashBytes(parts, sizeof(parts), h);
    });
    return h;
}

} // namespace detail
} // namespace cc

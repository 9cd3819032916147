// World snapshots: the instance layer (characters, garments, clocks, schedule, colliders' last
// poses, learned costs) as versioned, checksummed bytes; the cooked layer (assets, bodies) is
// checked by fingerprint and must be added to the restoring World as it was to the saving one
// (as Jolt's StateRecorder restores bodies into a PhysicsSystem that already holds them).

#include <array>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "CApiFields.h"
#include "SnapshotStream.h"
#include "WorldImpl.h"
#include "crowdcloth/core/Hash.h"

namespace cc::detail {
namespace {

constexpr char kMagic[8] = {'C', 'C', 'W', 'O', 'R', 'L', 'D', '\x1a'};  // 0x1a: text-mode copies break it
/// Bump on any change to what is written; a snapshot of another version is refused by name.
constexpr uint32_t kFormatVersion = 4;
constexpr uint32_t kByteOrderMark = 0x01020304u;
constexpr std::size_t kHeaderBytes = kSnapshotHeaderBytes;

template <typename T>
void putField(SnapshotWriter& w, const T& v) {
    if constexpr (std::is_array_v<T>) {
        for (const auto& e : v) putField(w, e);
    } else if constexpr (std::is_same_v<T, bool>) {
        w.put(uint8_t(v));
    } else {
        w.put(v);
    }
}

template <typename T>
void getField(SnapshotReader& r, T& v) {
    if constexpr (std::is_array_v<T>) {
        for (auto& e : v) getField(r, e);
    } else if constexpr (std::is_same_v<T, bool>) {
        v = r.get<uint8_t>() != 0;
    } else {
        v = r.get<T>();
    }
}

#define CC_SNAPSHOT_PUT(c, cpp) putField(w, x.cpp);
#define CC_SNAPSHOT_GET(c, cpp) getField(r, x.cpp);

/// The WorldDesc fields a run's results depend on (threads, batch size and the task runner do not).
std::vector<std::pair<const char*, double>> resultFields(const WorldDesc& d) {
    return {{"budgetThreads", double(d.budgetThreads)},     {"pixelTolerance", d.pixelTolerance},
            {"fixedCostModel", double(d.fixedCostModel)},   {"gravity[0]", d.gravity[0]},
            {"gravity[1]", d.gravity[1]},                   {"gravity[2]", d.gravity[2]},
            {"maxUpdateInterval", double(d.maxUpdateInterval)}, {"substeps", double(d.substeps)},
            {"solverIterations", double(d.solverIterations)},   {"strainLimit", d.strainLimit},
            {"selfCollision", double(d.selfCollision)},     {"spendSlack", double(d.spendSlack)}};
}

/// The fields RestoreMode::OtherSolver lets differ: how the state is stepped, not what it is.
bool isSolverField(const char* name) {
    return std::strcmp(name, "substeps") == 0 || std::strcmp(name, "solverIterations") == 0 ||
           std::strcmp(name, "strainLimit") == 0;
}

uint64_t fingerprint(SnapshotWriter& w) { return hashBytes(w.bytes().data(), w.bytes().size()); }

} // namespace

uint64_t designFingerprint(const ClothAssetDesc& x) {
    SnapshotWriter w;
    CC_ASSET_FIELDS(CC_SNAPSHOT_PUT)
    return fingerprint(w);
}

namespace {

/// The body's mesh, skeleton size, clips and the landmarks garments are fitted to.
uint64_t bodyFingerprint(const BodyAsset& body) {
    SnapshotWriter w;
    w.put(uint8_t(body.hostSkinned));
    w.putVector(body.mesh().bindPositions);
    w.put(uint64_t(body.mesh().triangles.size()));
    for (const auto& t : body.mesh().triangles) w.put(t[0]), w.put(t[1]), w.put(t[2]);
    w.put(uint64_t(body.character().skeleton.jointCount()));
    w.put(uint64_t(body.character().clips.size()));
    for (const AnimationClip& clip : body.character().clips) w.put(clip.name), w.put(clip.duration);
    w.put(uint8_t(body.fitStatus.isOk()));
    if (body.fitStatus.isOk()) {
        const BodyLandmarkDesc x = landmarksOf(body);
        CC_LANDMARK_FIELDS(CC_SNAPSHOT_PUT)
    }
    return fingerprint(w);
}

void putSchedule(SnapshotWriter& w, const lod::GarmentSchedule& s) {
    w.put(int32_t(s.level)), w.put(uint8_t(s.solver)), w.put(int32_t(s.substeps)), w.put(int32_t(s.iterations));
    w.put(uint8_t(s.collision)), w.put(uint8_t(s.selfCollision)), w.put(int32_t(s.updateInterval));
    w.put(uint8_t(s.visible)), w.put(s.screenRadiusPx), w.put(s.predictedErrorPx), w.put(s.predictedCostMs);
}

lod::GarmentSchedule getSchedule(SnapshotReader& r, int levelCount) {
    lod::GarmentSchedule s;
    s.level = r.get<int32_t>();
    const uint8_t solver = r.get<uint8_t>();
    s.substeps = r.get<int32_t>();
    s.iterations = r.get<int32_t>();
    const uint8_t collision = r.get<uint8_t>();
    s.selfCollision = r.get<uint8_t>() != 0;
    s.updateInterval = r.get<int32_t>();
    s.visible = r.get<uint8_t>() != 0;
    s.screenRadiusPx = r.get<double>();
    s.predictedErrorPx = r.get<double>();
    s.predictedCostMs = r.get<double>();
    const bool interval = s.updateInterval >= 0 && s.updateInterval <= 64 && (s.updateInterval & (s.updateInterval - 1)) == 0;
    if (r.ok() && !(s.level >= -1 && s.level < levelCount && solver < lod::kSolverChoiceCount &&
                    collision < lod::kCollisionDetailCount && s.substeps >= 1 && s.substeps <= 64 &&
                    s.iterations >= 1 && s.iterations <= 1000 && interval))
        r.fail("a garment's schedule is out of range");
    s.solver = lod::SolverChoice(solver);
    s.collision = lod::CollisionDetail(collision);
    return s;
}

/// A handle pool's layout: every slot's generation and the free slots in reuse order.
template <typename T>
void putLayout(SnapshotWriter& w, const HandlePool<T>& pool) {
    std::vector<uint32_t> generations(pool.slotCount());
    for (uint32_t i = 0; i < pool.slotCount(); ++i) generations[i] = pool.generationAt(i);
    w.putVector(generations);
    w.putVector(pool.freeSlots());
}

template <typename T>
uint32_t getLayout(SnapshotReader& r, HandlePool<T>& pool) {
    const auto generations = r.getVector<uint32_t>();
    const auto free = r.getVector<uint32_t>();
    if (r.ok() && !pool.resetLayout(generations, free)) r.fail("the free slots repeat or lie out of range");
    return r.ok() ? uint32_t(generations.size() - free.size()) : 0u;
}

Status refused(const std::string& why) { return Status::invalidArgument("restoreState: " + why); }

/// Reads a pool written as its layout, then per live slot the slot's index and what `make(slot)`
/// reads (the object, or an error that refuses the snapshot; a reader failure stays in `r`).
template <typename T, typename Make>
Status readPool(SnapshotReader& r, HandlePool<T>& pool, const char* what, Make&& make) {
    const uint32_t live = getLayout(r, pool);
    for (uint32_t k = 0; k < live; ++k) {
        const uint32_t slot = r.get<uint32_t>();
        if (!r.ok()) break;
        Result<std::unique_ptr<T>> made = make(slot);
        if (!made.isOk()) return made.status();
        if (!r.ok()) break;
        if (!pool.put(slot, std::move(made).value())) r.fail(std::string(what) + "'s slot is free or taken twice");
    }
    if (r.ok() && !pool.complete()) r.fail(std::string(what) + " is missing");
    return Status::ok();
}

} // namespace

void CharacterInstance::saveState(SnapshotWriter& w) const {
    w.put(int32_t(clip)), w.put(clipTime), w.put(playbackRate);
    w.put(position), w.put(yaw), w.put(previousPosition), w.put(previousYaw);
    w.put(speed), w.put(velocity), w.put(yawRate), w.put(uint8_t(motionKnown));
    w.put(uint64_t(garments.size()));
    for (GarmentId g : garments) w.put(g.index1), w.put(g.generation);
    if (body->hostSkinned) w.putVector(skinnedPositions);  // the last vertices the host handed in
    // The colliders' last poses: the next update sweeps the body from there.
    w.put(uint8_t(meshCollider != nullptr));
    if (meshCollider) {
        const Span<const Vec3> current = meshCollider->currentPositions();
        w.putVector(std::vector<Vec3>(current.begin(), current.end()));
        w.put(mMeshColliderTime), w.put(mMeshColliderRebuilt);
    }
    w.put(uint8_t(meshColliderBuildFailed));
    w.put(uint8_t(proxyColliderMade));
    if (proxyColliderMade) {
        w.put(uint64_t(proxyCollider.capsuleCount()));
        for (const collision::Capsule& c : proxyCollider.current()) w.put(c.a), w.put(c.b), w.put(c.radius);
        w.put(mProxyColliderTime);
    }
}

Status CharacterInstance::restoreState(SnapshotReader& r, collision::CollisionDevice& device) {
    clip = r.get<int32_t>();
    clipTime = r.getFinite("clipTime");
    playbackRate = r.getFinite("playbackRate");
    position = r.getFiniteVec3("position");
    yaw = r.getFinite("yaw");
    previousPosition = r.getFiniteVec3("previousPosition");
    previousYaw = r.getFinite("previousYaw");
    speed = r.getFinite("speed");
    velocity = r.getFiniteVec3("velocity");
    yawRate = r.getFinite("yawRate");
    motionKnown = r.get<uint8_t>() != 0;
    const int clipCount = int(body->character().clips.size());
    if (r.ok() && !(clip >= -1 && clip < clipCount && playbackRate >= 0.0 && playbackRate <= kMaxPlaybackRate &&
                    position.cwiseAbs().maxCoeff() <= kMaxCoordinate &&
                    previousPosition.cwiseAbs().maxCoeff() <= kMaxCoordinate))
        r.fail("a character's clip, playback rate or root is out of range");
    garments.resize(r.count(8));
    for (GarmentId& g : garments) g.index1 = r.get<uint32_t>(), g.generation = r.get<uint32_t>();
    const std::size_t vertices = body->mesh().vertexCount();
    if (body->hostSkinned) {
        skinnedPositions = r.getFiniteVec3s("a host-skinned vertex");
        if (r.ok() && skinnedPositions.size() != vertices) r.fail("host-skinned vertices do not match the body");
    }
    if (r.get<uint8_t>() != 0) {
        const std::vector<Vec3> current = r.getFiniteVec3s("a collider vertex");
        mMeshColliderTime = r.get<double>();
        mMeshColliderRebuilt = r.get<double>();
        if (r.ok() && (current.size() != vertices || std::isnan(mMeshColliderTime) || std::isnan(mMeshColliderRebuilt)))
            r.fail("a mesh collider does not match its body");
        if (!r.ok()) return Status::ok();
        // Made at its last pose, which is then also its previous one: the next update() moves it
        // from there exactly as the saved collider would have been moved.
        auto made = collision::BodyCollider::create(device, bodyTopology, current);
        if (!made.isOk()) return made.status();
        meshCollider = std::move(made).value();
    }
    meshColliderBuildFailed = r.get<uint8_t>() != 0;
    proxyColliderMade = r.get<uint8_t>() != 0;
    if (proxyColliderMade) {
        std::vector<collision::Capsule> capsules(r.count(7 * sizeof(double)));
        for (collision::Capsule& c : capsules) {
            c.a = r.getFiniteVec3("a capsule");
            c.b = r.getFiniteVec3("a capsule");
            c.radius = r.getFinite("a capsule's radius");
        }
        mProxyColliderTime = r.get<double>();
        if (r.ok() && (capsules.size() != body->mannequin.capsules.size() || std::isnan(mProxyColliderTime)))
            r.fail("the body's capsules do not match it");
        if (!r.ok()) return Status::ok();
        auto made = collision::CapsuleCollider::create(capsules);
        if (!made.isOk()) return made.status();
        proxyCollider = std::move(made).value();
    }
    poseCurrent = skinnedCurrent = hostVerticesGiven = false;  // as after a step
    return Status::ok();
}

void GarmentInstance::saveState(SnapshotWriter& w) const {
    w.put(int32_t(mLevel));
    w.put(int32_t(mSteppedLevel));
    w.put(uint8_t(mSteppedOnMesh));
    w.putVector(mPositions);
    w.putVector(mVelocities);
    w.putVector(mMorph);
    w.put(int32_t(mMorphFramesLeft));
    w.put(mSpecificKineticEnergy);
    w.put(mReleaseLeft);
    putSchedule(w, schedule);
    const GarmentStats& x = stats;
    CC_GARMENT_STATS_FIELDS(CC_SNAPSHOT_PUT)
    w.put(lastUpdateTime), w.put(lastRootVelocity), w.put(lastYawRate);
    w.put(lastError);
}

Status GarmentInstance::restoreState(SnapshotReader& r) {
    const int level = r.get<int32_t>();
    const int levelCount = int(mAsset->levels.size());
    if (r.ok() && !(level >= 0 && level < levelCount)) r.fail("a garment's level is out of range");
    const int steppedLevel = r.get<int32_t>();
    const uint8_t steppedOnMesh = r.get<uint8_t>();
    if (r.ok() && !(steppedLevel >= -1 && steppedLevel < levelCount && steppedOnMesh <= 1))
        r.fail("a garment's last update (level, collision) is out of range");
    auto positions = r.getFiniteVec3s("a garment vertex");
    auto velocities = r.getFiniteVec3s("a garment velocity");
    auto morph = r.getFiniteVec3s("a level switch's fade");
    const int morphFrames = r.get<int32_t>();
    const double energy = r.getFinite("kinetic energy");
    const double releaseLeft = r.getFinite("placement release time");
    const lod::GarmentSchedule restoredSchedule = getSchedule(r, levelCount);
    GarmentStats x;
    CC_GARMENT_STATS_FIELDS(CC_SNAPSHOT_GET)
    const double updateTime = r.getFinite("lastUpdateTime");
    const Vec3 rootVelocity = r.getFiniteVec3("lastRootVelocity");
    const double yawRate = r.getFinite("lastYawRate");
    std::string error = r.getString();
    if (!r.ok()) return Status::ok();
    const std::size_t n = mAsset->levels[level].active.simToVertex.size();
    const bool morphFits = morph.empty() || morph.size() == mAsset->renderVertexCount;
    if (positions.size() != n || velocities.size() != n || !morphFits || morphFrames < 0 ||
        morphFrames > kMorphFrames || (morphFrames > 0 && morph.empty()) || !(energy >= 0.0) ||
        !(releaseLeft >= 0.0 && releaseLeft <= kReleaseSeconds)) {
        r.fail("a garment's state does not match its asset (level " + std::to_string(level) + ", " +
               std::to_string(positions.size()) + " vertices)");
        return Status::ok();
    }
    // assign() into the buffers create() sized for the finest level: nothing reallocates later.
    mLevel = level;
    mSteppedLevel = steppedLevel;
    mSteppedOnMesh = steppedOnMesh == 1;
    mPositions.assign(positions.begin(), positions.end());
    mVelocities.assign(velocities.begin(), velocities.end());
    mMorph.assign(morph.begin(), morph.end());
    mMorphFramesLeft = morphFrames;
    mSpecificKineticEnergy = energy;
    mReleaseLeft = releaseLeft;
    schedule = restoredSchedule;
    stats = x;
    lastUpdateTime = updateTime;
    lastRootVelocity = rootVelocity;
    lastYawRate = yawRate;
    lastError = std::move(error);
    mSelfLevel = -1;  // self-collision's structures are remade for the level on first need
    mLocalDirty = mWorldDirty = true;
    return Status::ok();
}

Result<std::unique_ptr<GarmentInstance>> GarmentInstance::clone(CharacterInstance& character) const {
    GarmentDesc desc;
    desc.importance = mImportance;
    desc.inertiaScale = mInertiaScale;
    desc.forceLevel = mForceLevel;
    auto made = create(mAsset, mAssetIndex, character, mCharacterId, desc);
    if (!made.isOk()) return made.status();
    SnapshotWriter out;
    saveState(out);
    SnapshotReader in(out.bytes().data(), out.bytes().size());
    if (Status s = made.value()->restoreState(in); !s) return s;
    if (!in.ok()) return Status::error(StatusCode::InvalidOperation, "clone: " + in.error());
    return made;
}

Result<std::vector<uint8_t>> WorldImpl::saveState() const {
    SnapshotWriter w;
    w.tag("WDSC");
    const auto fields = resultFields(mDesc);
    w.put(uint64_t(fields.size()));
    for (const auto& [name, value] : fields) w.put(value);

    // The cooked layer by fingerprint; each cooked asset as the design and body it was fitted for.
    w.tag("DSGN");
    w.put(uint64_t(mDesigns.slotCount()));
    mDesigns.forEach([&](auto, const DesignRecord& d) { w.put(designFingerprint(d.desc)); });
    w.tag("BODY");
    w.put(uint64_t(mBodies.slotCount()));
    mBodies.forEach([&](auto, const BodyRecord& b) {
        w.put(bodyFingerprint(*b.body));
        w.put(uint64_t(b.spareColliders.size()));  // they decide whether a garment waits for a build
    });
    // Each cooked asset as the (design, body) slots it was fitted for, in one pass over the designs.
    std::vector<std::array<int64_t, 2>> origin(mAssets.slotCount(), {-1, -1});
    mDesigns.forEach([&](auto d, const DesignRecord& design) {
        // Not a structured binding: a lambda may not capture one before C++20 (clang refuses it).
        for (const auto& fit : design.fitted)
            mBodies.forEach([&](auto b, const BodyRecord& body) {
                if (body.body == fit.first) origin[fit.second.index1 - 1] = {int64_t(d.index1) - 1, int64_t(b.index1) - 1};
            });
    });
    w.tag("ASET");
    w.put(uint64_t(origin.size()));
    for (const auto& [design, body] : origin) {
        if (design < 0 || body < 0)
            return Status::error(StatusCode::InvalidOperation,
                                 "saveState: a garment asset was fitted to a body that setBodyLandmarks has since "
                                 "changed; a restoring World could not cook it again");
        w.put(uint32_t(design)), w.put(uint32_t(body));
    }

    w.tag("WRLD");
    w.put(mTime), w.put(mBudgetScale), w.put(mDesc.frameBudgetMs);
    {
        const FrameStats& x = mFrameStats;
        CC_FRAME_STATS_FIELDS(CC_SNAPSHOT_PUT)
    }
    w.put(uint64_t(mCameras.size()));
    for (const lod::SchedulerCamera& c : mCameras) {
        for (int k = 0; k < 16; ++k) w.put(c.viewProjection(k % 4, k / 4));
        w.put(c.viewportWidth), w.put(c.viewportHeight);
    }
    w.tag("COST");
    const auto learned = mCostModel.learned();
    w.put(uint64_t(learned.size()));
    for (const auto& e : learned)
        w.put(e.asset), w.put(int32_t(e.level)), w.put(uint8_t(e.solver)), w.put(uint8_t(e.collision)),
            w.put(e.meanMs), w.put(e.deviationMs), w.put(uint8_t(e.selfCollision));

    w.tag("CHAR");
    putLayout(w, mCharacters);
    Status stale;
    mCharacters.forEach([&](auto h, const CharacterInstance& c) {
        const BodyRecord* record = mBodies.get(c.bodyId);
        if (!record || record->body != c.body)
            stale = Status::error(StatusCode::InvalidOperation,
                                  "saveState: character " + std::to_string(h.index1) +
                                      " wears a body that setBodyLandmarks has since changed; a restoring World "
                                      "could not make it again");
        w.put(h.index1 - 1);
        w.put(c.bodyId.index1 - 1);
        c.saveState(w);
    });
    if (!stale) return stale;
    w.tag("GARM");
    putLayout(w, mGarments);
    mGarments.forEach([&](auto h, const GarmentInstance& g) {
        w.put(h.index1 - 1);
        w.put(g.assetIndex() - 1);
        w.put(g.character().index1), w.put(g.character().generation);
        w.put(g.importance()), w.put(int32_t(g.forcedLevel())), w.put(g.inertiaScale());
        g.saveState(w);
    });
    w.tag("END!");

    SnapshotWriter header;
    for (char c : kMagic) header.put(c);
    header.put(kFormatVersion), header.put(kByteOrderMark);
    header.put(uint64_t(w.bytes().size()));
    header.put(uint64_t(0));  // the checksum, sealed below
    std::vector<uint8_t> out = std::move(header.bytes());
    out.insert(out.end(), w.bytes().begin(), w.bytes().end());
    sealSnapshot(out);
    return out;
}

Status WorldImpl::restoreState(const void* data, std::size_t size, RestoreMode mode) {
    if (mode != RestoreMode::Continue && mode != RestoreMode::OtherSolver) return refused("unknown RestoreMode");
    if (!data && size > 0) return refused("data is null");
    const auto* bytes = static_cast<const uint8_t*>(data);
    if (size < kHeaderBytes)
        return refused(std::to_string(size) + " bytes: too short for a crowdcloth World snapshot's header (" +
                       std::to_string(kHeaderBytes) + ")");
    SnapshotReader header(bytes, kHeaderBytes);
    char magic[8];
    for (char& c : magic) c = header.get<char>();
    if (std::memcmp(magic, kMagic, sizeof(magic)) != 0) return refused("not a crowdcloth World snapshot (its magic differs)");
    const uint32_t version = header.get<uint32_t>();
    if (version != kFormatVersion)
        return refused("snapshot format version " + std::to_string(version) + "; this build reads version " +
                       std::to_string(kFormatVersion));
    if (header.get<uint32_t>() != kByteOrderMark) return refused("the snapshot was written on a machine of the other byte order");
    const uint64_t payload = header.get<uint64_t>();
    const uint64_t checksum = header.get<uint64_t>();
    if (payload != size - kHeaderBytes)
        return refused("truncated or padded: its header promises " + std::to_string(payload) + " bytes after it, " +
                       std::to_string(size - kHeaderBytes) + " are given");
    if (hashBytes(bytes + kHeaderBytes, payload) != checksum)
        return refused("corrupted: the bytes do not match the header's checksum");

    SnapshotReader r(bytes + kHeaderBytes, payload);
    auto readError = [&] { return refused(r.error()); };

    r.expectTag("WDSC");
    const auto fields = resultFields(mDesc);
    if (r.count(8) != fields.size() && r.ok()) r.fail("another set of WorldDesc fields");
    for (const auto& [name, value] : fields) {
        const double saved = r.get<double>();
        if (mode == RestoreMode::OtherSolver && isSolverField(name)) continue;
        if (r.ok() && saved != value)
            return refused(std::string("this World's WorldDesc.") + name + " is " + std::to_string(value) +
                           ", the snapshot's " + std::to_string(saved) + ": make the World with the same desc");
    }

    r.expectTag("DSGN");
    const uint64_t designs = r.count(8);
    if (r.ok() && designs > mDesigns.slotCount())
        return refused("the snapshot has " + std::to_string(designs) + " cloth assets, this World " +
                       std::to_string(mDesigns.slotCount()) + ": add the same assets in the same order first");
    for (uint32_t d = 0; d < designs && r.ok(); ++d) {
        const DesignRecord* record = mDesigns.get(HandlePool<DesignRecord>::Handle{d + 1, mDesigns.generationAt(d)});
        if (r.get<uint64_t>() != designFingerprint(record->desc) && r.ok())
            return refused("cloth asset " + std::to_string(d + 1) + " differs from the snapshot's (another desc)");
    }
    r.expectTag("BODY");
    const uint64_t bodies = r.count(16);
    if (r.ok() && bodies > mBodies.slotCount())
        return refused("the snapshot has " + std::to_string(bodies) + " bodies, this World " +
                       std::to_string(mBodies.slotCount()) + ": add the same bodies in the same order first");
    std::vector<BodyRecord*> bodyRecords;
    std::vector<uint64_t> spares;
    for (uint32_t b = 0; b < bodies && r.ok(); ++b) {
        BodyRecord* record = mBodies.get(HandlePool<BodyRecord>::Handle{b + 1, mBodies.generationAt(b)});
        const uint64_t saved = r.get<uint64_t>();
        spares.push_back(r.get<uint64_t>());
        if (r.ok() && saved != bodyFingerprint(*record->body))
            return refused("body " + std::to_string(b + 1) + " differs from the snapshot's (mesh, skeleton, clips or "
                           "landmarks)");
        if (r.ok() && spares.back() > kMaxSpareColliders) r.fail("too many spare colliders");
        bodyRecords.push_back(record);
    }

    // Cooked assets in the saved order (a cook is a pure function of design and body), so the
    // asset indices the garments, batches and learned costs use are the saved ones. Cooking is
    // added data: it stays if the restore fails later, as a garment added later would cook it.
    r.expectTag("ASET");
    const uint64_t assets = r.count(8);
    for (uint32_t a = 0; a < assets; ++a) {
        const uint32_t design = r.get<uint32_t>(), body = r.get<uint32_t>();
        if (!r.ok()) break;
        if (design >= designs || body >= bodies) return refused("a cooked asset names a design or body out of range");
        DesignRecord& d = *mDesigns.get(HandlePool<DesignRecord>::Handle{design + 1, mDesigns.generationAt(design)});
        bool here = false;
        for (const auto& [fittedBody, id] : d.fitted) here |= fittedBody == bodyRecords[body]->body && id.index1 == a + 1;
        if (!here && a < mAssets.slotCount())
            return refused("this World cooked its garment assets in another order than the snapshot's: restore into "
                           "a World whose garments were added in the same order, or that has none yet");
        if (!here) {
            auto made = fittedAsset(d, bodyRecords[body]->body);
            if (!made.isOk()) return refused("cooking cloth asset " + std::to_string(design + 1) + " for body " +
                                             std::to_string(body + 1) + ": " + made.status().message());
            if (made.value().index1 != a + 1) return refused("cooked assets out of order");
        }
    }

    r.expectTag("WRLD");
    const double time = r.getFinite("time"), budgetScale = r.getFinite("budget scale");
    const double frameBudget = r.getFinite("frame budget");
    FrameStats frameStats;
    {
        FrameStats& x = frameStats;
        CC_FRAME_STATS_FIELDS(CC_SNAPSHOT_GET)
    }
    std::vector<lod::SchedulerCamera> cameras(r.count(18 * sizeof(double)));
    for (lod::SchedulerCamera& c : cameras) {
        for (int k = 0; k < 16; ++k) c.viewProjection(k % 4, k / 4) = r.getFinite("a camera");
        c.viewportWidth = r.getFinite("a viewport");
        c.viewportHeight = r.getFinite("a viewport");
        if (r.ok() && !(c.viewportWidth > 0.0 && c.viewportHeight > 0.0)) r.fail("a viewport is empty");
    }
    if (r.ok() && !(frameBudget > 0.0 && budgetScale > 0.0)) r.fail("the budget is out of range");
    r.expectTag("COST");
    std::vector<lod::CostModel::LearnedCost> learned(r.count(19));
    for (auto& e : learned) {
        e.asset = r.get<uint32_t>(), e.level = r.get<int32_t>();
        e.solver = lod::SolverChoice(r.get<uint8_t>()), e.collision = lod::CollisionDetail(r.get<uint8_t>());
        e.meanMs = r.get<double>(), e.deviationMs = r.get<double>(), e.selfCollision = r.get<uint8_t>() != 0;
    }
    lod::CostModel costModel = mCostModel;
    if (r.ok())
        if (Status s = costModel.setLearned(learned); !s) r.fail(s.message());
    if (!r.ok()) return readError();

    // Characters and garments into pools of their own: this World's are replaced only when the
    // whole snapshot has been read.
    r.expectTag("CHAR");
    HandlePool<CharacterInstance> characters;
    Status pooled = readPool(r, characters, "a character", [&](uint32_t slot) -> Result<std::unique_ptr<CharacterInstance>> {
        const uint32_t body = r.get<uint32_t>();
        if (!r.ok()) return std::unique_ptr<CharacterInstance>();
        if (body >= bodies) return refused("a character's body is out of range");
        BodyRecord& record = *bodyRecords[body];
        if (Status s = prepareBodyTopology(record); !s) return refused(s.message());
        auto c = std::make_unique<CharacterInstance>();
        c->body = record.body;
        c->bodyId = BodyId{body + 1, mBodies.generationAt(body)};
        c->bodyTopology = record.topology;
        if (!record.body->hostSkinned) c->pose = CharacterPose(record.body->character());
        if (Status s = c->restoreState(r, *mDevice); !s)
            return refused("character " + std::to_string(slot + 1) + ": " + s.message());
        return c;
    });
    if (!pooled) return pooled;
    if (!r.ok()) return readError();

    r.expectTag("GARM");
    HandlePool<GarmentInstance> garments;
    pooled = readPool(r, garments, "a garment", [&](uint32_t slot) -> Result<std::unique_ptr<GarmentInstance>> {
        const uint32_t asset = r.get<uint32_t>();
        CharacterId owner;
        owner.index1 = r.get<uint32_t>(), owner.generation = r.get<uint32_t>();
        GarmentDesc desc;
        desc.importance = r.get<double>();
        desc.forceLevel = r.get<int32_t>();
        desc.inertiaScale = r.get<double>();
        if (!r.ok()) return std::unique_ptr<GarmentInstance>();
        const AssetRecord* record =
            asset < mAssets.slotCount() ? mAssets.get(HandlePool<AssetRecord>::Handle{asset + 1, mAssets.generationAt(asset)})
                                        : nullptr;
        CharacterInstance* c = characters.get(owner);
        if (!record || !c)
            return refused("garment " + std::to_string(slot + 1) + " names an asset or character that is not there");
        auto g = GarmentInstance::create(record->asset, asset + 1, *c, owner, desc);
        if (!g.isOk()) return refused("garment " + std::to_string(slot + 1) + ": " + g.status().message());
        if (Status s = g.value()->restoreState(r); !s) return refused(s.message());
        return g;
    });
    if (!pooled) return pooled;
    r.expectTag("END!");
    if (r.ok() && !r.atEnd()) r.fail("bytes follow the end");
    if (!r.ok()) return readError();
    // Every garment is on its character's list once, and every listed garment is there.
    std::size_t listed = 0;
    bool consistent = true;
    characters.forEach([&](auto h, const CharacterInstance& c) {
        listed += c.garments.size();
        for (GarmentId id : c.garments) {
            const GarmentInstance* g = garments.get(id);
            consistent &= g && g->character().index1 == h.index1 && g->character().generation == h.generation;
        }
    });
    if (!consistent || listed != garments.size()) return refused("the characters' garment lists do not match the garments");

    // Spare colliders as saved: whether a near garment's first mesh update waits for a build
    // depends on them.
    std::vector<std::vector<std::unique_ptr<collision::BodyCollider>>> newSpares(bodies);
    for (uint32_t b = 0; b < bodies; ++b) {
        BodyRecord& record = *bodyRecords[b];
        if (spares[b] > 0)
            if (Status s = prepareBodyTopology(record); !s) return refused(s.message());
        for (uint64_t k = record.spareColliders.size(); k < spares[b]; ++k) {
            auto made = collision::BodyCollider::create(*mDevice, record.topology, record.body->mesh().bindPositions);
            if (!made.isOk()) return refused("a spare collider: " + made.status().message());
            newSpares[b].push_back(std::move(made).value());
        }
    }

    // Nothing can fail from here on.
    for (uint32_t b = 0; b < bodies; ++b) {
        auto& list = bodyRecords[b]->spareColliders;
        if (list.size() > spares[b]) list.resize(spares[b]);
        for (auto& made : newSpares[b]) list.push_back(std::move(made));
    }
    mShadow.clear();  // its windows follow garments the snapshot replaces
    mCharacters = std::move(characters);
    mGarments = std::move(garments);
    mTime = time;
    mBudgetScale = budgetScale;
    mDesc.frameBudgetMs = frameBudget;
    mFrameStats = frameStats;
    mCameras = std::move(cameras);
    mCostModel = std::move(costModel);
    mItems.clear();
    mUpdates.clear();
    mColliderBuilds.clear();
    return Status::ok();
}

} // namespace cc::detail
